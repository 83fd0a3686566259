/* Unit tests for mer_scene_clone (lib/scene_clone.c): a copy hashes and meshes
 * byte-identically to its original, grows on identically under every preset, and
 * shares nothing with it (the original is freed first: ASan sees any alias). */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#include "scene_helpers.h"

/* The GLB of `s` with default mesh options. */
static uint8_t *glb(const mer_scene *s, size_t *size)
{
    mer_mesh *m = NULL;
    mer_error err;
    if (mer_mesh_build(s, NULL, &m, &err) != MER_OK)
        fail_msg("mesh: %s", err.message);
    uint8_t *bytes = NULL;
    if (mer_gltf_write_tree(m, NULL, NULL, &bytes, size, &err) != MER_OK)
        fail_msg("glTF: %s", err.message);
    mer_mesh_free(m);
    return bytes;
}

static void assert_same(const mer_scene *a, const mer_scene *b)
{
    assert_int_equal(mer_scene_hash(a), mer_scene_hash(b));
    size_t na, nb;
    uint8_t *ga = glb(a, &na), *gb = glb(b, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(ga, gb, na);
    mer_gltf_free(ga);
    mer_gltf_free(gb);
}

static mer_scene *copy(const mer_scene *s)
{
    mer_scene *c = NULL;
    mer_error err;
    if (mer_scene_clone(s, &c, &err) != MER_OK)
        fail_msg("clone: %s", err.message);
    return c;
}

/* A tetrahedron beside the trunk: a mesh obstacle. */
static void add_tetrahedron(mer_scene *s)
{
    static const float v[4][3] = {{2, 0.5f, -1}, {4, 0.5f, -1}, {3, 0.5f, 1}, {3, 3, 0}};
    static const int f[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    float xyz[36];
    for (int t = 0; t < 4; t++)
        for (int k = 0; k < 3; k++)
            memcpy(&xyz[9 * t + 3 * k], v[f[t][k]], sizeof v[0]);
    mer_error err;
    if (mer_scene_add_mesh(s, xyz, 4, &err) != MER_OK)
        fail_msg("mesh obstacle: %s", err.message);
}

/* The edits both copies of a scene get before the clone. */
static void shape(mer_scene *s)
{
    const float lo[3] = {-4, 0, -4}, hi[3] = {-3, 2, -3};
    mer_error err;
    assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
    add_tetrahedron(s);
    step(s, 5);
    uint32_t n = mer_scene_node_bound(s);
    if (n > 4)
        (void)mer_scene_prune(s, n - 2, &err);
}

static void test_presets_grow_on_identically(void **state)
{
    (void)state;
    for (size_t i = 0; i < mer_preset_count(); i++) {
        mer_params p;
        mer_error err;
        assert_int_equal(mer_preset_params(mer_preset_name(i), &p, &err), MER_OK);
        mer_scene *a = new_scene(&p, 7 + i), *b = new_scene(&p, 7 + i);
        shape(a);
        shape(b);
        mer_scene *c = copy(a);
        mer_scene_free(a); /* the copy must not lean on it */
        assert_same(b, c);
        step(b, 4);
        step(c, 4);
        assert_same(b, c);
        mer_scene_free(b);
        mer_scene_free(c);
    }
}

static void test_copy_of_a_copy_is_independent(void **state)
{
    (void)state;
    mer_scene *a = make(NULL, 3);
    step(a, 4);
    mer_scene *c = copy(a);
    mer_scene *d = copy(c);
    step(c, 3); /* grows the copy only */
    assert_same(a, d);
    step(a, 3);
    assert_same(a, c);
    mer_scene_free(a);
    mer_scene_free(c);
    mer_scene_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_presets_grow_on_identically),
        cmocka_unit_test(test_copy_of_a_copy_is_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
