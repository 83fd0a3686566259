/* Natural spacing for forests (meristem/sow.h): Bridson's Poisson-disk sampling
 * holds its minimum distance, reaches its count or says how many fit, and is
 * deterministic; the Voronoi cells of the sites contain each site and partition
 * a point set between them. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/rng.h>
#include <meristem/sow.h>

static const float LO[2] = {-20.0f, -10.0f}, HI[2] = {30.0f, 25.0f};

static void assert_spaced(const float *p, uint32_t n, float r)
{
    for (uint32_t i = 0; i < n; i++) {
        assert_true(p[2 * i] >= LO[0] && p[2 * i] <= HI[0]);
        assert_true(p[2 * i + 1] >= LO[1] && p[2 * i + 1] <= HI[1]);
        for (uint32_t j = 0; j < i; j++) {
            float dx = p[2 * i] - p[2 * j], dz = p[2 * i + 1] - p[2 * j + 1];
            assert_true(dx * dx + dz * dz >= r * r);
        }
    }
}

static void test_minimum_distance_and_count(void **state)
{
    (void)state;
    static float p[2 * 400];
    const float rs[3] = {2.0f, 3.5f, 5.0f};
    const uint32_t counts[3] = {200, 60, 30};
    for (int k = 0; k < 3; k++)
        for (uint64_t seed = 0; seed < 5; seed++) {
            uint32_t placed = 0;
            mer_error err;
            assert_int_equal(mer_poisson_disk(LO, HI, rs[k], counts[k], seed, p, &placed, &err),
                             MER_OK);
            assert_int_equal(placed, counts[k]);
            assert_spaced(p, placed, rs[k]);
        }
}

/* A sparse forest spreads over the whole area, not around the first point. */
static void test_sparse_forest_spreads(void **state)
{
    (void)state;
    float p[2 * 20];
    uint32_t placed;
    assert_int_equal(mer_poisson_disk(LO, HI, 2.0f, 20, 3, p, &placed, NULL), MER_OK);
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
    for (uint32_t i = 0; i < placed; i++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fminf(lo[a], p[2 * i + a]);
            hi[a] = fmaxf(hi[a], p[2 * i + a]);
        }
    assert_true(hi[0] - lo[0] > 0.6f * (HI[0] - LO[0]));
    assert_true(hi[1] - lo[1] > 0.6f * (HI[1] - LO[1]));
}

/* More than fit: MER_ERR_LIMIT naming how many do, and those are given. */
static void test_count_not_reached(void **state)
{
    (void)state;
    float *p = malloc(2 * 5000 * sizeof *p);
    assert_non_null(p);
    uint32_t placed = 0;
    mer_error err;
    assert_int_equal(mer_poisson_disk(LO, HI, 4.0f, 5000, 1, p, &placed, &err), MER_ERR_LIMIT);
    assert_string_equal(err.field, "count");
    assert_true(placed > 30 && placed < 5000);
    char want[32];
    snprintf(want, sizeof want, "only %u plants", (unsigned)placed);
    assert_non_null(strstr(err.message, want));
    assert_spaced(p, placed, 4.0f);
    /* Bridson's set is nearly maximal: few points of a fine lattice are at least
     * r from every placed point (30 tries per active point leave rare gaps). */
    int free_spots = 0, spots = 0;
    for (float x = LO[0]; x <= HI[0]; x += 0.5f)
        for (float z = LO[1]; z <= HI[1]; z += 0.5f) {
            int near = 0;
            for (uint32_t i = 0; i < placed && !near; i++) {
                float dx = p[2 * i] - x, dz = p[2 * i + 1] - z;
                near = dx * dx + dz * dz < 16.0f;
            }
            free_spots += !near;
            spots++;
        }
    assert_true(free_spots * 50 < spots);
    free(p);
}

static void test_deterministic(void **state)
{
    (void)state;
    float a[2 * 50], b[2 * 50], c[2 * 50];
    uint32_t na, nb, nc;
    assert_int_equal(mer_poisson_disk(LO, HI, 3.0f, 50, 77, a, &na, NULL), MER_OK);
    assert_int_equal(mer_poisson_disk(LO, HI, 3.0f, 50, 77, b, &nb, NULL), MER_OK);
    assert_int_equal(mer_poisson_disk(LO, HI, 3.0f, 50, 78, c, &nc, NULL), MER_OK);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, sizeof a);
    assert_true(memcmp(a, c, sizeof a) != 0);
}

static void test_refusals(void **state)
{
    (void)state;
    float p[2];
    uint32_t placed = 9;
    mer_error err;
    assert_int_equal(mer_poisson_disk(LO, HI, 0.0f, 1, 0, p, &placed, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "min_distance");
    assert_int_equal(placed, 0);
    assert_int_equal(mer_poisson_disk(HI, LO, 1.0f, 1, 0, p, &placed, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "area");
    assert_int_equal(mer_poisson_disk(LO, HI, 1e-4f, 1, 0, p, &placed, &err), MER_ERR_RANGE);
    assert_int_equal(mer_poisson_disk(LO, HI, 1.0f, 0, 0, NULL, &placed, &err), MER_OK);
    assert_int_equal(placed, 0);
}

/* Every site lies in its own cell; clipping points to every cell in turn gives
 * each point to exactly one site, the nearest. */
static void test_voronoi_cells(void **state)
{
    (void)state;
    float sites[2 * 12];
    uint32_t n;
    assert_int_equal(mer_poisson_disk(LO, HI, 6.0f, 12, 5, sites, &n, NULL), MER_OK);
    for (uint32_t i = 0; i < n; i++)
        assert_int_equal(mer_voronoi_cell(sites, n, sites + 2 * i), i);
    enum { M = 3000 };
    static float pts[3 * M], work[3 * M];
    mer_rng rng;
    mer_rng_seed(&rng, 4);
    for (int i = 0; i < M; i++) {
        pts[3 * i] = mer_rng_range(&rng, LO[0], HI[0]);
        pts[3 * i + 1] = mer_rng_range(&rng, 0.0f, 10.0f);
        pts[3 * i + 2] = mer_rng_range(&rng, LO[1], HI[1]);
    }
    size_t total = 0;
    for (uint32_t c = 0; c < n; c++) {
        memcpy(work, pts, sizeof pts);
        size_t kept = mer_voronoi_clip(sites, n, c, work, M);
        total += kept;
        for (size_t k = 0; k < kept; k++) {
            float dc[2] = {work[3 * k] - sites[2 * c], work[3 * k + 2] - sites[2 * c + 1]};
            for (uint32_t o = 0; o < n; o++) {
                float d[2] = {work[3 * k] - sites[2 * o], work[3 * k + 2] - sites[2 * o + 1]};
                assert_true(dc[0] * dc[0] + dc[1] * dc[1] <= d[0] * d[0] + d[1] * d[1]);
            }
        }
    }
    assert_int_equal(total, M);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_minimum_distance_and_count),
        cmocka_unit_test(test_sparse_forest_spreads),
        cmocka_unit_test(test_count_not_reached),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_voronoi_cells),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
