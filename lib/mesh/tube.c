/* meristem — bark: every axis as one generalized cylinder framed by parallel
 * transport, with its tip cone or cut disk and a trunk's base disk
 * (meristem/mesh.h, Bark, Caps, UVs). */
#include "config.h"

#include <math.h>

#include "mesh_private.h"
#include "core/vec.h"

/* What emit_ring may do with a ring that repeats the last (repeats_last):
 * nothing, go on from the last where a band holds it, or also take the
 * place of an axis's first ring, which no band holds yet. */
typedef enum merge { MERGE_NONE, MERGE_HELD, MERGE_FIRST } merge;

/* One axis being meshed: its ring layout and the frame carried along it. */
typedef struct tube {
    const merp_axis *a;
    const float *cos_t, *sin_t; /* the ring's angles, a->sides of each */
    uint32_t sides, stride;     /* stride: vertices per ring, with the seam vertex if any */
    uint32_t rings;             /* rings written: a tip ends in a cone, a cut in a ring */
    uint32_t ring0;             /* the first ring's first vertex */
    uint32_t prev_ring;         /* the last ring's first vertex */
    bool prev_joined;           /* whether a band joins the last ring to one below */
    bool prev_plain;            /* whether the last ring is an internode's (not a cut's) */
    float t_prev[3], normal[3]; /* the last ring's tangent and frame normal */
    float v;                    /* arc length / circumference so far (UV v) */
    float last_v, last_at, last_r; /* the last ring's v, its distance along its
                                      internode (a cut's; 0 at a base) and radius */
} tube;

/* Carries the frame normal `normal` from tangent `from` to tangent `to` by the
 * rotation between them: discrete parallel transport, hence no twist. Rodrigues
 * with the rotation's cosine and sine taken straight from dot and cross. */
static void transport(float normal[3], const float from[3], const float to[3])
{
    float k[3];
    v3_cross(from, to, k);
    float s = v3_len(k);
    if (s > 1e-7f) {
        float c = v3_dot(from, to);
        k[0] /= s;
        k[1] /= s;
        k[2] /= s;
        float kxn[3];
        v3_cross(k, normal, kxn);
        float d = v3_dot(k, normal) * (1.0f - c);
        for (int i = 0; i < 3; i++)
            normal[i] = normal[i] * c + kxn[i] * s + k[i] * d;
    }
    // Re-orthogonalize against rounding drift along long axes.
    float d = v3_dot(normal, to);
    for (int i = 0; i < 3; i++)
        normal[i] -= d * to[i];
    if (!v3_normalize(normal))
        v3_any_perp(to, normal);
}

/* The vertex after j on a ring of `stride` vertices: with a seam vertex the ring
 * never wraps (j + 1 ≤ sides < stride); without one, the last joins the first. */
static inline uint32_t next_on_ring(uint32_t j, uint32_t stride)
{
    return j + 1 < stride ? j + 1 : 0;
}

/* The direction of the axis's internode k, or of the nearest one with a
 * length from k on, up (step 1) or down (step -1) the chain; NULL where
 * none has one. An internode of no length (an L-system string that
 * branches twice at one point, a guiding-vector shoot's first hop) has a
 * direction but no extent. */
static const float *axis_dir_from(const merp_builder *b, const merp_axis *a, uint32_t k, int step)
{
    for (uint32_t j = k; j < a->count; j += (uint32_t)step) /* down past 0 wraps past count */
        if (b->nodes[b->chain[j]].length > 0.0f)
            return b->nodes[b->chain[j]].dir;
    return NULL;
}

/* The axis's direction at its base: its first internode with a length's
 * (ring 0's tangent, the base disk's normal reversed). */
static const float *axis_base_dir(const merp_builder *b, const merp_axis *a)
{
    const float *d = axis_dir_from(b, a, 0, 1);
    return d != NULL ? d : b->nodes[b->chain[0]].dir;
}

/* Ring i's centre and tangent (the miter of the internodes it joins), and the
 * UV v advanced over the internode below it. Internodes of no length are
 * passed over for the miter: the rings where they begin and end lie at one
 * point, and with the miter of the nearest internodes with a length either
 * side, all lie in one plane, one ring (emit_ring's repeats_last), where
 * tangents turning at that point tilted them apart and the band of no
 * length between two of them turned inside out on one side (abop-1.24c:
 * four bark vertices whose faces looked inwards). */
