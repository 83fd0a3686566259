/* meristem — the field of a branch junction: blend, PCM and generalized
 * bounded blending combined as G04 §3.2 does for the branch bark ridge
 * (implicit.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

/* Every term's function forced inline into field_with, so that with a
 * single fork's constant lanes the compiler folds the lookups away. */
#if defined(__GNUC__)
#define INLINE __attribute__((always_inline)) inline
#else
#define INLINE inline
#endif

/* Lateral k's crotch bound (see merp_junction_bound) into *b. */
static void crotch_bound(const merp_junction *j, uint32_t k, const float up[3], float ridge, merp_bound *b)
{
    const merp_seg *l = &j->lateral[k];
    float d[3], e[3];
    for (int a = 0; a < 3; a++)
        d[a] = l->b[a] - l->a[a];
    v3_normalize(d);
    /* e: the side the lateral leaves towards, across the parent's axis. */
    float cos_t = v3_dot(d, up);
    for (int a = 0; a < 3; a++)
        e[a] = d[a] - cos_t * up[a];
    if (!v3_normalize(e))
        v3_any_perp(up, e);
    /* The crotch C, in the plane (e, up): where the parent's surface x = r_P
     * meets the lateral's upper line J + t·d + r_L·n, n = (−cos θ, sin θ):
     * t = (r_P + r_L cos θ) / sin θ, θ ≥ 10° (a lateral along its parent has
     * no crotch to speak of). */
    float sin_t = sqrtf(fmaxf(0.0f, 1.0f - cos_t * cos_t));
    cos_t = fminf(cos_t, 0.985f), sin_t = fmaxf(sin_t, 0.17f);
    float r_P = j->in.rb, r_L = l->ra, t = (r_P + r_L * cos_t) / sin_t;
    float x = t * sin_t - r_L * cos_t, y = t * cos_t + r_L * sin_t;
    float g = ridge < 0.0f ? 0.0f : ridge > 1.0f ? 1.0f : ridge;
    for (int a = 0; a < 3; a++) {
        b->a[a] = l->a[a] + x * e[a] + y * up[a];
        b->b[a] = b->a[a] + 0.5f * r_L * g * d[a];
    }
    b->r_in = 0.4f * r_L * g;
    b->r_out = b->r_in + 0.8f * r_L * g + 1e-6f;
}

void merp_junction_bound(merp_junction *j, uint32_t k, const float up[3], float ridge)
{
    assert(k < j->laterals);
    crotch_bound(j, k, up, ridge, &j->bound[k]);
}

/* The bark's time law (merp_junction_age): a scar's visible weight after y
 * years, e^(−(y − 1)/τ) with τ = 3 years. */
#define AGE_TAU 3.0f

float merp_junction_scar_weight(float years)
{
    return years <= 1.0f ? 1.0f : expf(-(years - 1.0f) / AGE_TAU);
}

/* Lateral k's scar ring: the stretch of its axis where it meets the parent's
 * surface, from below (t = (r_P − r_L cos θ) / sin θ) to the crotch above (t
 * = (r_P + r_L cos θ) / sin θ), with F_b = 1 a little beyond its radius, so
 * the whole contact curve is a crease. */
static void ring_bound(const merp_junction *j, uint32_t k, const float up[3], merp_bound *b)
{
    const merp_seg *l = &j->lateral[k];
    float d[3];
    for (int a = 0; a < 3; a++)
        d[a] = l->b[a] - l->a[a];
    float len = v3_len(d);
    v3_normalize(d);
    float cos_t = fminf(v3_dot(d, up), 0.985f), sin_t = sqrtf(1.0f - cos_t * cos_t);
    float r_P = j->in.rb, r_L = l->ra;
    float t0 = fmaxf(0.0f, (r_P - r_L * cos_t) / sin_t), t1 = fminf(len, (r_P + r_L * cos_t) / sin_t);
    for (int a = 0; a < 3; a++) {
        b->a[a] = l->a[a] + t0 * d[a];
        b->b[a] = l->a[a] + fmaxf(t0, t1) * d[a];
    }
    b->r_in = 1.15f * r_L;
    b->r_out = b->r_in + 0.8f * r_L;
}

/* The parent's scar band holds F_b = 1 out to this × its radius: the
 * surface there lies up to ~1.35 × the pipe radius (bulge and blend). */
