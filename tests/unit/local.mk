# Unit tests in C (C++ where tinygltf reads our output back), with cmocka.
UNIT_LDADD = lib/libmeristem-core.la $(CMOCKA_LIBS)
UNIT_CPPFLAGS = $(AM_CPPFLAGS) $(CMOCKA_CFLAGS)

# The longest unit tests first (P09 Fig. 10 at full size over 8 seeds; every
# preset cloned and grown on): make -j starts the unit tests in this order.
check_PROGRAMS += tests/unit/test_forms_full
tests_unit_test_forms_full_SOURCES = tests/unit/test_forms_full.c tests/unit/forms.h \
	tests/unit/scene_helpers.h
tests_unit_test_forms_full_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_forms_full_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_clone
tests_unit_test_clone_SOURCES = tests/unit/test_clone.c tests/unit/scene_helpers.h
# GLB bytes are freed by the glTF writer's (C++) free: link with the C++ driver.
nodist_EXTRA_tests_unit_test_clone_SOURCES = lib/link-as-cxx.cc
tests_unit_test_clone_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_clone_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_result
tests_unit_test_result_SOURCES = tests/unit/test_result.c
tests_unit_test_result_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_result_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_gltf
tests_unit_test_gltf_SOURCES = tests/unit/test_gltf.cc tests/unit/plain_glb.h
tests_unit_test_gltf_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_gltf_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_rng
tests_unit_test_rng_SOURCES = tests/unit/test_rng.c
tests_unit_test_rng_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_rng_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_params
tests_unit_test_params_SOURCES = tests/unit/test_params.c
tests_unit_test_params_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_params_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_fate
tests_unit_test_fate_SOURCES = tests/unit/test_fate.c
tests_unit_test_fate_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_fate_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_markers
tests_unit_test_markers_SOURCES = tests/unit/test_markers.c
tests_unit_test_markers_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_markers_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_shadow
tests_unit_test_shadow_SOURCES = tests/unit/test_shadow.c
tests_unit_test_shadow_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_shadow_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_scene
tests_unit_test_scene_SOURCES = tests/unit/test_scene.c tests/unit/scene_helpers.h
tests_unit_test_scene_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_scene_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_skeleton
tests_unit_test_skeleton_SOURCES = tests/unit/test_skeleton.c
tests_unit_test_skeleton_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_skeleton_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_p09
tests_unit_test_p09_SOURCES = tests/unit/test_p09.c tests/unit/scene_helpers.h
tests_unit_test_p09_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_p09_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_edit
tests_unit_test_edit_SOURCES = tests/unit/test_edit.c tests/unit/scene_helpers.h
tests_unit_test_edit_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_edit_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_obstacles
tests_unit_test_obstacles_SOURCES = tests/unit/test_obstacles.c tests/unit/scene_helpers.h
tests_unit_test_obstacles_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_obstacles_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_model
tests_unit_test_model_SOURCES = tests/unit/test_model.c
# It writes GLB: link with the C++ driver, as libmeristem does (tinygltf needs libstdc++).
nodist_EXTRA_tests_unit_test_model_SOURCES = tests/unit/link-as-cxx.cc
tests_unit_test_model_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_model_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_presets
tests_unit_test_presets_SOURCES = tests/unit/test_presets.c
tests_unit_test_presets_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_presets_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_mesh
tests_unit_test_mesh_SOURCES = tests/unit/test_mesh.cc
tests_unit_test_mesh_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_mesh_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_obstacle_work
tests_unit_test_obstacle_work_SOURCES = tests/unit/test_obstacle_work.c tests/unit/scene_helpers.h
tests_unit_test_obstacle_work_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_obstacle_work_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_journal
tests_unit_test_journal_SOURCES = tests/unit/test_journal.c server/journal.c server/journal.h \
	server/io_hooks.h
tests_unit_test_journal_CPPFLAGS = $(UNIT_CPPFLAGS) $(ZLIB_CFLAGS)
tests_unit_test_journal_LDADD = $(CMOCKA_LIBS) $(ZLIB_LIBS)

# Short writes, ENOSPC and EIO on the journal's and the checkpoints' path.
check_PROGRAMS += tests/unit/test_journal_faults
tests_unit_test_journal_faults_SOURCES = tests/unit/test_journal_faults.c server/journal.c \
	server/journal.h server/checkpoint.c server/checkpoint.h server/io_hooks.h
