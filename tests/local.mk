# The test suite: `make check` runs all of it. Every test speaks TAP: cmocka
# (CMOCKA_MESSAGE_OUTPUT=TAP), node's test runner (--test-reporter=tap) and the
# shell checks, all read by automake's TAP driver.
include tests/unit/local.mk

TEST_EXTENSIONS = .js .sh
TAP_DRIVER = env AM_TAP_AWK='$(AWK)' $(SHELL) $(top_srcdir)/build-aux/tap-driver.sh
LOG_DRIVER = $(TAP_DRIVER)
JS_LOG_DRIVER = $(TAP_DRIVER)
SH_LOG_DRIVER = $(TAP_DRIVER)
JS_LOG_COMPILER = $(SHELL) $(top_srcdir)/tests/support/run-node.sh
SH_LOG_COMPILER = $(SHELL)

AM_TESTS_ENVIRONMENT = \
	export CMOCKA_MESSAGE_OUTPUT=TAP; \
	export MER_ARTIFACTS='$(abs_top_builddir)/tests/artifacts'; \
	export MERISTEMD='$(abs_top_builddir)/server/meristemd'; \
	export MER_WEB_ROOT='$(abs_top_builddir)/webroot'; \
	export MER_SRCDIR='$(abs_top_srcdir)'; \
	export MER_BUILDDIR='$(abs_top_builddir)'; \
	export NODE='$(NODE)'; \
	export NODE_PATH='$(NODE_MODULES_DIR)'; \
	export CHROMIUM='$(CHROMIUM)'; \
	export PACKAGE_VERSION='$(PACKAGE_VERSION)'; \
	export MER_SUITE_FILES='$(SUITE_TESTS) $(SUITE_SUPPORT)'; \
	mkdir -p "$$MER_ARTIFACTS";

# The whole suite, longest first: automake starts the tests in the order
# listed, so under make -j the long ones (a minute or more each) run beside
# the many short ones instead of alone at the end. TESTS lists the unit tests
# (tests/unit/local.mk, the two long ones first) before these.
SUITE_TESTS = \
	tests/golden/golden.test.js \
	tests/api/crashloop.test.js \
	tests/browser/brush.test.js \
	tests/api/slow-clients.test.js \
	tests/browser/controls.test.js \
	tests/api/restore.test.js \
	tests/browser/modeller.test.js \
	tests/api/durability.test.js \
	tests/conformance/importers.test.js \
	tests/api/compact.test.js \
	tests/browser/page.test.js \
	tests/api/sow.test.js \
	tests/api/inverse.test.js \
	tests/api/proto.test.js \
	tests/api/lsystem.test.js \
	tests/api/hygiene.test.js \
	tests/api/cli.test.js \
	tests/api/models.test.js \
	tests/browser/history.test.js \
	tests/browser/models.test.js \
	tests/browser/forest.test.js \
	tests/browser/junctions.test.js \
	tests/api/junctions.test.js \
	tests/api/security.test.js \
	tests/api/smoke.sh \
	tests/api/checkpoint.test.js \
	tests/api/limits.test.js \
	tests/api/history.test.js \
	tests/api/sessions.test.js \
	tests/api/mhd-refusals.test.js \
	tests/api/health.test.js \
	tests/api/undo.test.js \
	tests/api/stall-spread.test.js \
	tests/api/shutdown.test.js \
	tests/api/skeleton.test.js \
	tests/api/obstacles.test.js \
	tests/api/static.test.js \
	tests/check-exports.sh \
	tests/conformance/validate.test.js
# Files the suite reads besides its scripts (check-dist.sh looks for them too).
SUITE_SUPPORT = tests/support/run-node.sh tests/support/daemon.js tests/support/chromium.js \
	tests/support/gltf.js tests/support/render-glb.js tests/golden/golden.json