#define SCAR_R_IN 1.5f

void merp_junction_age(merp_junction *j, const float up[3], float years)
{
    assert(j->laterals <= MERP_JUNCTION_LATERALS);
    float sigma = merp_junction_scar_weight(years), m = 1.0f - sigma;
    /* The parent's scar: a band about its axis at J, 0.6 r_P either side.
     * F_b = 1 must hold on the surface all round, which the scar's own
     * bulge, the laterals' blend and the parent's taper push out from the
     * pipe radius at J: so out to SCAR_R_IN times the parent's thickest
     * radius within the band. */
    float ax[3];
    for (int a = 0; a < 3; a++)
        ax[a] = j->in.b[a] - j->in.a[a];
    float len = v3_len(ax);
    if (!v3_normalize(ax))
        memcpy(ax, up, sizeof ax);
    float r_P = j->in.rb, t = len > 0.0f ? fminf(1.0f, 0.6f * r_P / len) : 0.0f;
    float r_band = fmaxf(r_P, j->in.rb + t * (j->in.ra - j->in.rb));
    if (j->out.ra > 0.0f)
        r_band = fmaxf(r_band, j->out.ra);
    for (int a = 0; a < 3; a++) {
        j->scar.a[a] = j->in.b[a] - 0.6f * r_P * ax[a];
        j->scar.b[a] = j->in.b[a] + 0.6f * r_P * ax[a];
    }
    j->scar.r_in = SCAR_R_IN * r_band;
    j->scar.r_out = j->scar.r_in + 0.9f * r_band;
    j->scar_weight = j->out.ra > 0.0f ? sigma : 0.0f;
    /* Each lateral's ring turns into its crotch's ridge. */
    for (uint32_t k = 0; k < j->laterals; k++) {
        merp_bound ring, ridge;
        ring_bound(j, k, up, &ring);
        crotch_bound(j, k, up, 1.0f, &ridge);
        merp_bound *b = &j->bound[k];
        for (int a = 0; a < 3; a++) {
            b->a[a] = ring.a[a] + m * (ridge.a[a] - ring.a[a]);
            b->b[a] = ring.b[a] + m * (ridge.b[a] - ring.b[a]);
        }
        b->r_in = ring.r_in + m * (ridge.r_in - ring.r_in);
        b->r_out = ring.r_out + m * (ridge.r_out - ring.r_out);
    }
}

float merp_junction_ridge(const merp_junction *j, const float p[3])
{
    float F_b = 0.0f;
    for (uint32_t k = 0; k < j->laterals; k++) {
        if (j->bound[k].r_out <= 1e-5f)
            continue;
        float v = merp_bound_field(&j->bound[k], p);
        F_b = v > F_b ? v : F_b;
    }
    return F_b;
}

/* The parts of F_g at p: the parent's axis A (with its scar), the
 * laterals' PCM union b1 and blend b2, and the weights of the two bounded
 * blends with the differences they weigh. */
typedef struct terms {
    float F_s, scar_diff; /* the parent's scar: F_s and |B1 − B2| of in, out */
    float F_b, b1, b2;
} terms;

/* PCM's bulge width for the scar between a year's shoot and the last: the
 * widest (MERP_ISO), so the ring shows. */
#define SCAR_W MERP_ISO

/* A ball holding bound b's support (within r_out of its segment): about
 * the segment's midpoint, of radius half its length plus r_out, grown by
 * 1e-3 of itself and 1e-4 of the coordinates' magnitude, far above the
 * rounding of a lane's d², so that outside it the lane's d² ≥ r_out²
 * surely; and the box of lane's row grown to hold the ball (its float
 * bounds' rounding is far below that margin too). */
static void add_reach(merp_jprep *jp, uint32_t lane, const merp_bound *b)
{
    float *r = jp->reach[jp->reaches++], half[3], size = 0.0f;
    for (int a = 0; a < 3; a++) {
        r[a] = 0.5f * (b->a[a] + b->b[a]);
        half[a] = 0.5f * (b->b[a] - b->a[a]);
        size += fabsf(r[a]);
    }
    float rho = v3_len(half) + b->r_out;
    rho += 1e-3f * rho + 1e-4f * size;
    r[3] = rho * rho;
    float (*box)[3] = jp->bound_box[lane / MERP_ROW];
    for (int a = 0; a < 3; a++) {
        box[0][a] = fminf(box[0][a], r[a] - rho);
        box[1][a] = fmaxf(box[1][a], r[a] + rho);
    }
}

