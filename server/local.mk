# meristemd: the HTTP daemon.
bin_PROGRAMS += server/meristemd
server_meristemd_SOURCES = \
	server/main.c \
	server/settings.c server/settings.h \
	server/http.c server/http.h \
	server/guard.c server/guard.h server/guard_private.h \
	server/front.c server/front.h server/head.c server/head.h \
	server/relay.c server/relay.h server/framing.c server/framing.h \
	server/host.c server/host.h \
	server/request.c server/request.h \
	server/routes.c server/routes.h \
	server/static_files.c server/static_files.h \
	server/codec.c server/codec.h \
	server/refusal.c server/refusal.h \
	server/decode.c server/decode.h \
	server/spec.c server/spec_sow.c server/spec.h \
	server/edit_ops.c server/edit_ops.h \
	server/functions_json.c server/functions_json.h \
	server/edits.c server/edits.h \
	server/journal.c server/journal.h server/io_hooks.h server/io_faults.c \
	server/checkpoint.c server/checkpoint.h \
	server/session.c server/session.h server/session_private.h \
	server/session_load.c server/session_summary.c server/session_snapshot.c \
	server/session_history.c server/revisions.c server/revisions.h \
	server/snapshot.c server/snapshot.h \
	server/export.c server/export.h server/cores.c server/cores.h \
	server/cpu_quota.c server/cpu_quota.h \
	server/clock.h \
	server/registry.c server/registry.h \
	server/quarantine.c server/quarantine.h \
	server/loader.c server/loader.h \
	server/jobs.c server/jobs.h \
	server/metrics.c server/metrics.h \
	server/api.h server/api/private.h \
	server/api/async.c server/api/meta.c server/api/sessions.c \
	server/api/edits.c server/api/snapshot.c server/api/history.c \
	server/app.h
server_meristemd_CPPFLAGS = $(AM_CPPFLAGS) -DMER_WEB_ROOT='"$(webdir)"' -DMER_BUILD_DIR='"$(abs_top_builddir)"' $(MHD_CFLAGS) $(JANSSON_CFLAGS) $(ZLIB_CFLAGS)
server_meristemd_LDADD = lib/libmeristem.la $(MHD_LIBS) $(JANSSON_LIBS) $(ZLIB_LIBS)

# meristem: the offline command line (grow from a preset, write a GLB).
bin_PROGRAMS += server/meristem
server_meristem_SOURCES = server/cli.c server/codec.c server/codec.h server/export.c server/export.h \
	server/cpu_quota.c server/cpu_quota.h
server_meristem_CPPFLAGS = $(AM_CPPFLAGS) $(JANSSON_CFLAGS)
server_meristem_LDADD = lib/libmeristem.la $(JANSSON_LIBS)