tests_unit_test_journal_faults_CPPFLAGS = $(UNIT_CPPFLAGS) $(ZLIB_CFLAGS)
tests_unit_test_journal_faults_LDADD = $(UNIT_LDADD) $(ZLIB_LIBS)

check_PROGRAMS += tests/unit/test_host
tests_unit_test_host_SOURCES = tests/unit/test_host.c server/host.c server/host.h
tests_unit_test_host_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_host_LDADD = $(CMOCKA_LIBS)

check_PROGRAMS += tests/unit/test_cores
tests_unit_test_cores_SOURCES = tests/unit/test_cores.c server/cores.c server/cores.h
tests_unit_test_cores_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_cores_LDADD = $(CMOCKA_LIBS) -lpthread

check_PROGRAMS += tests/unit/test_cpu_quota
tests_unit_test_cpu_quota_SOURCES = tests/unit/test_cpu_quota.c server/cpu_quota.c server/cpu_quota.h
tests_unit_test_cpu_quota_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_cpu_quota_LDADD = $(CMOCKA_LIBS)

check_PROGRAMS += tests/unit/test_head
tests_unit_test_head_SOURCES = tests/unit/test_head.c server/head.c server/head.h
tests_unit_test_head_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_head_LDADD = $(CMOCKA_LIBS)

check_PROGRAMS += tests/unit/test_framing
tests_unit_test_framing_SOURCES = tests/unit/test_framing.c server/framing.c server/framing.h \
	server/head.c server/head.h
tests_unit_test_framing_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_framing_LDADD = $(CMOCKA_LIBS)

# libmicrohttpd's one call the guard makes is the test's own.
check_PROGRAMS += tests/unit/test_guard
tests_unit_test_guard_SOURCES = tests/unit/test_guard.c server/guard.c server/guard.h \
	server/guard_private.h server/clock.h
tests_unit_test_guard_CPPFLAGS = $(UNIT_CPPFLAGS) $(MHD_CFLAGS)
tests_unit_test_guard_LDADD = $(CMOCKA_LIBS) -lpthread

check_PROGRAMS += tests/unit/test_refusal
tests_unit_test_refusal_SOURCES = tests/unit/test_refusal.c server/refusal.c server/refusal.h \
	server/decode.c server/decode.h
tests_unit_test_refusal_CPPFLAGS = $(UNIT_CPPFLAGS) $(JANSSON_CFLAGS)
tests_unit_test_refusal_LDADD = $(UNIT_LDADD) $(JANSSON_LIBS)

check_PROGRAMS += tests/unit/test_snapshot_cache
tests_unit_test_snapshot_cache_SOURCES = tests/unit/test_snapshot_cache.c server/snapshot.c \
	server/snapshot.h
# Snapshot bytes are freed by the glTF writer's (C++) free: link with the C++ driver.
nodist_EXTRA_tests_unit_test_snapshot_cache_SOURCES = lib/link-as-cxx.cc
tests_unit_test_snapshot_cache_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_snapshot_cache_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_chaos
tests_unit_test_chaos_SOURCES = tests/unit/test_chaos.c tests/unit/scene_helpers.h
# It writes GLB: link with the C++ driver, as libmeristem does (tinygltf needs libstdc++).
nodist_EXTRA_tests_unit_test_chaos_SOURCES = tests/unit/link-as-cxx.cc
tests_unit_test_chaos_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_chaos_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_table1
tests_unit_test_table1_SOURCES = tests/unit/test_table1.c tests/unit/scene_helpers.h
tests_unit_test_table1_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_table1_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_forms
tests_unit_test_forms_SOURCES = tests/unit/test_forms.c tests/unit/forms.h tests/unit/scene_helpers.h
tests_unit_test_forms_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_forms_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_forms_figs
tests_unit_test_forms_figs_SOURCES = tests/unit/test_forms_figs.c tests/unit/forms.h \
	tests/unit/scene_helpers.h
tests_unit_test_forms_figs_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_forms_figs_LDADD = $(UNIT_LDADD)

if !DIST_SUITE
TESTS += $(check_PROGRAMS)
endif

