/* meristem — the field of a branch junction: blend, PCM and generalized
 * bounded blending combined as G04 §3.2 does for the branch bark ridge
 * (implicit.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

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
 * surely. */
static void add_reach(merp_jprep *jp, const merp_bound *b)
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
}

/* Lane l of a run's rows (seg or bound) into *r, l's lane in it. */
static merp_row *lane_row(merp_row *rows, uint32_t l, int *lane)
{
    assert(l < MERP_JROWS * MERP_ROW);
    *lane = (int)(l % MERP_ROW);
    return rows + l / MERP_ROW;
}

void merp_jprep_init_run(merp_jprep *jp, const merp_junction *j, uint32_t forks)
{
    assert(forks >= 1 && forks <= MERP_RUN_FORKS);
    uint32_t laterals = 0;
    for (uint32_t i = 0; i < forks; i++) {
        assert(j[i].laterals <= MERP_JUNCTION_LATERALS);
        assert(i + 1 == forks || j[i].out.ra > 0.0f); /* a run goes on to its next fork */
        laterals += j[i].laterals;
    }
    assert(j->in.ra > 0.0f && j->in.rb > 0.0f);
    jp->j = j;
    jp->forks = forks;
    jp->lateral_lane = forks + 1;
    jp->bound_lane = forks;
    jp->rows = (jp->lateral_lane + laterals + MERP_ROW - 1) / MERP_ROW;
    uint32_t brows = (jp->bound_lane + laterals + MERP_ROW - 1) / MERP_ROW;
    jp->rows = brows > jp->rows ? brows : jp->rows;
    jp->reaches = 0;
    for (uint32_t r = 0; r < jp->rows; r++) {
        merp_row_clear(&jp->seg[r]);
        merp_row_clear(&jp->bound[r]);
    }
    int l;
    merp_row *row = lane_row(jp->seg, MERP_JSEG_IN, &l);
    merp_row_set(row, l, j->in.a, j->in.b, j->in.ra, j->in.rb);
    uint32_t sl = jp->lateral_lane, bl = jp->bound_lane;
    for (uint32_t i = 0; i < forks; i++) {
        const merp_junction *f = &j[i];
        if (f->out.ra > 0.0f) {
            row = lane_row(jp->seg, i + 1, &l);
            merp_row_set(row, l, f->out.a, f->out.b, f->out.ra, f->out.rb);
        }
        if (f->scar_weight > 0.0f && f->out.ra > 0.0f) {
            row = lane_row(jp->bound, i, &l);
            merp_row_set(row, l, f->scar.a, f->scar.b, f->scar.r_in, f->scar.r_out);
            add_reach(jp, &f->scar);
        }
        for (uint32_t k = 0; k < f->laterals; k++, sl++, bl++) {
            const merp_seg *s = &f->lateral[k];
            const merp_bound *b = &f->bound[k];
            row = lane_row(jp->seg, sl, &l);
            merp_row_set(row, l, s->a, s->b, s->ra, s->rb);
            if (b->r_out > 1e-5f) { /* merp_junction_ridge's test: a bound of no ridge is 0 */
                row = lane_row(jp->bound, bl, &l);
                merp_row_set(row, l, b->a, b->b, b->r_in, b->r_out);
                add_reach(jp, b);
            }
        }
    }
}

void merp_jprep_init(merp_jprep *jp, const merp_junction *j)
{
    merp_jprep_init_run(jp, j, 1);
}

/* The parent's axis A folded up the run (merp_run's law), with each fork's
 * scar's bounded blend, from the segments' lanes fs and the bounds' Fb, and
 * the scars' terms into *t (F_s·|B1 − B2| of the strongest). */
static float axis_terms(const merp_jprep *jp, const float *fs, const float *Fb, terms *t)
{
    float A = fs[MERP_JSEG_IN];
    t->F_s = t->scar_diff = 0.0f;
    for (uint32_t i = 0; i < jp->forks; i++) {
        const merp_junction *j = &jp->j[i];
        /* A lane left out is 0: f_out without a continuation, F_s without a scar. */
        float f_in = A, f_out = fs[i + 1], m = f_out > f_in ? f_out : f_in;
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

/* B2 = A + Σ L_k (eq. 3) and F_b = max_k F_b,k (merp_junction_ridge). */
static void blend_terms(const merp_jprep *jp, float A, const float *fs, const float *Fb, terms *t)
{
    /* merp_blend_sum of (A, L_0, ...) inline, in its order (from +0): a
     * call and a copy of the terms a sample cost about as much as the sum. */
    float b2 = 0.0f + A, F_b = 0.0f;
    const float *L = fs + jp->lateral_lane, *B = Fb + jp->bound_lane;
    for (uint32_t i = 0, n = 0; i < jp->forks; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++, n++) {
            b2 += L[n];
            F_b = B[n] > F_b ? B[n] : F_b;
        }
    t->b2 = b2;
    t->F_b = F_b;
}

/* B1 = max(A', L_k') of PCM (eq. 2). */
static float pcm_term(const merp_jprep *jp, float A, const float *fs)
{
    const float *L = fs + jp->lateral_lane;
    float A_d = A, b1 = 0.0f;
    for (uint32_t i = 0, n = 0; i < jp->forks; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++, n++)
            A_d += merp_pcm_delta(MERP_ISO - L[n], jp->j[i].w);
    for (uint32_t i = 0, n = 0; i < jp->forks; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++, n++) {
            float L_d = L[n] + merp_pcm_delta(MERP_ISO - A, jp->j[i].w);
            b1 = L_d > b1 ? L_d : b1;
        }
    return A_d > b1 ? A_d : b1;
}

/* Every term at p but B1 into *t, the segments' lanes into fs; returns A. */
static float row_terms(const merp_jprep *jp, const float p[3], float *fs, terms *t)
{
    float Fb[MERP_JROWS * MERP_ROW];
    for (uint32_t r = 0; r < jp->rows; r++)
        merp_row_seg_field(&jp->seg[r], p, fs + MERP_ROW * r);
    merp_jprep_bound_field(jp, p, Fb);
    float A = axis_terms(jp, fs, Fb, t);
    blend_terms(jp, A, fs, Fb, t);
    return A;
}

static void junction_terms(const merp_jprep *jp, const float p[3], terms *t)
{
    float fs[MERP_JROWS * MERP_ROW];
    float A = row_terms(jp, p, fs, t);
    t->b1 = pcm_term(jp, A, fs);
}

float merp_jprep_field(const merp_jprep *jp, const float p[3])
{
    float fs[MERP_JROWS * MERP_ROW];
    terms t;
    float A = row_terms(jp, p, fs, &t);
    /* Beyond the ridge (most samples) F_b = 0 and eq. (4) is B2 exactly
     * (0·B1 + 1·B2, B2 ≥ +0), without B1. */
    if (t.F_b == 0.0f)
        return t.b2;
    return merp_gbb(t.F_b, pcm_term(jp, A, fs), t.b2);
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
    junction_terms(&jp, p, &t);
    *scar = t.F_s * t.scar_diff;
    *ridge = t.F_b * fabsf(t.b1 - t.b2);
}