static void ring_place(const merp_builder *b, tube *tb, uint32_t i, float center[3], float t[3])
{
    const uint32_t count = tb->a->count;
    if (i == 0) {
        memcpy(center, b->nodes[b->chain[0]].base, 3 * sizeof(float));
        memcpy(t, axis_base_dir(b, tb->a), 3 * sizeof(float));
        return;
    }
    const mer_node *below = &b->nodes[b->chain[i - 1]];
    merp_tip_of(below, center);
    const mer_node *owner = &b->nodes[b->chain[i < count ? i : count - 1]];
    const float *down = axis_dir_from(b, tb->a, i - 1, -1), *up = axis_dir_from(b, tb->a, i < count ? i : count - 1, 1);
    /* one side with no length: the other's direction alone (at an axis's
     * base hop, ring 0's) */
    down = down != NULL ? down : up != NULL ? up : owner->dir;
    up = up != NULL ? up : down;
    for (int k = 0; k < 3; k++)
        t[k] = down[k] + up[k];
    if (!v3_normalize(t))
        memcpy(t, up, 3 * sizeof(float));
    const float *r = b->radii;
    float circumference = MERP_TWO_PI * 0.5f * (r[i - 1] + r[i]);
    tb->v += circumference > 0.0f ? below->length / circumference : 0.0f;
}

/* Vertex j's direction from the axis (`radial`) and position `p` on the
 * ring about `center` of `radius` in the frame (tb->normal, bin). */
static void ring_vertex(const tube *tb, const float center[3], float radius, const float bin[3], uint32_t j,
                        float radial[3], float p[3])
{
    for (int k = 0; k < 3; k++) {
        radial[k] = tb->cos_t[j] * tb->normal[k] + tb->sin_t[j] * bin[k];
        p[k] = center[k] + radius * radial[k];
    }
}

/* Whether the ring about `center` of `radius` in the frame (tb->normal,
 * bin) puts every vertex where the last ring's is, to the rounding of the
 * coordinates (a millionth of their size: a zero-length internode whose
 * tangent turns moves some vertices by an ulp). */
static bool repeats_last(const tube *tb, const mer_mesh_part *part, const float center[3], float radius,
                         const float bin[3])
{
    for (uint32_t j = 0; j < tb->sides; j++) {
        float radial[3], p[3];
        ring_vertex(tb, center, radius, bin, j, radial, p);
        for (int k = 0; k < 3; k++) {
            float q = part->positions[3 * ((size_t)tb->prev_ring + j) + k];
            if (!(fabsf(p[k] - q) <= 1e-6f * (1.0f + fabsf(q))))
                return false;
        }
    }
    return true;
}

/* A ring about `center` in the plane ⊥ t (the frame carried to t), normals
 * tilted by `slope` (the local taper, so a cone shades as a cone), UV v `v`,
 * joined by quads to the last ring when `join`. A cut ring of joint `jt`
 * (mesh.h, Junctions) is recorded there on a dry run and copied from there
 * otherwise, frame and all, with the normal the patch gave its copy, so the
 * two match bit for bit and shade alike.
 *
 * A ring that repeats the last internode's (repeats_last: the rings of an
 * internode of no length, where an L-system string branches twice at one
 * point or a guiding-vector branch begins with a hop of none) is not
 * written, nor the band of no area between them, as `m` allows: the last
 * ring goes on for both (MERGE_HELD), or, where no band holds the last yet
 * (an axis's first ring), this one takes its place (MERGE_FIRST). Counted
 * in the cursor's merged_v and merged_i. */