/* Lane l of a run's rows (seg or bound) into *r, l's lane in it. */
static merp_row *lane_row(merp_row *rows, uint32_t l, int *lane)
{
    assert(l < MERP_JROWS * MERP_ROW);
    *lane = (int)(l % MERP_ROW);
    return rows + l / MERP_ROW;
}

/* jp's lane tables for the run of `forks` at j with `link` (see
 * merp_jprep_init_run); returns the lanes of seg and of bound it uses. */
static void lay_out(merp_jprep *jp, const merp_junction *j, const merp_link *link, uint32_t forks, uint32_t *lanes,
                    uint32_t *blanes)
{
    merp_jlanes *L = &jp->lanes;
    uint32_t lane = 1, blane = forks;
    L->groups = 0;
    L->in_lane[0] = 0;
    for (uint32_t i = 0; i < forks; i++) {
        merp_link l = link != NULL ? link[i] : (merp_link){(uint8_t)(i - 1), MERP_LINK_OUT};
        if (i == 0 || l.slot != MERP_LINK_OUT)
            L->group_first[L->groups++] = (uint8_t)i;
        if (i > 0) {
            assert(l.from < i && (l.slot != MERP_LINK_OUT || l.from == i - 1));
            assert(l.slot == MERP_LINK_OUT || l.slot < j[l.from].laterals);
            if (l.slot == MERP_LINK_OUT) {
                L->in_lane[i] = L->out_lane[l.from];
            } else {
                L->in_lane[i] = L->lat_lane[l.from][l.slot];
                L->child[l.from][l.slot] = (uint8_t)(L->groups - 1);
            }
        }
        L->out_lane[i] = (uint8_t)lane++;
        for (uint32_t k = 0; k < j[i].laterals; k++) {
            L->lat_lane[i][k] = (uint8_t)lane++;
            L->bnd_lane[i][k] = (uint8_t)blane++;
            L->child[i][k] = 0;
        }
    }
    L->group_first[L->groups] = (uint8_t)forks;
    *lanes = lane, *blanes = blane;
}

/* Grows the box of the row of lane l to hold segment g's support: its
 * ends' box grown by its largest R = r / x_c, with a margin (as add_reach's)
 * far above the rounding of a lane's d², so that beyond the box the lane's
 * x² ≥ 1 surely. */
static void box_segment(merp_jprep *jp, uint32_t l, const merp_seg *g)
{
    float (*b)[3] = jp->seg_box[l / MERP_ROW], R = fmaxf(g->ra, g->rb) / MERP_SEG_XC, size = 0.0f;
    for (int k = 0; k < 3; k++)
        size += fabsf(g->a[k]) + fabsf(g->b[k]);
    R += 1e-3f * R + 1e-4f * size;
    for (int k = 0; k < 3; k++) {
        b[0][k] = fminf(b[0][k], fminf(g->a[k], g->b[k]) - R);
        b[1][k] = fmaxf(b[1][k], fmaxf(g->a[k], g->b[k]) + R);
    }
}

