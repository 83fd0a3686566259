# The golden test: recorded hashes and GLB digests that a refactoring must keep.
# `make golden-update` re-records them (commit that on its own, saying why).
# It runs in `make check` from SUITE_TESTS (tests/local.mk), first of all.
EXTRA_DIST += tests/golden/golden.test.js tests/golden/golden.json

golden-update: all
	@$(AM_TESTS_ENVIRONMENT) export MER_GOLDEN_UPDATE=1; \
	$(SHELL) $(top_srcdir)/tests/support/run-node.sh $(top_srcdir)/tests/golden/golden.test.js
.PHONY: golden-update