static void emit_ring(merp_builder *b, tube *tb, const float center[3], const float t[3],
                      float radius, float slope, float v, const mer_node *owner, bool join, merge m,
                      merp_joint *jt, uint32_t cut)
{
    assert(m == MERGE_NONE || jt == NULL);
    merp_cursor *c = &b->bark;
    const uint32_t sides = tb->sides, stride = tb->stride;
    if (jt != NULL && !b->dry) {
        /* The recorded ring's frame, not the one carried here: the dry run
         * had every fork planned, and a fork unplanned since (its patch
         * failed, so its shafts are tubes again) carried the frame along
         * other tangents, to a frame turned from the ring the patch was
         * stitched to. The rings beyond go on from the recorded one. */
        assert(jt->ok && jt->sides[cut] == sides);
        memcpy(tb->normal, jt->frame[cut][0], sizeof tb->normal);
    } else {
        transport(tb->normal, tb->t_prev, t);
    }
    memcpy(tb->t_prev, t, sizeof tb->t_prev);
    float bin[3];
    v3_cross(t, tb->normal, bin);
    // radial ⊥ t and both are unit, so |radial + slope·t| is the same all round.
    const float inv = 1.0f / sqrtf(1.0f + slope * slope);
    if (b->dry) {
        if (jt == NULL)
            return;
        for (uint32_t j = 0; j < sides; j++) {
            float radial[3];
            ring_vertex(tb, center, radius, bin, j, radial, jt->ring[cut] + 3 * j);
        }
        memcpy(jt->frame[cut][0], tb->normal, sizeof tb->normal);
        memcpy(jt->frame[cut][1], bin, sizeof bin);
        jt->v[cut] = v;
        jt->sides[cut] = sides;
        return;
    }
    if (m != MERGE_NONE && join && tb->prev_plain && (tb->prev_joined || m == MERGE_FIRST) &&
        repeats_last(tb, c->part, center, radius, bin)) {
        c->merged_v += stride;
        c->merged_i += 6 * sides;
        if (tb->prev_joined) {
            /* The kept ring is this internode's now (Picking: the band
             * above it is this internode's; the one below it still reads
             * as the internode under the one of no length, by its ring). */
            for (uint32_t j = 0; j < stride; j++)
                c->part->node_ids[tb->prev_ring + j] = owner->id;
            merp_mesh_color(b, c->part, tb->prev_ring, stride, owner);
            return;
        }
        /* The last ring, the axis's first, is the last vertices taken. */
        c->v -= stride;
        c->part->chunks[c->part->chunk_count - 1].vertex_count -= stride;
        join = false;
    }
    const uint32_t first = merp_take_vertices(c, stride);
    mer_mesh_part *part = c->part;
    for (uint32_t j = 0; j < stride; j++) {
        uint32_t jj = j == sides ? 0 : j;
        float radial[3], p[3], nrm[3];
        ring_vertex(tb, center, radius, bin, jj, radial, p);
        for (int k = 0; k < 3; k++)
            nrm[k] = (radial[k] + slope * t[k]) * inv;
        if (jt != NULL) { /* the patch's own copy of this vertex shares it all */
            memcpy(p, jt->ring[cut] + 3 * jj, sizeof p);
            memcpy(nrm, jt->ring_normal[cut] + 3 * jj, sizeof nrm);
        }
        merp_set_vertex(part, first + j, p, nrm, (float)j / (float)sides, v, owner->id);
    }
    merp_mesh_color(b, part, first, stride, owner);
    if (join) {
        uint32_t base, *out = merp_take_indices(c, 6 * sides, &base); /* the band's 2 × sides triangles */
        const uint32_t below = tb->prev_ring - base, here = first - base;
        for (uint32_t j = 0; j < sides; j++, out += 6) {
            uint32_t k = next_on_ring(j, stride);
            out[0] = below + j, out[1] = below + k, out[2] = here + k;
            out[3] = below + j, out[4] = here + k, out[5] = here + j;
        }
    }
    tb->prev_ring = first;
    tb->prev_joined = join;
    tb->prev_plain = jt == NULL;
}

/* Ring i at `center`, square to `t` (ring_place), and the quads joining it
 * to the last ring when `join`. */
static void ring_placed(merp_builder *b, tube *tb, uint32_t i, const float center[3], const float t[3], bool join)
{
    const uint32_t count = tb->a->count;
    const mer_node *owner = &b->nodes[b->chain[i < count ? i : count - 1]];
    const float *r = b->radii;
    uint32_t lo = i > 0 ? i - 1 : 0, hi = i < count ? i + 1 : count;
    float span = 0.0f;
    for (uint32_t k = lo; k < hi; k++)
        span += b->nodes[b->chain[k < count ? k : count - 1]].length;
    float slope = span > 0.0f ? (r[lo] - r[hi]) / span : 0.0f;
    /* A twig's lines run from ring to ring; a disk's rim is vertices of its
     * own, so the ring under it must keep a band. */
    merge m = b->bark.twig ? MERGE_NONE
              : i + 1 == tb->rings && tb->a->end != MERP_END_TIP ? MERGE_HELD
                                                                  : MERGE_FIRST;
    emit_ring(b, tb, center, t, r[i], slope, tb->v, owner, join, m, NULL, 0);
    tb->last_v = tb->v, tb->last_at = 0.0f, tb->last_r = r[i];
}

