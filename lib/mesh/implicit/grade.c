/* meristem — a graded grid (implicit.h, merp_grid_warp): levels along one
 * axis whose cells widen where a patch needs no fine ones, and finding and
 * bounding cells in it. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "mesh/implicit/implicit.h"

/* How much the ratio allowed may change per lattice cell of h along the
 * axis: the cells widen from 1 to 2 × h over some 33 of them, so that
 * between two levels (the allowance taken per lattice cell, a step may
 * change twice as much) the cells lean by a few per cent of their distance
 * from the center. Of the runs' patches of 56 presets (seed 1, 14 steps)
 * that a graded grid serves, 24 of about 120 did not close on it with 0.1
 * (the regular grid then took them), the 10k bench tree's run of 14 forks
 * among them; with 0.03, 14 of 124. */
#define GRADE_SLOPE 0.03f

void merp_grid_locate(const merp_grid *g, const float p[3], uint32_t cell[3])
{
    const merp_grid_warp *w = g->warp;
    float r = 1.0f;
    if (w != NULL) {
        const int A = w->axis;
        uint32_t lo = 0, hi = g->n[A] - 1; /* the last level at or below p */
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo + 1) / 2;
            if (w->level[mid] <= p[A])
                lo = mid;
            else
                hi = mid - 1;
        }
        /* the cell's sides lean: its ratio at p's height, as merp_grid_clamp's */
        float t = (p[A] - w->level[lo]) / (w->level[lo + 1] - w->level[lo]);
        t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
        cell[A] = lo, r = w->ratio[lo] + t * (w->ratio[lo + 1] - w->ratio[lo]);
    }
    for (int a = 0; a < 3; a++) {
        if (w != NULL && a == w->axis)
            continue;
        float x = w != NULL ? w->center[a] + (p[a] - w->center[a]) / r : p[a];
        float c = floorf((x - g->origin[a]) / g->h);
        cell[a] = c < 0.0f ? 0 : c >= (float)g->n[a] ? g->n[a] - 1 : (uint32_t)c;
    }
}

void merp_grid_clamp(const merp_grid *g, const uint32_t cell[3], float v[3])
{
    const merp_grid_warp *w = g->warp;
    if (w == NULL) {
        for (int k = 0; k < 3; k++) {
            float lo = g->origin[k] + (float)cell[k] * g->h;
            v[k] = v[k] < lo ? lo : v[k] > lo + g->h ? lo + g->h : v[k];
        }
        return;
    }
    const int A = w->axis;
    const uint32_t l = cell[A];
    float bottom = w->level[l], top = w->level[l + 1];
    v[A] = v[A] < bottom ? bottom : v[A] > top ? top : v[A];
    float t = (v[A] - bottom) / (top - bottom), r = w->ratio[l] + t * (w->ratio[l + 1] - w->ratio[l]);
    for (int k = 0; k < 3; k++) {
        if (k == A)
            continue;
        float lo = w->center[k] + (g->origin[k] + (float)cell[k] * g->h - w->center[k]) * r;
        float hi = w->center[k] + (g->origin[k] + (float)(cell[k] + 1) * g->h - w->center[k]) * r;
        v[k] = v[k] < lo ? lo : v[k] > hi ? hi : v[k];
    }
}

/* The ratio allowed at lattice position u (in cells of h from the axis's
 * origin), from each lattice cell's (graded to GRADE_SLOPE). */
static float allowed(const float *fine, uint32_t n, float u)
{
    float c = floorf(u);
    return fine[c < 0.0f ? 0 : c >= (float)n ? n - 1 : (uint32_t)c];
}

/* The width (in cells of h) of the level step from u, upwards (dir 1) or
 * downwards (-1): the ratio allowed there, no more than at its far end. */
static float step_at(const float *fine, uint32_t n, float u, float dir)
{
    float r = allowed(fine, n, u);
    return fminf(r, allowed(fine, n, u + dir * r));
}

uint32_t merp_grade_levels(float *fine, uint32_t n, uint32_t anchor, uint32_t room, float *u, float *ratio)
{
    assert(n >= 1 && anchor < n && room >= 2);
    for (uint32_t i = 0; i < n; i++)
        assert(fine[i] >= 1.0f);
    for (uint32_t i = 1; i < n; i++)
        fine[i] = fminf(fine[i], fine[i - 1] + GRADE_SLOPE);
    for (uint32_t i = n - 1; i-- > 0;)
        fine[i] = fminf(fine[i], fine[i + 1] + GRADE_SLOPE);
    /* Down from the anchor's lattice plane (a whole number of cells, so
     * where the ratio stays 1 the levels are the lattice's), then up; each
     * level's ratio its step's, as step_at gives it (≥ 1: the difference of
     * two positions can round below), positions summed in double. */
    uint32_t below = 0;
    double x = anchor;
    while (x > 0.0) {
        if (below + 2 > room)
            return 0;
        float step = step_at(fine, n, (float)x - 0.5f, -1.0f);
        x -= (double)step;
        u[below] = (float)x, ratio[below++] = step; /* reversed below */
    }
    for (uint32_t i = 0; i < below / 2; i++) {
        float t = u[i], q = ratio[i];
        u[i] = u[below - 1 - i], u[below - 1 - i] = t;
        ratio[i] = ratio[below - 1 - i], ratio[below - 1 - i] = q;
    }
    uint32_t count = below;
    x = anchor;
    u[count++] = (float)x;
    while (x < (double)n) {
        if (count + 1 > room)
            return 0;
        float step = step_at(fine, n, (float)x + 0.5f, 1.0f);
        x += (double)step;
        ratio[count - 1] = step; /* the step above the level before */
        u[count++] = (float)x;
    }
    ratio[count - 1] = ratio[count - 2]; /* the last level's: the step below it */
    return count - 1;
}
