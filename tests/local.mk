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
	mkdir -p "$$MER_ARTIFACTS";

TESTS += tests/check-exports.sh
TESTS += tests/api/health.test.js
TESTS += tests/api/static.test.js
TESTS += tests/api/cli.test.js
TESTS += tests/api/sessions.test.js
TESTS += tests/api/junctions.test.js
TESTS += tests/api/durability.test.js
TESTS += tests/api/undo.test.js
TESTS += tests/api/checkpoint.test.js
TESTS += tests/api/restore.test.js
TESTS += tests/api/sow.test.js
TESTS += tests/api/compact.test.js
TESTS += tests/api/crashloop.test.js
TESTS += tests/api/security.test.js
TESTS += tests/api/limits.test.js
TESTS += tests/api/mhd-refusals.test.js
TESTS += tests/api/obstacles.test.js
TESTS += tests/api/shutdown.test.js
TESTS += tests/api/slow-clients.test.js
TESTS += tests/api/proto.test.js
TESTS += tests/api/stall-spread.test.js
TESTS += tests/api/history.test.js
TESTS += tests/api/skeleton.test.js
TESTS += tests/api/lsystem.test.js
TESTS += tests/api/inverse.test.js
TESTS += tests/api/hygiene.test.js
TESTS += tests/api/models.test.js
TESTS += tests/api/smoke.sh
TESTS += tests/browser/page.test.js
TESTS += tests/browser/brush.test.js
TESTS += tests/browser/controls.test.js
TESTS += tests/browser/modeller.test.js
TESTS += tests/conformance/importers.test.js
TESTS += tests/browser/history.test.js
TESTS += tests/browser/models.test.js
TESTS += tests/browser/forest.test.js
TESTS += tests/browser/junctions.test.js
TESTS += tests/conformance/validate.test.js

# The conformance test validates every GLB the other tests leave behind, so it runs last.
tests/conformance/validate.test.log: tests/unit/test_gltf.log tests/unit/test_mesh.log \
	tests/api/cli.test.log tests/api/sessions.test.log tests/api/smoke.log \
	tests/api/models.test.log \
	tests/api/lsystem.test.log tests/api/inverse.test.log tests/conformance/importers.test.log

EXTRA_DIST += \
	tests/check-exports.sh \
	tests/support/run-node.sh \
	tests/support/daemon.js \
	tests/support/chromium.js \
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
