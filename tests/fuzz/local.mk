# libFuzzer harnesses (configure --enable-fuzz, with clang). `make fuzz-smoke`
# runs each over its seed corpus for a fixed number of inputs; see README.md
# (Fuzzing) for a longer run before a release.
FUZZ_HARNESSES = tests/fuzz/fuzz_edits tests/fuzz/fuzz_journal tests/fuzz/fuzz_gltf \
	tests/fuzz/fuzz_spec tests/fuzz/fuzz_checkpoint tests/fuzz/fuzz_head \
	tests/fuzz/fuzz_framing
# The daemon's decoding, applying and journaling code, compiled into the harnesses.
FUZZ_SERVER = server/refusal.c server/refusal.h server/decode.c server/decode.h \
	server/codec.c server/codec.h server/edit_ops.c server/edit_ops.h \
	server/edits.c server/edits.h server/spec.c server/spec.h \
	server/journal.c server/journal.h server/io_hooks.h \
	server/functions_json.c server/functions_json.h server/spec_sow.c
FUZZ_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir) $(JANSSON_CFLAGS) $(ZLIB_CFLAGS)
FUZZ_LDADD = lib/libmeristem-core.la $(JANSSON_LIBS) $(ZLIB_LIBS)

if FUZZ
noinst_PROGRAMS += $(FUZZ_HARNESSES)
endif
EXTRA_PROGRAMS += $(FUZZ_HARNESSES)

tests_fuzz_fuzz_edits_SOURCES = tests/fuzz/fuzz_edits.c tests/fuzz/fuzz_common.h $(FUZZ_SERVER)
tests_fuzz_fuzz_journal_SOURCES = tests/fuzz/fuzz_journal.c tests/fuzz/fuzz_common.h $(FUZZ_SERVER)
tests_fuzz_fuzz_gltf_SOURCES = tests/fuzz/fuzz_gltf.c tests/fuzz/fuzz_common.h
tests_fuzz_fuzz_spec_SOURCES = tests/fuzz/fuzz_spec.c tests/fuzz/fuzz_common.h $(FUZZ_SERVER)
tests_fuzz_fuzz_checkpoint_SOURCES = tests/fuzz/fuzz_checkpoint.c tests/fuzz/fuzz_common.h
# The front's head check stands alone: no library, no jansson.
tests_fuzz_fuzz_head_SOURCES = tests/fuzz/fuzz_head.c server/head.c server/head.h
tests_fuzz_fuzz_head_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)
tests_fuzz_fuzz_head_LDFLAGS = $(FUZZ_LDFLAGS)
tests_fuzz_fuzz_framing_SOURCES = tests/fuzz/fuzz_framing.c server/framing.c server/framing.h \
	server/head.c server/head.h
tests_fuzz_fuzz_framing_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)
tests_fuzz_fuzz_framing_LDFLAGS = $(FUZZ_LDFLAGS)
# libmeristem has C++ parts: link with the C++ driver.
nodist_EXTRA_tests_fuzz_fuzz_edits_SOURCES = tests/fuzz/link-as-cxx.cc
nodist_EXTRA_tests_fuzz_fuzz_journal_SOURCES = tests/fuzz/link-as-cxx.cc
nodist_EXTRA_tests_fuzz_fuzz_gltf_SOURCES = tests/fuzz/link-as-cxx.cc
nodist_EXTRA_tests_fuzz_fuzz_spec_SOURCES = tests/fuzz/link-as-cxx.cc
nodist_EXTRA_tests_fuzz_fuzz_checkpoint_SOURCES = tests/fuzz/link-as-cxx.cc
tests_fuzz_fuzz_edits_CPPFLAGS = $(FUZZ_CPPFLAGS)
tests_fuzz_fuzz_journal_CPPFLAGS = $(FUZZ_CPPFLAGS)
tests_fuzz_fuzz_gltf_CPPFLAGS = $(FUZZ_CPPFLAGS)
tests_fuzz_fuzz_spec_CPPFLAGS = $(FUZZ_CPPFLAGS)
tests_fuzz_fuzz_checkpoint_CPPFLAGS = $(FUZZ_CPPFLAGS)
tests_fuzz_fuzz_edits_LDADD = $(FUZZ_LDADD)
tests_fuzz_fuzz_journal_LDADD = $(FUZZ_LDADD)
tests_fuzz_fuzz_gltf_LDADD = $(FUZZ_LDADD)
tests_fuzz_fuzz_spec_LDADD = $(FUZZ_LDADD)
tests_fuzz_fuzz_checkpoint_LDADD = $(FUZZ_LDADD)
tests_fuzz_fuzz_edits_LDFLAGS = $(FUZZ_LDFLAGS)
tests_fuzz_fuzz_journal_LDFLAGS = $(FUZZ_LDFLAGS)
tests_fuzz_fuzz_gltf_LDFLAGS = $(FUZZ_LDFLAGS)
tests_fuzz_fuzz_spec_LDFLAGS = $(FUZZ_LDFLAGS)
tests_fuzz_fuzz_checkpoint_LDFLAGS = $(FUZZ_LDFLAGS)

# Inputs per harness in fuzz-smoke: seconds in all, not minutes. Or, for a
# release, FUZZ_SECONDS: each harness that long (make fuzz-smoke FUZZ_SECONDS=3600).
FUZZ_SMOKE_RUNS = 500
FUZZ_SECONDS =

fuzz-smoke: $(FUZZ_HARNESSES)
	@FUZZ_SMOKE_RUNS=$(FUZZ_SMOKE_RUNS) FUZZ_SECONDS=$(FUZZ_SECONDS) $(SHELL) $(srcdir)/tests/fuzz/run.sh \
	  $(srcdir) $(FUZZ_HARNESSES)
.PHONY: fuzz-smoke

EXTRA_DIST += tests/fuzz/run.sh tests/fuzz/corpus
CLEANFILES += $(FUZZ_HARNESSES)
