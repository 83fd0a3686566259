# `make bench`: the figures behind the performance targets, printed, never
# judged (these machines are noisy). Built only on demand.
#  - bench: the Table 1 workloads (P09 §6), space colonization with a million
#    markers (P09's, and Runions 2007's to 50,000 internodes) and a forest of 100 trees, each grown to its internode count,
#    and Xu & Mould 2015's guiding-vector tree of 4,000 endpoints (gv-fig4-4000's six iterations):
#    internodes, steps (and the paper's), seconds (min and median of
#    BENCH_RUNS runs), internodes per second, peak memory (each run in a
#    process of its own), the scene's hash.
#  - bench_inverse: the inverse model's Populus (G04 §4) grown through its 27
#    years, and shown at the fractional year 12.25: seconds, internodes, hash.
#  - bench_lsystem: Honda's tree (ABOP Fig. 2.6a) derived to about 15 million
#    modules: derivation and turtle seconds, peak memory and bytes per module;
#    then the model's step of the same size onto the skeleton (a process each).
#  - bench_mesh: meshing and GLB encoding of a 10,000- and a 700,000-internode tree,
#    and the brush client's compact snapshot of the first (detail 2, meshopt, no UVs);
#    then both trees with implicit junctions (issue 18), their patches on 1 and 2 threads
#    (the small tree's the best of 10 meshings: a tenth of a second each, where 3 let
#    a busy host's noise through).
#  - bench_patch: one implicit junction's patch (issue 18) at a few grid
#    spacings: best and median milliseconds per patch, vertices, triangles.
# `make table1`: see below.
# `make bench-http`: meristemd under wrk on loopback (needs Debian's wrk).
# `make bench-restore`: time to listen and to the first answer from the oldest
# session of a data folder of 1,000 sessions of 200 edits (built once, by a
# real meristemd, in bench-restore-data/; needs node).
# `make bench-page`: the brush client loading and drawing 10,000-internode
# snapshots in headless Chromium (needs node, the npm test tools, chromium).
EXTRA_PROGRAMS = tests/bench/bench tests/bench/bench_mesh tests/bench/table1 \
	tests/bench/bench_inverse tests/bench/bench_lsystem tests/bench/bench_patch
tests_bench_bench_lsystem_SOURCES = tests/bench/bench_lsystem.c
tests_bench_bench_lsystem_LDADD = lib/libmeristem-core.la
tests_bench_bench_SOURCES = tests/bench/bench.c
tests_bench_bench_LDADD = lib/libmeristem-core.la
tests_bench_bench_mesh_SOURCES = tests/bench/bench_mesh.c
tests_bench_bench_inverse_SOURCES = tests/bench/bench_inverse.c
tests_bench_bench_inverse_LDADD = lib/libmeristem-core.la
tests_bench_table1_SOURCES = tests/bench/table1.c
tests_bench_bench_patch_SOURCES = tests/bench/bench_patch.c tests/unit/fork_fixture.h
tests_bench_bench_patch_LDADD = lib/libmeristem-core.la
tests_bench_table1_LDADD = lib/libmeristem-core.la
tests_bench_bench_mesh_LDADD = lib/libmeristem-core.la
# It encodes GLB through tinygltf: link with the C++ driver.
nodist_EXTRA_tests_bench_bench_mesh_SOURCES = tests/bench/link-as-cxx.cc
CLEANFILES += tests/bench/bench$(EXEEXT) tests/bench/bench_mesh$(EXEEXT) tests/bench/table1$(EXEEXT) \
	tests/bench/bench_inverse$(EXEEXT) tests/bench/bench_lsystem$(EXEEXT) tests/bench/bench_patch$(EXEEXT)
EXTRA_DIST += tests/bench/http-bench.sh tests/bench/page-load.js tests/bench/refused-edit.js \
	tests/bench/restore.js

BENCH_WORKLOADS = table1-left table1-center table1-right \
  colonization-1M-markers forest-100-trees runions-1M-markers guiding-4000-endpoints
BENCH_RUNS = 3

bench: tests/bench/bench$(EXEEXT) tests/bench/bench_mesh$(EXEEXT) tests/bench/bench_inverse$(EXEEXT) \
  tests/bench/bench_lsystem$(EXEEXT) tests/bench/bench_patch$(EXEEXT)
	@./tests/bench/bench$(EXEEXT) --header
	@for w in $(BENCH_WORKLOADS); do ./tests/bench/bench$(EXEEXT) $$w $(BENCH_RUNS) || exit 1; done
	@./tests/bench/bench_inverse$(EXEEXT) $(BENCH_RUNS)
	@./tests/bench/bench_mesh$(EXEEXT) 10000
	@./tests/bench/bench_mesh$(EXEEXT) 10000 2 compact
	@./tests/bench/bench_mesh$(EXEEXT) 700000
	@./tests/bench/bench_mesh$(EXEEXT) 10000 3 implicit 1 10
	@./tests/bench/bench_mesh$(EXEEXT) 10000 3 implicit 2 10
	@./tests/bench/bench_mesh$(EXEEXT) 700000 3 implicit 1
	@./tests/bench/bench_mesh$(EXEEXT) 700000 3 implicit 2
	@./tests/bench/bench_lsystem$(EXEEXT) --header
	@./tests/bench/bench_lsystem$(EXEEXT) string $(BENCH_RUNS)
	@./tests/bench/bench_lsystem$(EXEEXT) step $(BENCH_RUNS)
	@./tests/bench/bench_patch$(EXEEXT)

bench-http: server/meristemd$(EXEEXT)
	@$(SHELL) $(srcdir)/tests/bench/http-bench.sh server/meristemd$(EXEEXT)

bench-page: server/meristemd$(EXEEXT) webroot/.stamp
	@MERISTEMD='$(abs_top_builddir)/server/meristemd' MER_WEB_ROOT='$(abs_top_builddir)/webroot' \
	  NODE_PATH='$(NODE_MODULES_DIR)' CHROMIUM='$(CHROMIUM)' '$(NODE)' $(srcdir)/tests/bench/page-load.js
# `make table1`: P09 Table 1's trees at full size, judged on step counts (within
# 25 % of the paper's) and on staying inside the 200³ grid, never on time.
# TABLE1_SEEDS seeds each (default 2).
TABLE1_SEEDS = 2
table1: tests/bench/table1$(EXEEXT)
	@./tests/bench/table1$(EXEEXT) $(TABLE1_SEEDS)

bench-restore: server/meristemd$(EXEEXT)
	@MERISTEMD='$(abs_top_builddir)/server/meristemd' MER_WEB_ROOT='$(abs_top_srcdir)/web' \
	  BENCH_RESTORE_DIR='$(abs_top_builddir)/bench-restore-data' '$(NODE)' $(srcdir)/tests/bench/restore.js
.PHONY: bench bench-http bench-page bench-restore table1
