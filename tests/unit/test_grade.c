/* A graded grid (implicit.h, merp_grid_warp; grade.c): levels that widen
 * away from where the cells must be fine, whole lattice cells from the
 * anchor while they stay fine; sample positions, cells and bounds that
 * agree; and dual contouring on one, which closes a tapered capsule on
 * fewer cells than the regular grid its thin end needs. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "mesh/implicit/implicit.h"
#include "trimesh_check.h"

#define N 400

/* Lattice cells 190..209 must be fine, the others may be 4 wide. */
static void fine_in_middle(float *fine)
{
    for (uint32_t i = 0; i < N; i++)
        fine[i] = i >= 190 && i < 210 ? 1.0f : 4.0f;
}

static void levels_widen_away_from_fine(void **state)
{
    (void)state;
    float fine[N], u[N + 2], ratio[N + 2];
    fine_in_middle(fine);
    uint32_t cells = merp_grade_levels(fine, N, 200, N + 2, u, ratio);
    assert_true(cells > 0 && cells < N / 2); /* far fewer than the lattice's */
    assert_true(u[0] <= 0.0f && u[cells] >= (float)N);
    uint32_t anchor = N + 2, widest = 0;
    for (uint32_t l = 0; l <= cells; l++) {
        if (u[l] == 200.0f)
            anchor = l;
        assert_true(ratio[l] >= 1.0f && ratio[l] <= 4.0f);
        if (l < cells) {
            assert_true(u[l + 1] > u[l]);
            assert_float_equal(ratio[l], u[l + 1] - u[l], 1e-4f); /* the step, its positions rounded */
            /* the ratio changes gently: at most a tenth of a cell per cell of h */
            assert_true(fabsf(ratio[l + 1] - ratio[l]) <= 0.1f * (u[l + 1] - u[l]) + 1e-5f);
            if (ratio[l] > 3.5f)
                widest++;
        }
        /* every level within the fine cells is a whole lattice plane */
        if (u[l] >= 190.0f && u[l] <= 210.0f)
            assert_float_equal(u[l], floorf(u[l]), 0.0f);
    }
    assert_true(anchor <= cells);
    assert_true(widest > 0); /* far from the fine cells, the cells widen to 4 */
}

static void levels_need_room(void **state)
{
    (void)state;
    float fine[N], u[8], ratio[8];
    for (uint32_t i = 0; i < N; i++)
        fine[i] = 1.0f;
    assert_int_equal(merp_grade_levels(fine, N, 10, 8, u, ratio), 0);
}

/* A grid graded along y: fine about y = 0.7 (near the capsule's thin end),
 * up to 4 × h at its thick end, scaled about the y axis. */
typedef struct graded_grid {
    merp_grid g;
    merp_grid_warp w;
    float level[N + 2], ratio[N + 2];
} graded_grid;

static void graded_capsule_grid(graded_grid *gg, float h)
{
    merp_grid *g = &gg->g;
    *g = (merp_grid){{-0.9f, -1.9f, -0.9f}, h, {0, 0, 0}, NULL};
    for (int a = 0; a < 3; a++)
        g->n[a] = (uint32_t)ceilf((a == 1 ? 3.8f : 1.8f) / h);
    assert_true(g->n[1] <= N);
    float fine[N], u[N + 2];
    for (uint32_t i = 0; i < g->n[1]; i++) {
        float y = g->origin[1] + ((float)i + 0.5f) * h;
        fine[i] = y > 0.5f ? 1.0f : 4.0f;
    }
    uint32_t anchor = (uint32_t)floorf((1.0f - g->origin[1]) / h);
    uint32_t cells = merp_grade_levels(fine, g->n[1], anchor, N + 2, u, gg->ratio);
    assert_true(cells > 0 && cells < g->n[1]);
    gg->w = (merp_grid_warp){.axis = 1, .level = gg->level, .ratio = gg->ratio, .center = {0, 0, 0}};
    float widest = 0, lean = 0;
    for (uint32_t l = 0; l <= cells; l++) {
        gg->level[l] = g->origin[1] + u[l] * h;
        widest = fmaxf(widest, gg->ratio[l]);
        if (l < cells)
            lean = fmaxf(lean, fabsf(gg->ratio[l + 1] - gg->ratio[l]));
    }
    for (int a = 0; a < 3; a++)
        gg->w.reach[a] = widest * h + lean * (float)g->n[a] * h;
    gg->w.reach[1] = widest * h;
    g->origin[1] = gg->level[0];
    g->n[1] = cells;
    g->warp = &gg->w;
}