/* Ring i (ring_place, then ring_placed). */
static void ring(merp_builder *b, tube *tb, uint32_t i, bool join)
{
    float center[3], t[3];
    ring_place(b, tb, i, center, t);
    ring_placed(b, tb, i, center, t, join);
}

/* Where joint jt's cut ring `cut` lies, at its distance along the axis's
 * internode k: its centre, its tangent (square to the patch's shaft there,
 * its cut plane's normal, towards the axis's tip) and radius; *f: how far
 * along the internode. */
static void cut_place(const merp_builder *b, const merp_joint *jt, uint32_t cut, uint32_t k, float center[3],
                      float t[3], float *radius, float *f)
{
    const mer_node *n = &b->nodes[b->chain[k]];
    const float *r = b->radii, s = jt->at[cut];
    *f = n->length > 0.0f ? s / n->length : 0.0f;
    for (int a = 0; a < 3; a++) {
        center[a] = n->base[a] + s * n->dir[a];
        t[a] = cut == MERP_CUT_IN ? -jt->n[cut][a] : jt->n[cut][a];
    }
    *radius = r[k] + (r[k + 1] - r[k]) * *f;
}

/* Joint jt's cut ring `cut` in the axis's internode k (cut_place). */
static void cut_ring(merp_builder *b, tube *tb, merp_joint *jt, uint32_t cut, uint32_t k, bool join)
{
    const mer_node *n = &b->nodes[b->chain[k]];
    const float *r = b->radii, s = jt->at[cut];
    float center[3], t[3], radius, f;
    cut_place(b, jt, cut, k, center, t, &radius, &f);
    float slope = n->length > 0.0f ? (r[k] - r[k + 1]) / n->length : 0.0f;
    float circumference = MERP_TWO_PI * 0.5f * (r[k] + r[k + 1]);
    float v = tb->v + (circumference > 0.0f ? s / circumference : 0.0f);
    emit_ring(b, tb, center, t, radius, slope, v, n, join, MERGE_NONE, jt, cut);
    tb->last_v = v, tb->last_at = s, tb->last_r = radius;
}

/* How far the disk about `c` of radius `r` square to unit `t` lies on the
 * + side of the plane through `o` square to unit `n` (its nearest rim
 * point's signed distance). */
static float disk_clear(const float c[3], const float t[3], float r, const float o[3], const float n[3])
{
    float q[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]}, ct = v3_dot(n, t);
    return v3_dot(n, q) - r * sqrtf(fmaxf(0.0f, 1.0f - ct * ct));
}

/* Whether ring i (centre `center`, tangent `t`) and the band to it from
 * joint jt's cut ring `cut` in internode k (or from it to the cut, when the
 * cut is `after` the ring) would fold: a cut square to a shaft that leans
 * from its internode puts one side of its ring farther along the axis than
 * the other, and where a ring is nearer than that (internodes shorter than
 * their radius: abop-1.24d, seed 1, 14 steps, 6 cuts, and some in the
 * guiding-vector trees, populus-deltoides and fig12b) the band between them
 * turns inside out. Not a fold: each disk wholly on its own side of the
 * other's plane (the tube lies on the + side of a cut's normal jt->n, in or
 * out). */
static bool folds_on_cut(const merp_builder *b, const float center[3], const float t[3], uint32_t i,
                         const merp_joint *jt, uint32_t cut, uint32_t k, bool after)
{
    float o[3], tc[3], rho, f;
    cut_place(b, jt, cut, k, o, tc, &rho, &f);
    float back[3] = {-t[0], -t[1], -t[2]};
    return disk_clear(center, t, b->radii[i], o, jt->n[cut]) <= 0.0f ||
           disk_clear(o, jt->n[cut], rho, center, after ? t : back) <= 0.0f;
}

/* How many internodes before an in cut a ring is checked against it
 * (ring_folds): a cut tilted across internodes shorter than its radius may
 * reach back past more than one ring. */
#define FOLD_LOOK 8u