check_PROGRAMS += tests/unit/test_lsystem_expr
tests_unit_test_lsystem_expr_SOURCES = tests/unit/test_lsystem_expr.c
tests_unit_test_lsystem_expr_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_lsystem_expr_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_lsystem
tests_unit_test_lsystem_SOURCES = tests/unit/test_lsystem.c
tests_unit_test_lsystem_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_lsystem_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_lsystem_tier2
tests_unit_test_lsystem_tier2_SOURCES = tests/unit/test_lsystem_tier2.c tests/unit/scene_helpers.h
tests_unit_test_lsystem_tier2_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_lsystem_tier2_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_lsystem_turtle
tests_unit_test_lsystem_turtle_SOURCES = tests/unit/test_lsystem_turtle.c
tests_unit_test_lsystem_turtle_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_lsystem_turtle_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_runions
tests_unit_test_runions_SOURCES = tests/unit/test_runions.c tests/unit/scene_helpers.h
tests_unit_test_runions_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_runions_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_noise
tests_unit_test_noise_SOURCES = tests/unit/test_noise.c tests/unit/scene_helpers.h
tests_unit_test_noise_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_noise_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_sow
tests_unit_test_sow_SOURCES = tests/unit/test_sow.c
tests_unit_test_sow_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_sow_LDADD = $(UNIT_LDADD)
check_PROGRAMS += tests/unit/test_lsystem_model
tests_unit_test_lsystem_model_SOURCES = tests/unit/test_lsystem_model.c tests/unit/scene_helpers.h
nodist_EXTRA_tests_unit_test_lsystem_model_SOURCES = lib/link-as-cxx.cc
tests_unit_test_lsystem_model_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_lsystem_model_LDADD = $(UNIT_LDADD)
check_PROGRAMS += tests/unit/test_gfunc
tests_unit_test_gfunc_SOURCES = tests/unit/test_gfunc.c
tests_unit_test_gfunc_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_gfunc_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_inverse_eqs
tests_unit_test_inverse_eqs_SOURCES = tests/unit/test_inverse_eqs.c
tests_unit_test_inverse_eqs_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_inverse_eqs_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_inverse
tests_unit_test_inverse_SOURCES = tests/unit/test_inverse.c tests/unit/inverse_helpers.h \
	tests/unit/scene_helpers.h
# It writes GLB: link with the C++ driver (tinygltf needs libstdc++).
nodist_EXTRA_tests_unit_test_inverse_SOURCES = tests/unit/link-as-cxx.cc
tests_unit_test_inverse_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_inverse_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_inverse_edits
tests_unit_test_inverse_edits_SOURCES = tests/unit/test_inverse_edits.c tests/unit/inverse_helpers.h \
	tests/unit/scene_helpers.h
# It meshes: link with the C++ driver (tinygltf needs libstdc++).
nodist_EXTRA_tests_unit_test_inverse_edits_SOURCES = tests/unit/link-as-cxx.cc
tests_unit_test_inverse_edits_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_inverse_edits_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_guiding
tests_unit_test_guiding_SOURCES = tests/unit/test_guiding.c tests/unit/scene_helpers.h
tests_unit_test_guiding_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_guiding_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_implicit
tests_unit_test_implicit_SOURCES = tests/unit/test_implicit.c tests/unit/fork_fixture.h
tests_unit_test_implicit_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_implicit_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_mtet
tests_unit_test_mtet_SOURCES = tests/unit/test_mtet.c tests/unit/trimesh_check.h
tests_unit_test_mtet_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_mtet_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_atan2
tests_unit_test_atan2_SOURCES = tests/unit/test_atan2.c
tests_unit_test_atan2_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_atan2_LDADD = $(CMOCKA_LIBS) -lm

check_PROGRAMS += tests/unit/test_dc
tests_unit_test_dc_SOURCES = tests/unit/test_dc.c tests/unit/trimesh_check.h
tests_unit_test_dc_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_dc_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_grade
tests_unit_test_grade_SOURCES = tests/unit/test_grade.c tests/unit/trimesh_check.h
tests_unit_test_grade_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_grade_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_patch
tests_unit_test_patch_SOURCES = tests/unit/test_patch.c tests/unit/trimesh_check.h tests/unit/fork_fixture.h
tests_unit_test_patch_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_patch_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_forest
tests_unit_test_forest_SOURCES = tests/unit/test_forest.c tests/unit/scene_helpers.h
tests_unit_test_forest_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_forest_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_junctions
tests_unit_test_junctions_SOURCES = tests/unit/test_junctions.c tests/unit/trimesh_check.h
nodist_EXTRA_tests_unit_test_junctions_SOURCES = tests/unit/link-as-cxx.cc
tests_unit_test_junctions_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_junctions_LDADD = $(UNIT_LDADD)
