/* Allocation failure: through the hook of meristem/alloc.h, fail the N-th
 * allocation of a call, for every N until the call needs no more, and check
 * meristem/result.h's promise: the call returns MER_ERR_NOMEM, changes nothing
 * (mer_scene_hash as before, no output) and leaks nothing (the hook counts
 * blocks; ASan checks the rest when the suite runs under it). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include <meristem.h>
#include <meristem/mesh.h>

#include "scene_helpers.h"

/* The counting allocator: `fail_at` is the number of the allocation to refuse
 * (0: none); `live` the blocks handed out and not yet freed. */
static size_t calls, fail_at, live;

static void *chaos_malloc(size_t size)
{
    if (++calls == fail_at)
        return NULL;
    void *p = malloc(size ? size : 1);
    live += p != NULL;
    return p;
}

static void *chaos_realloc(void *ptr, size_t size)
{
    if (++calls == fail_at)
        return NULL;
    void *p = realloc(ptr, size ? size : 1);
    live += p != NULL && ptr == NULL;
    return p;
}

static void chaos_free(void *ptr)
{
    live -= ptr != NULL;
    free(ptr);
}

static int setup(void **state)
{
    (void)state;
    calls = fail_at = live = 0;
    mer_set_alloc_funcs(chaos_malloc, chaos_realloc, chaos_free);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    mer_set_alloc_funcs(NULL, NULL, NULL);
    return 0;
}

/* One call under test on `s`, its output (if any) released before returning. */
typedef mer_result (*chaos_call)(mer_scene *s, mer_error *err);

/* Runs `call` on `s` failing the 1st, 2nd, ... allocation it makes, until it
 * succeeds; each failure must be MER_ERR_NOMEM with `s` unchanged and no block
 * lost (blocks the scene keeps, a grown array, are counted when it is freed).
 * Returns the number of allocations the call needed. */
static size_t fail_each(mer_scene *s, chaos_call call)
{
    const uint64_t before = mer_scene_hash(s);
    for (size_t n = 1;; n++) {
        calls = 0;
        fail_at = n;
        mer_error err = {0};
        mer_result rc = call(s, &err);
        fail_at = 0;
        if (rc == MER_OK)
            return n - 1;
        if (rc != MER_ERR_NOMEM)
            fail_msg("allocation %zu failed: %s (%s), not nomem", n, mer_result_name(rc),
                     err.message);
        if (mer_scene_hash(s) != before)
            fail_msg("allocation %zu failed and the scene changed", n);
    }
}

/* A small tree in a space-colonization scene with an obstacle: every path
 * below has work to do. */
static mer_scene *chaos_scene(void)
{
    mer_params p = mer_params_default();
    mer_scene *s = new_scene(&p, 3);
    step(s, 4);
    return s;
}

static mer_result call_prune(mer_scene *s, mer_error *err)
{
    return mer_scene_prune(s, 2, err);
}

static mer_result call_add_markers(mer_scene *s, mer_error *err)
{
    static const float xyz[] = {0, 5, 0, 1, 6, 1, -1, 7, 0, 0.5f, 4, -0.5f};
    return mer_scene_add_markers(s, xyz, 4, err);
}

static mer_result call_brush(mer_scene *s, mer_error *err)
{
    mer_brush b = {.center = {0, 6, 0}, .radius = 2, .max_count = 50, .pressure = 0.5f};
    return mer_scene_brush(s, &b, NULL, NULL, err);
}

static mer_result call_add_box(mer_scene *s, mer_error *err)
{
    static const float lo[3] = {4, 0, -1}, hi[3] = {5, 2, 1};
    return mer_scene_add_box(s, lo, hi, err);
}

/* A closed tetrahedron beside the tree. */
static const float tetra[] = {
    3, 0, 3, 5, 0, 3, 4, 0, 5,   3, 0, 3, 4, 2, 4, 5, 0, 3,
    5, 0, 3, 4, 2, 4, 4, 0, 5,   4, 0, 5, 4, 2, 4, 3, 0, 3,
};

static mer_result call_add_mesh(mer_scene *s, mer_error *err)
{
    return mer_scene_add_mesh(s, tetra, 4, err);
}

static mer_result call_fill_mesh(mer_scene *s, mer_error *err)
{
    return mer_scene_fill_mesh_markers(s, tetra, 4, 30, err);
}