void merp_jprep_init_run(merp_jprep *jp, const merp_junction *j, const merp_link *link, uint32_t forks)
{
    assert(forks >= 1 && forks <= MERP_RUN_FORKS);
    for (uint32_t i = 0; i < forks; i++)
        assert(j[i].laterals <= MERP_JUNCTION_LATERALS);
    assert(j->in.ra > 0.0f && j->in.rb > 0.0f);
    jp->j = j;
    jp->forks = forks;
    uint32_t lanes, blanes;
    lay_out(jp, j, link, forks, &lanes, &blanes);
    jp->rows = ((lanes > blanes ? lanes : blanes) + MERP_ROW - 1) / MERP_ROW;
    for (uint32_t k = 0; forks == 1 && k < j->laterals; k++) /* the lanes the fast path takes as constants */
        assert(jp->lanes.lat_lane[0][k] == MERP_JLANES_SINGLE.lat_lane[0][k] &&
               jp->lanes.bnd_lane[0][k] == MERP_JLANES_SINGLE.bnd_lane[0][k] && jp->lanes.child[0][k] == 0);
    assert(forks > 1 || (jp->lanes.in_lane[0] == MERP_JSEG_IN && jp->lanes.out_lane[0] == MERP_JSEG_OUT &&
                         jp->lanes.groups == 1));
    jp->reaches = 0;
    for (uint32_t r = 0; r < jp->rows; r++) {
        merp_row_clear(&jp->seg[r]);
        merp_row_clear(&jp->bound[r]);
    }
    for (uint32_t r = 0; r < jp->rows; r++)
        for (int k = 0; k < 3; k++)
            jp->seg_box[r][0][k] = jp->bound_box[r][0][k] = INFINITY,
            jp->seg_box[r][1][k] = jp->bound_box[r][1][k] = -INFINITY;
    const merp_jlanes *L = &jp->lanes;
    int l;
    merp_row *row = lane_row(jp->seg, 0, &l);
    merp_row_set(row, l, j->in.a, j->in.b, j->in.ra, j->in.rb);
    box_segment(jp, 0, &j->in);
    for (uint32_t i = 0; i < forks; i++) {
        const merp_junction *f = &j[i];
        if (f->out.ra > 0.0f) {
            row = lane_row(jp->seg, L->out_lane[i], &l);
            merp_row_set(row, l, f->out.a, f->out.b, f->out.ra, f->out.rb);
            box_segment(jp, L->out_lane[i], &f->out);
        }
        if (f->scar_weight > 0.0f && f->out.ra > 0.0f) {
            row = lane_row(jp->bound, i, &l);
            merp_row_set(row, l, f->scar.a, f->scar.b, f->scar.r_in, f->scar.r_out);
            add_reach(jp, i, &f->scar);
        }
        for (uint32_t k = 0; k < f->laterals; k++) {
            const merp_seg *s = &f->lateral[k];
            const merp_bound *b = &f->bound[k];
            row = lane_row(jp->seg, L->lat_lane[i][k], &l);
            merp_row_set(row, l, s->a, s->b, s->ra, s->rb);
            box_segment(jp, L->lat_lane[i][k], s);
            if (b->r_out > 1e-5f) { /* merp_junction_ridge's test: a bound of no ridge is 0 */
                row = lane_row(jp->bound, L->bnd_lane[i][k], &l);
                merp_row_set(row, l, b->a, b->b, b->r_in, b->r_out);
                add_reach(jp, L->bnd_lane[i][k], b);
            }
        }
    }
}

void merp_jprep_init(merp_jprep *jp, const merp_junction *j)
{
    merp_jprep_init_run(jp, j, NULL, 1);
}

/* Group g's axis A folded up its forks (merp_link's law), with each fork's
 * scar's bounded blend, from the segments' lanes fs and the bounds' Fb,
 * and the scars' terms into *t (F_s·|B1 − B2| of the strongest). */
static INLINE float axis_terms(const merp_jprep *jp, const merp_jlanes *L, uint32_t g, const float *fs,
                               const float *Fb, terms *t)
{
    uint32_t first = L->group_first[g], end = L->group_first[g + 1];
    float A = fs[L->in_lane[first]];
    t->F_s = t->scar_diff = 0.0f;
    for (uint32_t i = first; i < end; i++) {
        const merp_junction *j = &jp->j[i];
        /* A lane left out is 0: f_out without a continuation, F_s without a scar. */
        float f_in = A, f_out = fs[L->out_lane[i]], m = f_out > f_in ? f_out : f_in;
        if (j->scar_weight > 0.0f && j->out.ra > 0.0f) {
            float F_s = j->scar_weight * Fb[i];
            if (F_s > 0.0f) {
                float a1 = merp_pcm_union(f_in, f_out, SCAR_W), diff = fabsf(a1 - m);
                if (F_s * diff >= t->F_s * t->scar_diff)
                    t->F_s = F_s, t->scar_diff = diff;
                m = merp_gbb(F_s, a1, m);
            }
        }
        A = m;
    }
    return A;
}

/* Lateral k of fork i at p: its segment's lane, or the field of the group
 * that goes on up it (Fg). */