if DIST_SUITE
# distcheck's build of the tarball (AM_DISTCHECK_CONFIGURE_FLAGS gives it
# --enable-dist-suite). What it adds to the plain and sanitizer builds, which
# run the whole suite on the same sources, is the tarball: that it holds every
# file, builds out of a read-only source tree (with every test program, so
# every test source is in it), installs and uninstalls. A third run of the
# whole suite proves nothing more about the code, so it runs what checks the
# tarball itself: every test script and data file of the suite is in it
# (check-dist.sh), the library's exports, the daemon with its web root and
# contract files, the offline command, and the page in Chromium.
TESTS += tests/check-dist.sh \
	tests/check-exports.sh \
	tests/api/health.test.js \
	tests/api/static.test.js \
	tests/api/proto.test.js \
	tests/api/cli.test.js \
	tests/api/smoke.sh \
	tests/browser/page.test.js
else
TESTS += $(SUITE_TESTS)
endif

# Every test waits for config.h. Its rule (empty, but a recipe) runs in each
# make, and every unit test program depends on it; without this make starts
# all the node and shell tests first and the unit tests last, whatever their
# place in TESTS, so test_clone (about a minute under ASan, the longest test)
# ran alone at the end of the sanitizer check. With it the tests start in the
# order of TESTS.
$(TEST_LOGS): config.h

# The conformance test validates every GLB the other tests leave behind, so it runs last.
tests/conformance/validate.test.log: tests/unit/test_gltf.log tests/unit/test_mesh.log \
	tests/api/cli.test.log tests/api/sessions.test.log tests/api/smoke.log \
	tests/api/models.test.log \
	tests/api/lsystem.test.log tests/api/inverse.test.log tests/conformance/importers.test.log

EXTRA_DIST += \
	tests/check-exports.sh \
	tests/check-dist.sh \
	tests/support/run-node.sh \
	tests/support/daemon.js \
	tests/support/chromium.js \
	tests/support/gltf.js \
	tests/api/health.test.js \
	tests/api/static.test.js \
	tests/api/cli.test.js \
	tests/api/sessions.test.js \
	tests/api/junctions.test.js \
	tests/api/durability.test.js \
	tests/api/undo.test.js \
	tests/api/checkpoint.test.js \
	tests/api/restore.test.js \
	tests/api/lsystem.test.js \
	tests/api/inverse.test.js \
	tests/api/compact.test.js \
	tests/api/crashloop.test.js \
	tests/api/security.test.js \
	tests/api/limits.test.js tests/api/mhd-refusals.test.js tests/api/obstacles.test.js \
	tests/api/shutdown.test.js \
	tests/api/slow-clients.test.js \
	tests/api/proto.test.js \
	tests/api/stall-spread.test.js \
	tests/api/history.test.js \
	tests/api/skeleton.test.js \
	tests/api/hygiene.test.js \
	tests/api/models.test.js \
	tests/api/sow.test.js \
	tests/api/smoke.sh \
	tests/support/render-glb.js \
	tests/browser/page.test.js \
	tests/browser/forest.test.js \
	tests/browser/junctions.test.js \
	tests/browser/brush.test.js \
	tests/browser/controls.test.js \
	tests/browser/modeller.test.js \
	tests/conformance/importers.test.js \
	tests/browser/history.test.js \
	tests/browser/models.test.js \
	tests/conformance/validate.test.js

# A thousand kill -9 cycles (make check runs a few dozen); CRASH_SEED=N replays one.
crash-loop: all
	@$(AM_TESTS_ENVIRONMENT) CRASH_CYCLES=$${CRASH_CYCLES:-1000} \
	  $(SHELL) $(top_srcdir)/tests/support/run-node.sh $(top_srcdir)/tests/api/crashloop.test.js
.PHONY: crash-loop

clean-local: clean-artifacts
clean-artifacts:
	-rm -rf tests/artifacts bench-restore-data
.PHONY: clean-artifacts
EXTRA_DIST += build-aux/tap-driver.sh
include tests/bench/local.mk
include tests/gallery/local.mk
include tests/golden/local.mk
include tests/fuzz/local.mk