/* Whether ring i (placed at `center`, `t`) is left out of the tube: where
 * it would fold (folds_on_cut) against the out cut whose ring is the last
 * written (`out_cut`, in internode out_k; UINT32_MAX: none), or against the
 * next in cut within FOLD_LOOK internodes, the band then running from the
 * last ring to the next. Never the axis's first ring or its last (its tip's
 * cone and its end's disk are built on it), so a ring stays before every in
 * cut and at the end. The same in the counting walk and the writing one. */
static bool ring_folds(const merp_builder *b, const tube *tb, uint32_t i, const float center[3], const float t[3],
                       bool any, uint32_t out_cut, uint32_t out_k)
{
    const uint32_t count = tb->a->count;
    if (!any || i + 1 >= tb->rings)
        return false;
    if (out_cut != UINT32_MAX &&
        folds_on_cut(b, center, t, i, &b->joints[out_cut / MERP_PATCH_CUTS], out_cut % MERP_PATCH_CUTS, out_k, false))
        return true;
    for (uint32_t k = i; k < count && k < i + FOLD_LOOK; k++) { /* (no out cut comes first: outside) */
        uint32_t g = b->cut_begin[b->chain[k]];
        if (g != UINT32_MAX)
            return folds_on_cut(b, center, t, i, &b->joints[g], MERP_CUT_IN, k, true);
    }
    return false;
}

/* The rings of an axis with implicit junctions, with `emit` written (or, on
 * a dry run, recorded), else only counted into *rings and *bands: ring i
 * at the base of internode i unless it lies inside a patch or would fold
 * against a cut (ring_folds), and in
 * internode i the cut that ends a patch (a lateral's or a relay's first,
 * the out cut of a fork below, or at a relayed fork the cut of the thinner
 * continuation, one of its laterals) and then the cut that begins one (the
 * in cut of a fork at or above its tip). A patch's span may cover several internodes.
 * Returns whether the axis ends inside a patch (a relayed fork at its tip). */
static bool rings_with_joints(merp_builder *b, tube *tb, bool emit, uint32_t *rings, uint32_t *bands)
{
    const uint32_t count = tb->a->count;
    bool inside = b->lateral_in[b->chain[0]] != UINT32_MAX, any = false;
    uint32_t out_cut = UINT32_MAX, out_k = 0; /* the last ring's, when it is an out cut's */
    *rings = *bands = 0;
    for (uint32_t i = 0; i < tb->rings; i++) {
        if (!inside) {
            float center[3], t[3];
            ring_place(b, tb, i, center, t); /* carries v to ring i, written or not */
            if (!ring_folds(b, tb, i, center, t, any, out_cut, out_k)) {
                if (emit)
                    ring_placed(b, tb, i, center, t, any);
                *bands += any;
                ++*rings, any = true, out_cut = UINT32_MAX;
            }
        } else if (emit) {
            float center[3], t[3];
            ring_place(b, tb, i, center, t); /* only to carry v to ring i */
        }
        if (i >= count)
            break;
        uint32_t id = b->chain[i], e = b->cut_end[id], g = b->cut_begin[id];
        if (e != UINT32_MAX) {
            assert(inside);
            if (emit)
                cut_ring(b, tb, &b->joints[e / MERP_PATCH_CUTS], e % MERP_PATCH_CUTS, i, false);
            ++*rings, any = true, inside = false;
            out_cut = e, out_k = i;
        }
        if (g != UINT32_MAX) {
            assert(!inside && any);
            if (emit)
                cut_ring(b, tb, &b->joints[g], MERP_CUT_IN, i, true);
            ++*rings, ++*bands, inside = true;
            out_cut = UINT32_MAX;
        }
    }
    return inside;
}

/* With implicit junctions, a disk's centre lies this × its radius inside
 * the tube (against its normal). The bark is then a closed 2-manifold
 * where two disks meet at one point: two laterals' base disks at a fork
 * left as tubes, or one of them and the parent's end disk there, in a
 * plane whose rings both hold the point above and below the plane (a
 * ring's frame starts level), would otherwise share the spokes to those
 * points, an edge of four triangles (abop-2.8a, seed 1, 14 steps: 22 such
 * directed edges). A 1/32 dimple shows nowhere, and the trunk's base stays
 * on the ground. Without junctions the bark is not closed (laterals have
 * no base disk), and its disks stay flat. */
