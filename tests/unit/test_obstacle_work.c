/* Unit tests for the bound on the work a mesh obstacle or mesh volume puts on a
 * scene (lib/env/solid.c merp_solid_work, obstacles.c, volumes.c, env.c).
 *
 * A mesh given in raw quantized units (0..65535, a KHR_mesh_quantization file
 * read without its dequantizing transform) or one spanning thousands of scene
 * units has cells thousands of voxels wide: every voxel centre the shadow cast
 * asks about lies in the few cells along the mesh's faces and walks long runs of
 * them, a hundred triangle tests each, a million voxels: seconds of work for a
 * few dozen triangles. Such a mesh is refused, MER_ERR_RANGE naming "xyz",
 * before it is cast; the estimate that refuses it is checked to follow the real
 * cost (meshes of the scene's size stay far below the bound). */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/scene.h>

#include "scene_helpers.h"
#include "scene_private.h" /* merp_solid and its work estimate */

/* A cube [lo, hi]³, each face split into k × k quads: 12 k² triangles. */
static size_t cube(float lo, float hi, int k, float *out)
{
    size_t t = 0;
    for (int ax = 0; ax < 3; ax++)
        for (int side = 0; side < 2; side++) {
            int U = (ax + 1) % 3, V = (ax + 2) % 3;
            for (int i = 0; i < k; i++)
                for (int j = 0; j < k; j++) {
                    float q[4][3];
                    float u0 = lo + (hi - lo) * (float)i / (float)k;
                    float u1 = lo + (hi - lo) * (float)(i + 1) / (float)k;
                    float v0 = lo + (hi - lo) * (float)j / (float)k;
                    float v1 = lo + (hi - lo) * (float)(j + 1) / (float)k;
                    for (int c = 0; c < 4; c++)
                        q[c][ax] = side ? hi : lo;
                    q[0][U] = u0, q[0][V] = v0, q[1][U] = u1, q[1][V] = v0;
                    q[2][U] = u1, q[2][V] = v1, q[3][U] = u0, q[3][V] = v1;
                    const int order[6] = {0, 1, 2, 0, 2, 3};
                    for (int c = 0; c < 6; c++)
                        memcpy(out + 9 * t + 3 * (c % 3) + (c >= 3 ? 9 : 0), q[order[c]],
                               3 * sizeof *out);
                    t += 2;
                }
        }
    return t;
}

static float tri[9 * 12 * 16];

static double work_in_default_scene(const float *xyz, size_t n)
{
    merp_solid *s = NULL;
    mer_error err;
    assert_int_equal(merp_solid_new(xyz, n, &s, &err), MER_OK);
    mer_params p = mer_params_default();
    double vox = (double)p.voxel;
    double w = merp_solid_work(s, p.bounds_min, p.bounds_max, 2.0 / (vox * vox * vox));
    merp_solid_free(s);
    return w;
}

static void test_quantized_mesh_refused(void **state)
{
    (void)state;
    mer_scene *s = new_scene(NULL, 1);
    uint64_t before = mer_scene_hash(s);
    // 108 triangles in raw 16-bit units: the scene lies in the cells of three faces.
    size_t n = cube(-1.0f, 65535.0f, 3, tri);
    mer_error err = {0};
    assert_int_equal(mer_scene_add_mesh(s, tri, n, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "xyz");
    assert_non_null(strstr(err.message, "too coarse"));
    // Or only 1e4 units across, around the scene.
    n = cube(-1.0f, 1e4f, 3, tri);
    assert_int_equal(mer_scene_add_mesh(s, tri, n, &err), MER_ERR_RANGE);
    assert_true(mer_scene_hash(s) == before); /* nothing added */
    mer_scene_free(s);
}

/* A slab 1e4 wide and 1 thick: every cell lies on its faces. */
static size_t slab(float *out)
{
    size_t n = cube(0.0f, 1e4f, 1, out);
    for (size_t i = 1; i < 9 * n; i += 3)
        out[i] = out[i] > 0.0f ? 1.0f : 0.0f;
    return n;
}

static void test_coarse_mesh_volume_refused(void **state)
{
    (void)state;
    // A marker volume draws in the cells that may hold inside points; in a slab
    // every one of them walks a run of face cells for every draw.
    mer_scene *s = new_scene(NULL, 1);
    uint64_t before = mer_scene_hash(s);
    mer_error err = {0};
    size_t n = slab(tri);
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, n, 1000000, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "xyz");
    assert_true(mer_scene_hash(s) == before);
    // A cube as wide is mostly inside, O(1) per draw: taken.
    n = cube(-1.0f, 1e4f, 3, tri);
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, n, 1000, &err), MER_OK);
    mer_scene_free(s);
}

static void test_scene_sized_meshes_accepted(void **state)
{
    (void)state;
    // The estimate follows the cost: coarse cells around the scene cost it
    // thousands of times what a mesh of its own size does.
    double coarse = work_in_default_scene(tri, cube(-1.0f, 65535.0f, 3, tri));
    double fits = work_in_default_scene(tri, cube(-30.0f, 30.0f, 4, tri));
    assert_true(coarse > MERP_SOLID_WORK_MAX);
    assert_true(fits < MERP_SOLID_WORK_MAX / 20);
    assert_true(coarse > 50 * fits);
    mer_scene *s = new_scene(NULL, 1);
    mer_error err = {0};
    size_t n = cube(-30.0f, 30.0f, 4, tri);
    assert_int_equal(mer_scene_add_mesh(s, tri, n, &err), MER_OK);
    // A mesh far larger than the scene but whose faces lie outside it costs
    // nothing there: its inside is cached per cell.
    n = cube(-2e5f, 2e5f, 2, tri);
    assert_int_equal(mer_scene_add_mesh(s, tri, n, &err), MER_OK);
    mer_scene_free(s);
}

static void test_finer_grid_rechecks(void **state)
{
    (void)state;
    // Accepted on a coarse shadow grid, a mesh of 2000-unit cells must not
    // become a million voxel walks when the voxels shrink.
    mer_params p = mer_params_default();
    p.voxel = 20.0f;
    mer_scene *s = new_scene(&p, 1);
    mer_error err = {0};
    size_t n = cube(-1.0f, 65535.0f, 3, tri);
    assert_int_equal(mer_scene_add_mesh(s, tri, n, &err), MER_OK);
    uint64_t before = mer_scene_hash(s);
    p.voxel = 1.0f;
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "voxel");
    assert_true(mer_scene_hash(s) == before);
    assert_true(mer_scene_params(s)->voxel == 20.0f);
    mer_scene_free(s);
}

static void test_boxes_and_spheres_bounded(void **state)
{
    (void)state;
    // Boxes and spheres answer in O(1) and are cast over the grid only,
    // whatever their size: the bound is the grid's.
    mer_scene *s = new_scene(NULL, 1);
    mer_error err = {0};
    const float lo[3] = {-1e6f, -1e6f, -1e6f}, hi[3] = {1e6f, 1e6f, 1e6f};
    assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
    const float c[3] = {0.0f, 0.0f, 0.0f};
    assert_int_equal(mer_scene_add_sphere(s, c, 1e6f, &err), MER_OK);
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quantized_mesh_refused),
        cmocka_unit_test(test_coarse_mesh_volume_refused),
        cmocka_unit_test(test_scene_sized_meshes_accepted),
        cmocka_unit_test(test_finer_grid_rechecks),
        cmocka_unit_test(test_boxes_and_spheres_bounded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
