/* meristem — implicit junctions in the bark (meristem/mesh.h, Junctions; G04
 * §3, issue 18): which forks get a patch and where their shafts are cut,
 * each shaft across as many short internodes as its cut needs; the field
 * each patch polygonizes (joints.c builds and writes the patches). */
#include "config.h"

#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "mesh_private.h"

#define JUNCTION_DIAMETER_FRACTION 0.2f /* junction_diameter 0: this × the thickest */
#define LATERAL_RATIO 0.25f  /* a lateral in a patch: at least this × its parent's diameter */
#define SUPPORT_SEEN 0.8f    /* another primitive's field counts within this × its support */
#define MAX_SPAN 64u         /* a patch's shaft crosses at most this many internodes */
#define CUT_GAP 0.1f         /* two patches' cuts in one internode: this × its radius apart */
#define STRAIGHT 0.5f        /* a shaft's axis stays within this × its radius of one line ... */
#define STRAIGHT_COS 0.9f    /* ... and its cut's internode within 25° of it */
#define EXTEND 3.0f          /* a shaft's segment reaches this many cells past its cut */
#define REPLANS 4u           /* a fork's cuts are placed at most this many times (plan_one) */
#define PCM_WIDTH 0.15f      /* w of PCM's bulge, in field units */
#define CELLS_PER_RADIUS 3.0f /* a patch's grid: cells per parent radius ... */
#define CELLS_PER_LATERAL_RADIUS 1.25f /* ... and at least per lateral radius */
#define THIN_CUT 0.4f        /* a cut ring at least this many cells in radius */

/* Whether internode id (living) is a living tip's last, which tube.c
 * meshes as a cone. */
static bool tip_cone(const merp_builder *b, uint32_t id)
{
    const mer_node *n = &b->nodes[id];
    bool child = n->main_child != MER_NO_NODE && b->nodes[n->main_child].alive;
    return !child && n->terminal_bud != MER_BUD_NONE;
}

/* Whether a shaft may cross or be cut in internode id: a living one, and
 * no tip's cone unless `cone` (a shaft may end in a cone, the tube then
 * running from the cut ring to the apex; and a relayed fork's parent may be
 * one, its tip inside the patch). */
static bool usable(const merp_builder *b, uint32_t id, bool cone)
{
    if (id == MER_NO_NODE || id >= b->node_count || !b->nodes[id].alive || b->nodes[id].length <= 0.0f)
        return false;
    return cone || !tip_cone(b, id);
}

static void segment_of(const merp_builder *b, uint32_t id, merp_seg *s)
{
    const mer_node *n = &b->nodes[id];
    memcpy(s->a, n->base, sizeof s->a);
    merp_tip_of(n, s->b);
    s->ra = merp_node_radius(b, id);
    s->rb = merp_node_end_radius(b, id);
}

/* A patch's grid spacing: a few cells across the parent, about one across
 * its thinnest lateral's radius (enough for marching tetrahedra to keep the
 * tube, and the patch's cost). */
float merp_joint_cell(const merp_builder *b, const merp_joint *jt)
{
    float h = merp_node_radius(b, jt->start[MERP_CUT_IN]) / CELLS_PER_RADIUS;
    for (uint32_t s = jt->relay ? MERP_CUT_OUT : MERP_CUT_LATERAL; s < jt->cuts; s++) /* a relay is a lateral */
        h = fminf(h, merp_node_radius(b, jt->start[s]) / CELLS_PER_LATERAL_RADIUS);
    return h;
}

static int axis_cmp(const void *key, const void *elem)
{
    uint32_t id = *(const uint32_t *)key, first = ((const merp_axis *)elem)->first;
    return id < first ? -1 : id > first;
}

static const merp_axis *axis_from(const merp_builder *b, uint32_t first)
{
    return bsearch(&first, b->axes, b->axis_count, sizeof *b->axes, axis_cmp);
}