#define DISK_DIMPLE (1.0f / 32.0f)

/* A disk over the ring at `ring_at`: a centre vertex at `at` (dimpled by
 * DISK_DIMPLE with implicit junctions) and a rim of its own, all with
 * normal `nrm` (the disk's own, so the edge stays sharp); `v_sign` -1
 * mirrors the UVs' v and `reverse` the winding, for a disk seen from
 * below. */
static void disk(merp_builder *b, const tube *tb, uint32_t ring_at, const float at[3],
                 const float nrm[3], float v_sign, bool reverse, const mer_node *owner)
{
    merp_cursor *c = &b->bark;
    const uint32_t sides = tb->sides;
    float centre[3] = {at[0], at[1], at[2]};
    if (b->opt.junctions == MER_JUNCTIONS_IMPLICIT) {
        const float *rim0 = c->part->positions + 3 * (size_t)ring_at;
        float r[3] = {rim0[0] - at[0], rim0[1] - at[1], rim0[2] - at[2]};
        float depth = DISK_DIMPLE * sqrtf(v3_dot(r, r));
        for (int k = 0; k < 3; k++)
            centre[k] -= depth * nrm[k];
    }
    uint32_t center_id = merp_put_vertex(c, centre, nrm, 0.5f, 0.5f, owner);
    uint32_t rim = c->v;
    for (uint32_t j = 0; j < sides; j++) {
        float p[3];
        memcpy(p, c->part->positions + 3 * (ring_at + j), sizeof p);
        merp_put_vertex(c, p, nrm, 0.5f + 0.5f * tb->cos_t[j], 0.5f + v_sign * 0.5f * tb->sin_t[j],
                        owner);
    }
    merp_mesh_color(b, c->part, center_id, sides + 1, owner);
    for (uint32_t j = 0; j < sides; j++) {
        if (reverse)
            merp_put_triangle(c, center_id, rim + (j + 1) % sides, rim + j);
        else
            merp_put_triangle(c, center_id, rim + j, rim + (j + 1) % sides);
    }
}

/* A living tip's cone to its end point, or a cut's disk; nothing where the
 * axis ends inside a patch. */
static void tip(merp_builder *b, tube *tb)
{
    merp_cursor *c = &b->bark;
    const merp_axis *a = tb->a;
    const mer_node *last = &b->nodes[b->chain[a->count - 1]];
    const uint32_t top_ring = tb->prev_ring;
    float end[3];
    merp_tip_of(last, end);
    if (a->ends_in)
        return; /* the patch it ends in covers its tip */
    if (a->end != MERP_END_TIP) {
        disk(b, tb, top_ring, end, tb->t_prev, 1.0f, false, last);
        return;
    }
    /* The cone from the last ring (its base, or a patch's cut in it) to the
     * apex: v runs on by its length over its mean circumference, π r. */
    float circumference = MERP_TWO_PI * 0.5f * tb->last_r;
    tb->v = tb->last_v + (circumference > 0.0f ? (last->length - tb->last_at) / circumference : 0.0f);
    uint32_t apex = merp_put_vertex(c, end, last->dir, 0.5f, tb->v, last);
    merp_mesh_color(b, c->part, apex, 1, last);
    for (uint32_t j = 0; j < tb->sides; j++)
        merp_put_triangle(c, top_ring + j, top_ring + next_on_ring(j, tb->stride), apex);
    if (c->twig)
        merp_put_line(c, top_ring, apex);
}

/* The tube of axis a before its first ring: the chain, the ring layout and
 * a deterministic start frame (horizontal where it can be). */
static void tube_start(merp_builder *b, const merp_axis *a, const float *cos_t, const float *sin_t,
                       tube *tb)
{
    const bool seam = !b->opt.no_uvs; // a ring repeats its first vertex at u = 1 for the UV seam
    *tb = (tube){.a = a, .cos_t = cos_t, .sin_t = sin_t, .sides = a->sides,
                 .stride = seam ? a->sides + 1 : a->sides,
                 .rings = a->end == MERP_END_TIP ? a->count : a->count + 1, .ring0 = b->bark.v};
    memcpy(tb->t_prev, axis_base_dir(b, a), sizeof tb->t_prev);
    const float up[3] = {0.0f, 1.0f, 0.0f};
    v3_cross(up, tb->t_prev, tb->normal);
    if (!v3_normalize(tb->normal))
        v3_any_perp(tb->t_prev, tb->normal);
}