/* Each cell's centre lies in it (merp_grid_locate) and stays put in
 * merp_grid_clamp; a far point is clamped to within the cell's corners;
 * every corner lies within merp_grid_reach of the cell's lowest. */
static void cells_agree_on(float h)
{
    graded_grid gg;
    graded_capsule_grid(&gg, h);
    const merp_grid *g = &gg.g;
    for (uint32_t k = 0; k < g->n[2]; k += 3)
        for (uint32_t j = 0; j < g->n[1]; j++)
            for (uint32_t i = 0; i < g->n[0]; i += 2) {
                float c[3] = {0, 0, 0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
                float low[3];
                merp_grid_point(g, i, j, k, low);
                for (int q = 0; q < 8; q++) {
                    float p[3];
                    merp_grid_point(g, i + (q & 1), j + (q >> 1 & 1), k + (q >> 2 & 1), p);
                    for (int a = 0; a < 3; a++) {
                        c[a] += p[a] / 8.0f, lo[a] = fminf(lo[a], p[a]), hi[a] = fmaxf(hi[a], p[a]);
                        assert_true(fabsf(p[a] - low[a]) <= merp_grid_reach(g, a) * 1.0001f);
                    }
                }
                uint32_t cell[3];
                merp_grid_locate(g, c, cell);
                assert_int_equal(cell[0], i);
                assert_int_equal(cell[1], j);
                assert_int_equal(cell[2], k);
                const uint32_t at[3] = {i, j, k};
                float v[3] = {c[0], c[1], c[2]};
                merp_grid_clamp(g, at, v);
                for (int a = 0; a < 3; a++)
                    assert_float_equal(v[a], c[a], 1e-5f);
                float far[3] = {10.0f, -10.0f, 10.0f};
                merp_grid_clamp(g, at, far);
                for (int a = 0; a < 3; a++)
                    assert_true(far[a] >= lo[a] - 1e-5f && far[a] <= hi[a] + 1e-5f);
            }
}

/* On 26 cells across, and on 90, where the cells far from the axis lean
 * by more than their width between levels of different ratios. */
static void cells_agree(void **state)
{
    (void)state;
    cells_agree_on(0.07f);
    cells_agree_on(0.02f);
}

static float seg_fn(const float p[3], const void *data)
{
    return merp_seg_field(data, p);
}

static uint32_t capsule_triangles(const merp_grid *g, const merp_seg *s)
{
    uint64_t v, t;
    merp_dc_bound(g, &v, &t);
    mesh_out o;
    mesh_alloc(&o, v, t);
    mer_error err;
    assert_int_equal(merp_dc_polygonize(g, seg_fn, NULL, s, NULL, 0, &o.m, NULL, &err), MER_OK);
    assert_closed_genus0(&o);
    for (uint32_t i = 0; i < o.m.vertex_count; i++) {
        const float *p = o.m.positions + 3 * i;
        float t_, d = merp_seg_distance(s, p, &t_), r = (1 - t_) * s->ra + t_ * s->rb;
        /* within 10 % of the cells there (4 × h at the thick end) */
        assert_float_equal(d, r, p[1] > 0.5f ? 7e-3f : 2.8e-2f);
    }
    uint32_t n = o.m.triangle_count;
    mesh_free(&o);
    return n;
}

/* A capsule thick at y = −1 (0.6) and thin at y = 1 (0.15), on cells of
 * h = 0.05 where it is thin and up to 4 × h where it is thick: closed,
 * genus 0, on the surface; and fewer triangles than on the regular grid. */
static void capsule_on_graded_grid(void **state)
{
    (void)state;
    const merp_seg s = {{0, -1, 0}, {0, 1, 0}, 0.6f, 0.15f};
    graded_grid gg;
    graded_capsule_grid(&gg, 0.05f);
    uint32_t graded = capsule_triangles(&gg.g, &s);
    merp_grid regular = {{-0.9f, -1.9f, -0.9f}, 0.05f, {36, 76, 36}, NULL};
    uint32_t fine = capsule_triangles(&regular, &s);
    print_message("capsule: %u triangles graded, %u regular\n", graded, fine);
    assert_true(graded < fine / 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(levels_widen_away_from_fine),
        cmocka_unit_test(levels_need_room),
        cmocka_unit_test(cells_agree),
        cmocka_unit_test(capsule_on_graded_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