/* How far along n from J a cut of a shaft of radius r (reach ρ) must lie to
 * be clear of a primitive leaving J along m with support R: the disk at d
 * is at least d·sin φ − ρ from that primitive's axis (φ between n and m), or
 * d when m points back. -1 when they are too close to parallel. */
static float clear_of(const float n[3], const float m[3], float R, float rho)
{
    float c = v3_dot(n, m);
    if (c <= 0.0f)
        return R;
    float s = sqrtf(fmaxf(0.0f, 1.0f - c * c));
    return s < 0.2f ? -1.0f : (R + rho) / s;
}

/* The years of a shoot made in step `born`: 1 in the season it appears (a
 * node made in the last step has born = step − 1: the step count is raised
 * after the model's step). */
static float years_since(const merp_builder *b, uint32_t born)
{
    return b->step > born + 1 ? (float)(b->step - born) : 1.0f;
}

/* What the patches planned so far cover, by node id: an internode is
 * claimed from its base up to lo[id] (a patch's out or lateral shaft ends
 * in it) and from hi[id] up to its tip (an in shaft begins in it); a node
 * inside a patch has lo = its length, hi = 0. */
typedef struct claims {
    float *lo, *hi;
} claims;

/* The centre of the cut at `at` along internode id. */
static void point_on(const mer_node *n, float at, float o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = n->base[k] + at * n->dir[k];
}

/* Cut s of jt: `need` along its shaft's axis from J, forwards from J at the
 * base of `first` or, `back`, backwards from J at its tip; across as many
 * internodes as that takes (short internodes of a thick axis), none of them
 * claimed by another patch, none a living tip's cone (but a relayed fork's
 * parent, whose tip the patch covers). Sets node[s], at[s];
 * with `mark`, claims what the shaft covers. False when it does not fit. */
static bool follow(const merp_builder *b, claims *cl, uint32_t first, bool back, float need, bool mark,
                   merp_joint *jt, uint32_t s)
{
    float arc = 0.0f;
    uint32_t id = first;
    for (uint32_t passed = 0;; passed++) {
        /* a relayed fork's parent may be a tip's cone: the patch covers its tip */
        bool cone = !back || (jt->relay && id == first);
        if (!usable(b, id, cone) || passed > MAX_SPAN)
            return false;
        const mer_node *n = &b->nodes[id];
        float len = n->length, gap = CUT_GAP * merp_node_radius(b, id);
        if (arc + len > need) {
            float at = back ? len - (need - arc) : need - arc;
            bool taken = back ? at <= cl->lo[id] + gap || cl->hi[id] < len
                              : cl->lo[id] > 0.0f || at >= cl->hi[id] - gap;
            if (taken || (!back && tip_cone(b, id) && len - at < merp_node_radius(b, id)))
                return false; /* ... or a tip's cone left under a radius long: a flat disk */
            if (mark && back)
                cl->hi[id] = at;
            else if (mark)
                cl->lo[id] = at;
            jt->node[s] = id, jt->at[s] = at;
            return true;
        }
        if (cl->lo[id] > 0.0f || cl->hi[id] < len)
            return false;
        if (mark)
            cl->lo[id] = len, cl->hi[id] = 0.0f;
        arc += len;
        uint32_t next = back ? n->parent : n->main_child;
        if (back && (next == MER_NO_NODE || b->nodes[next].main_child != id))
            return false;
        id = next;
    }
}

/* Whether the axis from J to cut s is straight enough to be one segment of
 * the field: every internode boundary between them within STRAIGHT × r of
 * the line from J to the cut's centre (inside the shaft's tube), and the
 * cut's internode, whose tube goes on from the cut ring, along it. */
