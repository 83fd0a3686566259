# meristemd: the HTTP daemon.
bin_PROGRAMS += server/meristemd
server_meristemd_SOURCES = \
	server/main.c \
	server/settings.c server/settings.h \
	server/http.c server/http.h \
	server/request.c server/request.h \
	server/routes.c server/routes.h \
	server/static_files.c server/static_files.h
server_meristemd_CPPFLAGS = $(AM_CPPFLAGS) -DMER_WEB_ROOT='"$(webdir)"' $(MHD_CFLAGS) $(JANSSON_CFLAGS)
server_meristemd_LDADD = lib/libmeristem.la $(MHD_LIBS) $(JANSSON_LIBS)