static mer_result call_fill_volume(mer_scene *s, mer_error *err)
{
    static const float center[3] = {0, 8, 0}, size[3] = {3, 3, 3};
    return mer_scene_fill_markers(s, MER_VOLUME_SPHERE, center, size, 40, err);
}

/* New parameters that rebuild the grids. */
static mer_result call_set_params(mer_scene *s, mer_error *err)
{
    mer_params p = *mer_scene_params(s);
    p.voxel *= 0.5f;
    p.marker_cell *= 0.5f;
    p.ground = 0.5f;
    return mer_scene_set_params(s, &p, err);
}

static mer_result call_snapshot(mer_scene *s, mer_error *err)
{
    mer_mesh *mesh = NULL;
    mer_result rc = mer_mesh_build(s, NULL, &mesh, err);
    if (rc != MER_OK) {
        assert_null(mesh);
        return rc;
    }
    uint8_t *glb = NULL;
    size_t size = 0;
    rc = mer_gltf_write_tree(mesh, NULL, NULL, &glb, &size, err);
    mer_mesh_free(mesh);
    if (rc != MER_OK)
        assert_null(glb);
    mer_gltf_free(glb);
    return rc;
}

static void run(chaos_call call)
{
    mer_scene *s = chaos_scene();
    assert_true(fail_each(s, call) > 0);
    mer_scene_free(s);
    assert_int_equal(live, 0);
}

/* A step is not all-or-nothing (scene.h: the failing step may be partial; the
 * daemon restores the session): each failure must be MER_ERR_NOMEM with the
 * whole steps before it kept, leave a scene that steps and meshes on, and leak
 * nothing. A fresh scene for each N, since a failed step changes it. */
static void test_step(void **state)
{
    (void)state;
    for (size_t n = 1;; n++) {
        mer_scene *s = chaos_scene();
        const uint32_t at = mer_scene_step_index(s);
        uint32_t done = 0;
        calls = 0;
        fail_at = n;
        mer_result rc = mer_scene_step(s, 3, NULL, NULL, NULL, &done, NULL);
        fail_at = 0;
        if (rc == MER_OK) {
            mer_scene_free(s);
            break;
        }
        assert_int_equal(rc, MER_ERR_NOMEM);
        assert_true(done < 3);
        assert_int_equal(mer_scene_step_index(s), at + done);
        step(s, 1);
        mer_mesh *mesh = NULL;
        assert_int_equal(mer_mesh_build(s, NULL, &mesh, NULL), MER_OK);
        mer_mesh_free(mesh);
        mer_scene_free(s);
        assert_int_equal(live, 0);
    }
    assert_int_equal(live, 0);
}

static void test_prune(void **state) { (void)state; run(call_prune); }
static void test_add_markers(void **state) { (void)state; run(call_add_markers); }
static void test_brush(void **state) { (void)state; run(call_brush); }
static void test_add_box(void **state) { (void)state; run(call_add_box); }
static void test_snapshot(void **state) { (void)state; run(call_snapshot); }
static void test_add_mesh(void **state) { (void)state; run(call_add_mesh); }
static void test_fill_mesh(void **state) { (void)state; run(call_fill_mesh); }
static void test_fill_volume(void **state) { (void)state; run(call_fill_volume); }
static void test_set_params(void **state) { (void)state; run(call_set_params); }

/* Creating a scene: every failure is NOMEM, with nothing returned or kept. */
static void test_new(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    for (size_t n = 1;; n++) {
        calls = 0;
        fail_at = n;
        mer_scene *s = NULL;
        mer_result rc = mer_scene_new(&p, 3, &s, NULL);
        fail_at = 0;
        if (rc == MER_OK) {
            mer_scene_free(s);
            break;
        }
        assert_int_equal(rc, MER_ERR_NOMEM);
        assert_null(s);
        assert_int_equal(live, 0);
    }
    assert_int_equal(live, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_new, setup, teardown),
        cmocka_unit_test_setup_teardown(test_step, setup, teardown),
        cmocka_unit_test_setup_teardown(test_prune, setup, teardown),
        cmocka_unit_test_setup_teardown(test_add_markers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_brush, setup, teardown),
        cmocka_unit_test_setup_teardown(test_add_box, setup, teardown),
        cmocka_unit_test_setup_teardown(test_snapshot, setup, teardown),
        cmocka_unit_test_setup_teardown(test_add_mesh, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fill_mesh, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fill_volume, setup, teardown),
        cmocka_unit_test_setup_teardown(test_set_params, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