static bool straight(const merp_builder *b, const merp_joint *jt, uint32_t first, uint32_t s,
                     const float J[3], float r)
{
    const float *dir = b->nodes[jt->node[s]].dir, *u = jt->n[s];
    float D = jt->d[s];
    if (D <= 0.0f || fabsf(v3_dot(u, dir)) < STRAIGHT_COS)
        return false;
    for (uint32_t id = first; id != jt->node[s];) {
        const mer_node *n = &b->nodes[id];
        float q[3], e[3];
        if (s == MERP_CUT_IN)
            memcpy(q, n->base, sizeof q);
        else
            merp_tip_of(n, q);
        for (int k = 0; k < 3; k++)
            q[k] -= J[k];
        v3_cross(q, u, e);
        if (v3_len(e) > STRAIGHT * r)
            return false;
        id = s == MERP_CUT_IN ? n->parent : n->main_child;
    }
    return true;
}

/* The parent's radius at J in jt's field: its tube's there (the next ring's,
 * its continuation's), but a relayed fork's parent keeps its own, which the
 * pipe model gives the relay's pipes too: its tube's next ring (a thinner
 * continuation's) lies inside the patch. */
static float in_radius(const merp_builder *b, const merp_joint *jt)
{
    uint32_t P = jt->start[MERP_CUT_IN];
    return jt->relay ? merp_node_radius(b, P) : merp_node_end_radius(b, P);
}

/* Shaft s's segment of the field: the straight line from its start at J
 * through its cut's centre, reaching EXTEND cells past it (so the surface
 * at the cut is the plain tube), its radius r0 at J and the tube's at the cut. */
static void shaft_segment(const merp_builder *b, const merp_joint *jt, uint32_t s, const float J[3], float r0,
                          float h, merp_seg *g)
{
    float r_cut = merp_cut_radius(b, jt, s);
    float D = jt->d[s], E = D + EXTEND * h;
    float r_far = fmaxf(r0 + (r_cut - r0) * E / D, 0.5f * r_cut), Q[3];
    for (int k = 0; k < 3; k++)
        Q[k] = J[k] + jt->n[s][k] * E;
    if (s == MERP_CUT_IN) {
        memcpy(g->a, Q, sizeof g->a), memcpy(g->b, J, sizeof g->b);
        g->ra = r_far, g->rb = r0;
    } else {
        memcpy(g->a, J, sizeof g->a), memcpy(g->b, Q, sizeof g->b);
        g->ra = r0, g->rb = r_far;
    }
}

/* Places jt's cuts (see follow), `need` each from J, and with them its
 * field's shafts; with `mark`, claims them. False when one does not fit. */
static bool place_cuts(const merp_builder *b, claims *cl, const uint32_t *first, const float *need, float h,
                       bool mark, merp_joint *jt)
{
    merp_junction *f = &jt->field;
    float J[3];
    memcpy(J, f->in.b, sizeof J);
    for (uint32_t s = 0; s < jt->cuts; s++) {
        bool back = s == MERP_CUT_IN;
        if (!follow(b, cl, first[s], back, need[s], mark, jt, s))
            return false;
        point_on(&b->nodes[jt->node[s]], jt->at[s], jt->o[s]);
        /* The cut plane is square to the shaft's segment, and so is the
         * tube's cut ring (tube.c), which is then a cross-section of the
         * segment's capsule however the axis bends beyond it. */
        const float *from = s < MERP_CUT_LATERAL ? J : b->nodes[first[s]].base;
        for (int k = 0; k < 3; k++)
            jt->n[s][k] = jt->o[s][k] - from[k];
        jt->d[s] = v3_len(jt->n[s]);
        if (!v3_normalize(jt->n[s]))
            return false;
        if (!mark && !straight(b, jt, first[s], s, from, merp_node_radius(b, first[s])))
            return false;
    }
    if (!mark) {
        merp_seg *g[MERP_PATCH_CUTS] = {&f->in, &f->out, &f->lateral[0], &f->lateral[1]};
        for (uint32_t s = 0; s < jt->cuts; s++) {
            const float *from = s < MERP_CUT_LATERAL ? J : b->nodes[first[s]].base;
            float r0 = s == MERP_CUT_IN ? in_radius(b, jt) : merp_node_radius(b, first[s]);
            shaft_segment(b, jt, s, from, r0, h, g[s]);
        }
    }
    return true;
}