static INLINE float lateral_of(const merp_jlanes *L, uint32_t i, uint32_t k, const float *fs, const float *Fg)
{
    uint32_t c = L->child[i][k];
    return c != 0 ? Fg[c] : fs[L->lat_lane[i][k]];
}

/* Group g's field at p (its terms into *t) from the lanes and the fields
 * of the groups after it: B2 = A + Σ L_k (eq. 3), F_b = max_k F_b,k
 * (merp_junction_ridge), B1 = max(A', L_k') (PCM, eq. 2) where F_b > 0, and
 * eq. (4). Beyond the ridge (most samples) F_b = 0 and eq. (4) is B2
 * exactly (0·B1 + 1·B2, B2 ≥ +0), without B1 (t->b1 is then B2). */
static INLINE float group_field(const merp_jprep *jp, const merp_jlanes *L, uint32_t g, const float *fs,
                                const float *Fb, const float *Fg, terms *t)
{
    uint32_t first = L->group_first[g], end = L->group_first[g + 1];
    float A = axis_terms(jp, L, g, fs, Fb, t);
    /* merp_blend_sum of (A, L_0, ...) inline, in its order (from +0): a
     * call and a copy of the terms a sample cost about as much as the sum. */
    float b2 = 0.0f + A, F_b = 0.0f;
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++) {
            b2 += lateral_of(L, i, k, fs, Fg);
            float v = Fb[L->bnd_lane[i][k]];
            F_b = v > F_b ? v : F_b;
        }
    t->b2 = t->b1 = b2;
    t->F_b = F_b;
    if (F_b == 0.0f)
        return b2;
    float A_d = A, b1 = 0.0f;
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++)
            A_d += merp_pcm_delta(MERP_ISO - lateral_of(L, i, k, fs, Fg), jp->j[i].w);
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++) {
            float L_d = lateral_of(L, i, k, fs, Fg) + merp_pcm_delta(MERP_ISO - A, jp->j[i].w);
            b1 = L_d > b1 ? L_d : b1;
        }
    t->b1 = A_d > b1 ? A_d : b1;
    return merp_gbb(F_b, t->b1, b2);
}

/* The run's field at p, the first group's terms into *t, with its lanes
 * where L says (jp's own, or SINGLE's). */
static INLINE float field_with(const merp_jprep *jp, const merp_jlanes *L, const float p[3], terms *t)
{
    /* Fg zeroed for the compiler: each group's is written before it is read. */
    float fs[MERP_JROWS * MERP_ROW], Fb[MERP_JROWS * MERP_ROW], Fg[MERP_RUN_FORKS] = {0};
    for (uint32_t r = 0; r < jp->rows; r++) {
        if (merp_jprep_beyond_row(jp, r, p))
            memset(fs + MERP_ROW * r, 0, MERP_ROW * sizeof *fs); /* +0, as the lanes give */
        else
            merp_row_seg_field(&jp->seg[r], p, fs + MERP_ROW * r);
    }
    merp_jprep_bound_field(jp, p, Fb);
    for (uint32_t g = L->groups; g-- > 1;) {
        terms u;
        Fg[g] = group_field(jp, L, g, fs, Fb, Fg, &u);
    }
    return group_field(jp, L, 0, fs, Fb, Fg, t);
}

static float run_field(const merp_jprep *jp, const float p[3], terms *t)
{
    /* A single fork's lanes as constants: the compiler folds their lookups
     * (and the groups' and forks' loops) away on the path most samples take. */
    if (jp->forks == 1)
        return field_with(jp, &MERP_JLANES_SINGLE, p, t);
    return field_with(jp, &jp->lanes, p, t);
}

float merp_jprep_field(const merp_jprep *jp, const float p[3])
{
    terms t;
    return run_field(jp, p, &t);
}

float merp_junction_field(const float p[3], const void *data)
{
    merp_jprep jp;
    merp_jprep_init(&jp, data);
    return merp_jprep_field(&jp, p);
}

void merp_junction_strength(const merp_junction *j, const float p[3], float *scar, float *ridge)
{
    merp_jprep jp;
    merp_jprep_init(&jp, j);
    terms t;
    run_field(&jp, p, &t);
    *scar = t.F_s * t.scar_diff;
    *ridge = t.F_b * fabsf(t.b1 - t.b2);
}