static mer_result mesh_axis(merp_builder *b, const merp_axis *a, const float *cos_t,
                            const float *sin_t, mer_error *err)
{
    assert(a->count >= 1 && a->sides >= 3 && a->sides <= MERP_MAX_SIDES);
    mer_result rc = merp_mesh_chain(b, a, err);
    if (rc == MER_OK)
        rc = merp_mesh_begin_group(&b->bark, (uint32_t)merp_axis_vertices(a, !b->opt.no_uvs), err);
    if (rc != MER_OK)
        return rc;
    merp_cursor *c = &b->bark;
    tube tb;
    tube_start(b, a, cos_t, sin_t, &tb);
    const mer_node *first = &b->nodes[b->chain[0]];
    uint32_t rings, bands;
    if (b->joints != NULL) {
        bool ends_in = rings_with_joints(b, &tb, true, &rings, &bands);
        assert(ends_in == (bool)a->ends_in); /* as the counting walk found */
        (void)ends_in;
    }
    else
        for (uint32_t i = 0; i < tb.rings; i++)
            ring(b, &tb, i, i > 0);
    // A twig's line runs along its prism's first edge: at under a pixel wide, the
    // edge and the centre line are the same pixels (a twig is in no patch).
    if (c->twig)
        for (uint32_t i = 0; i + 1 < tb.rings; i++)
            merp_put_line(c, tb.ring0 + i * tb.stride, tb.ring0 + (i + 1) * tb.stride);
    tip(b, &tb);
    if (a->base_cap) {
        // Seen from below the ring runs clockwise: the disk reverses it to face outwards.
        const float *d = axis_base_dir(b, a);
        const float down[3] = {-d[0], -d[1], -d[2]};
        disk(b, &tb, tb.ring0, first->base, down, -1.0f, true, first);
    }
    return MER_OK;
}

static void angle_table(uint32_t sides, float *cos_t, float *sin_t)
{
    for (uint32_t j = 0; j < sides; j++) {
        float angle = MERP_TWO_PI * (float)j / (float)sides;
        cos_t[j] = cosf(angle);
        sin_t[j] = sinf(angle);
    }
}

mer_result merp_mesh_record_rings(merp_builder *b, merp_axis *a, bool record, mer_error *err)
{
    float cos_t[MERP_MAX_SIDES], sin_t[MERP_MAX_SIDES];
    mer_result rc = merp_mesh_chain(b, a, err);
    if (rc != MER_OK)
        return rc;
    angle_table(a->sides, cos_t, sin_t);
    tube tb;
    uint32_t rings, bands;
    b->dry = true;
    tube_start(b, a, cos_t, sin_t, &tb);
    a->ends_in = rings_with_joints(b, &tb, record, &rings, &bands);
    b->dry = false;
    a->extra_rings = (int32_t)rings - (int32_t)tb.rings;
    a->lost_bands = (int32_t)tb.rings - 1 - (int32_t)bands;
    return MER_OK;
}

mer_result merp_mesh_bark(merp_builder *b, mer_error *err)
{
    float cos_t[MERP_MAX_SIDES], sin_t[MERP_MAX_SIDES];
    uint32_t table_sides = 0;
    // With twig lines, thicker axes first, then the twigs in chunks of their own.
    const uint32_t passes = b->opt.twig_lines ? 2 : 1;
    for (uint32_t pass = 0; pass < passes; pass++) {
        b->bark.twig = pass == 1;
        for (uint32_t i = 0; i < b->axis_count; i++) {
            const merp_axis *a = &b->axes[i];
            if (passes == 2 && merp_mesh_is_twig(b, a) != (pass == 1))
                continue;
            if (a->sides != table_sides) {
                angle_table(a->sides, cos_t, sin_t);
                table_sides = a->sides;
            }
            mer_result rc = mesh_axis(b, a, cos_t, sin_t, err);
            if (rc != MER_OK)
                return rc;
        }
        // The junctions' patches after the thicker axes, never in twig chunks.
        mer_result rc = pass == 0 && b->joints != NULL ? merp_mesh_joints_write(b, err) : MER_OK;
        if (rc != MER_OK)
            return rc;
    }
    return MER_OK;
}