/* Whether lateral L of P may be a shaft of P's patch: a living axis of its
 * own (no twig), at least LATERAL_RATIO of P's diameter, from J. */
static bool patch_lateral(const merp_builder *b, const mer_node *p, const float J[3], uint32_t L)
{
    if (!usable(b, L, true) || b->nodes[L].diameter < LATERAL_RATIO * p->diameter)
        return false;
    const merp_axis *a = axis_from(b, L);
    float gap[3];
    for (int i = 0; i < 3; i++)
        gap[i] = b->nodes[L].base[i] - J[i];
    return a != NULL && !merp_mesh_is_twig(b, a) && v3_len(gap) <= 1e-4f * (1.0f + v3_len(J));
}

/* Plans the fork at P's tip into jt (cuts, field); false when it does not
 * fit between the patches planned so far.
 *
 * A fork with no living continuation (P ends in its terminal bud, dormant
 * or flowered, or in a cut: the forks of a sympodium, and of trees whose
 * apical control lets the laterals outgrow the leader) is relayed: its
 * thickest lateral takes the continuation's place in the patch, one solid
 * with P (A = max(in, out), with the bud scale scar where its shoot began),
 * and the other laterals blend into both with their ridges. That is how
 * the tree itself goes on (the relay shoot becomes the axis; G04's ridge
 * forms between a branch and the stem it leaves, and the stem here is P and
 * its relay); P's tip, which tube.c would draw as a cone (or a disk) with
 * the laterals leaving its apex, lies inside the patch, whose field ends
 * P's shaft in its capsule's round end.
 *
 * With `swap`, a fork whose continuation is thinner than its thickest
 * lateral is relayed too: that lateral goes on from P, the continuation
 * becomes one of the patch's laterals (its cut ring ends the patch on P's
 * own axis, whose tube goes on from it). merp_mesh_joints_plan asks for it
 * only where the fork does not fit as it grew (fig6-sylleptic's, whose
 * laterals grow in their parent's season and outgrow its continuation),
 * so a fork that fits keeps its continuation. */
static bool plan_one(merp_builder *b, claims *cl, uint32_t P, bool swap, merp_joint *jt)
{
    const mer_node *p = &b->nodes[P];
    uint32_t C = p->main_child;
    const bool none = C == MER_NO_NODE || !b->nodes[C].alive, relay = none || swap;
    float J[3];
    merp_tip_of(p, J);
    uint32_t lat[2], nl = 0;
    for (int k = 0; k < 2; k++)
        if (patch_lateral(b, p, J, p->lateral_child[k]))
            lat[nl++] = p->lateral_child[k];
    if (relay) { /* the thickest lateral relays the axis (the first of equals) */
        if (nl == 0)
            return false;
        uint32_t t = nl == 2 && b->nodes[lat[1]].diameter > b->nodes[lat[0]].diameter, L = lat[t];
        if (swap) { /* the continuation, thinner, in the relay's place among the laterals */
            if (none || !usable(b, C, true) || !(b->nodes[C].diameter < b->nodes[L].diameter))
                return false;
            lat[t] = C;
        } else {
            if (nl == 2)
                lat[0] = lat[1 - t];
            nl--;
        }
        C = L;
    }
    if (!usable(b, P, none) || !usable(b, C, true) || (nl == 0 && !relay))
        return false;
    *jt = (merp_joint){.start = {P, C}, .cuts = 2, .relay = relay};
    merp_junction *f = &jt->field;
    segment_of(b, P, &f->in);
    segment_of(b, C, &f->out);
    f->in.rb = in_radius(b, jt); /* a relayed parent keeps its own */
    f->w = PCM_WIDTH;
    for (uint32_t k = 0; k < nl; k++) {
        segment_of(b, lat[k], &f->lateral[f->laterals]);
        jt->start[jt->cuts++] = lat[k];
        f->laterals++;
    }
    float h = merp_joint_cell(b, jt);
    /* Each shaft's direction away from J, and its primitives' supports. */
    float dir[MERP_PATCH_CUTS][3], R[MERP_PATCH_CUTS], need[MERP_PATCH_CUTS];
    uint32_t first[MERP_PATCH_CUTS];
    for (int i = 0; i < 3; i++)
        dir[MERP_CUT_IN][i] = -p->dir[i];
    for (uint32_t s = 1; s < jt->cuts; s++)
        memcpy(dir[s], b->nodes[jt->start[s]].dir, sizeof dir[s]);
    for (uint32_t s = 0; s < jt->cuts; s++) {
        const merp_seg *g = s == 0 ? &f->in : s == 1 ? &f->out : &f->lateral[s - 2];
        R[s] = SUPPORT_SEEN * merp_seg_support(g);
        first[s] = jt->start[s];
    }
    /* Each cut's reach is sized by the tube's radius at the cut (joints.c),
     * which is known only once the cut is placed: first the radius at J, then,
     * while a cut lands where its axis is thicker, again with that radius
     * (the cut moves out, clear of the others by the wider reach). */
    float r_reach[MERP_PATCH_CUTS];
    for (uint32_t s = 0; s < jt->cuts; s++)
        r_reach[s] = merp_node_radius(b, jt->start[s]);
    for (uint32_t pass = 0;; pass++) {
        for (uint32_t s = 0; s < jt->cuts; s++) {
            float r = merp_node_radius(b, jt->start[s]), rho = MERP_JOINT_REACH * r_reach[s] + h, d = r;
            for (uint32_t o = 0; o < jt->cuts; o++) {
                if (o == s || (s < 2 && o < 2)) /* in and out are one solid (max) */
                    continue;
                float c = clear_of(dir[s], dir[o], R[o], rho);
                if (c < 0.0f)
                    return false;
                d = fmaxf(d, c);
            }
            need[s] = d + 2.0f * h;
        }
        if (!place_cuts(b, cl, first, need, h, false, jt))
            return false;
        bool thicker = false;
        for (uint32_t s = 0; s < jt->cuts; s++) {
            float r = merp_cut_radius(b, jt, s);
            if (r > r_reach[s])
                r_reach[s] = r, thicker = true;
        }
        if (!thicker)
            break;
        if (pass + 1 == REPLANS)
            return false; /* still thickening: the axis is no shaft for a patch */
    }
    /* A cut ring under THIN_CUT cells in radius: its loop on the grid is
     * a cell or two, and no polygonizer's patch closed on it (fig6-sylleptic,
     * whose continuations are far thinner than their laterals and taper
     * fast beyond them: 119 of 171 open patches; the rest of its forks, and
     * every other preset's, are unchanged by it). Such a fork is not
     * planned, so its shafts are free for the forks beside it. */
    for (uint32_t s = 0; s < jt->cuts; s++)
        if (merp_cut_radius(b, jt, s) < THIN_CUT * h)
            return false;
    place_cuts(b, cl, first, need, h, true, jt);
    float ridge_up[3];
    memcpy(ridge_up, b->nodes[C].dir, sizeof ridge_up);
    /* The bark ages with the oldest lateral (G04 Fig. 7). The parent's bud
     * scale scar exists only where J ends one season's shoot and C begins the
     * next's, and ages with C's shoot. */
    uint32_t born = b->nodes[C].born; /* a relay's own, where it has no lateral */
    for (uint32_t k = 0; k < f->laterals; k++)
        born = k == 0 || b->nodes[first[2 + k]].born < born ? b->nodes[first[2 + k]].born : born;
    merp_junction_age(f, ridge_up, years_since(b, born));
    f->scar_weight = b->nodes[C].born == p->born
                         ? 0.0f
                         : merp_junction_scar_weight(years_since(b, b->nodes[C].born));
    return true;
}

/* A fork that may get a patch, and its thickest lateral's diameter. */
typedef struct candidate {
    float key;
    uint32_t id;
} candidate;

static int candidate_cmp(const void *x, const void *y)
{
    const candidate *a = x, *b = y;
    if (a->key != b->key)
        return a->key > b->key ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* The forks at least `threshold` thick with a lateral of LATERAL_RATIO,
 * thickest lateral first (ties by id): where patches compete for the short
 * internodes of an axis, the thickest branches get them. *count is set. */
static candidate *candidates(const merp_builder *b, float threshold, uint32_t *count)
{
    uint32_t n = 0;
    candidate *c = merp_malloc((b->node_count ? b->node_count : 1) * sizeof *c);
    if (c == NULL)
        return NULL;
    for (uint32_t id = 0; id < b->node_count; id++) {
        const mer_node *p = &b->nodes[id];
        if (!p->alive || p->diameter < threshold)
            continue;
        float key = 0.0f;
        for (int k = 0; k < 2; k++) {
            uint32_t L = p->lateral_child[k];
            if (L != MER_NO_NODE && b->nodes[L].alive && b->nodes[L].diameter >= LATERAL_RATIO * p->diameter)
                key = fmaxf(key, b->nodes[L].diameter);
        }
        if (key > 0.0f)
            c[n++] = (candidate){key, id};
    }
    qsort(c, n, sizeof *c, candidate_cmp);
    *count = n;
    return c;
}

mer_result merp_mesh_joints_plan(merp_builder *b, mer_error *err)
{
    size_t n = b->node_count, m = n ? n : 1;
    b->joint_at = merp_malloc(m * sizeof *b->joint_at);
    b->lateral_in = merp_malloc(m * sizeof *b->lateral_in);
    b->cut_end = merp_malloc(m * sizeof *b->cut_end);
    b->cut_begin = merp_malloc(m * sizeof *b->cut_begin);
    claims cl = {merp_malloc(m * sizeof *cl.lo), merp_malloc(m * sizeof *cl.hi)};
    float threshold = b->opt.junction_diameter > 0.0f ? b->opt.junction_diameter
                                                      : JUNCTION_DIAMETER_FRACTION * b->max_diameter;
    uint32_t cap = 0, count = 0;
    candidate *c = candidates(b, threshold, &count);
    mer_result rc = MER_OK;
    if (!b->joint_at || !b->lateral_in || !b->cut_end || !b->cut_begin || !cl.lo || !cl.hi || !c)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory planning junctions");
    for (size_t i = 0; i < n && rc == MER_OK; i++) {
        b->joint_at[i] = b->lateral_in[i] = b->cut_end[i] = b->cut_begin[i] = UINT32_MAX;
        cl.lo[i] = 0.0f, cl.hi[i] = INFINITY;
    }
    merp_joint jt;
    for (uint32_t i = 0; i < count && rc == MER_OK; i++) {
        uint32_t id = c[i].id;
        if (!plan_one(b, &cl, id, false, &jt) && !plan_one(b, &cl, id, true, &jt))
            continue;
        if (b->joint_count == cap) {
            cap = cap ? 2 * cap : 16;
            merp_joint *grown = merp_realloc(b->joints, cap * sizeof *grown);
            if (grown == NULL) {
                rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory planning junctions");
                break;
            }
            b->joints = grown;
        }
        jt.ok = true;
        b->joints[b->joint_count] = jt;
        b->joint_at[id] = b->joint_count;
        b->cut_begin[jt.node[MERP_CUT_IN]] = b->joint_count;
        for (uint32_t s = 1; s < jt.cuts; s++) {
            b->cut_end[jt.node[s]] = b->joint_count * MERP_PATCH_CUTS + s;
            if (jt.start[s] != b->nodes[id].main_child) /* an axis that begins in the patch */
                b->lateral_in[jt.start[s]] = b->joint_count * MERP_PATCH_CUTS + s;
        }
        b->joint_count++;
    }
    b->joints_unfit = count - b->joint_count;
    merp_free(c), merp_free(cl.lo), merp_free(cl.hi);
    return rc;
}
