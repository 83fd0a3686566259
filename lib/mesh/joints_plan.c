/* meristem — implicit junctions in the bark (meristem/mesh.h, Junctions; G04
 * §3, issue 18): which forks get a patch (a fork of its own, or a run of
 * forks a few radii apart, up one axis or up a lateral, or up a short axis
 * that ends inside the patch with the thin forks on it) and where their
 * shafts are cut, each shaft across as many short internodes as its cut
 * needs; the field each patch polygonizes (joints.c builds and writes the
 * patches). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "mesh_private.h"

#define JUNCTION_DIAMETER_FRACTION 0.2f /* junction_diameter 0: this × the thickest */
#define LATERAL_RATIO 0.25f  /* a lateral in a patch: at least this × its parent's diameter */
#define SUPPORT_SEEN 0.8f    /* another primitive's field counts within this × its support */
#define MAX_SPAN 64u         /* a patch's shaft crosses at most this many internodes */
#define CUT_GAP 0.1f         /* two patches' cuts in one internode: this × its radius apart */
#define BASE_GAP 0.01f       /* a cut and a trunk's base disk: this × its radius apart */
#define STRAIGHT 0.5f        /* a shaft's axis stays within this × its radius of one line ... */
#define STRAIGHT_COS 0.9f    /* ... and its cut's internode within 25° of it */
#define EXTEND 3.0f          /* a shaft's segment reaches this many cells past its cut */
/* A fork's cuts are placed at most this many times (place_clear): a cut that
 * lands where its axis is thicker moves out, and down a steeply tapering
 * trunk (the inverse model's conifer) that takes up to a dozen passes: with
 * 4, inverse-conifer left 23 forks (seeds 1-5) "still thickening", with 12,
 * 9, none of them for that; 64 patch no more. A single fork's cut that its
 * bending axis leaves short of clearing the others moves out in the same
 * passes. */
#define REPLANS 12u
#define PCM_WIDTH 0.15f      /* w of PCM's bulge, in field units */
#define CELLS_PER_RADIUS 3.0f /* a patch's grid: cells per parent radius ... */
#define CELLS_PER_LATERAL_RADIUS 1.25f /* ... and at least per lateral radius */
#define THIN_CUT 0.4f        /* a cut ring at least this many cells in radius ... */
#define THIN_CELLS 0.5f      /* ... or the patch's cells made finer, to this many, */
#define THIN_FINER 4.0f      /* ... at most this many times */
#define TILT 0.44f           /* sin 26°: a cut plane leans at most this far off its shaft (STRAIGHT_COS) */
#define RUN_FINEST 12.0f     /* a run's cells: at most this many per its in shaft's radius, */
#define RUN_FINE_CELLS 2000000u /* ... or its grid at most this many cells (plan_run) */
#define RUN_CLEAR 40.0f      /* a run's cut: within this × its shaft's radius of its J */
/* A run of more than RUN_FORKS forks is planned on a grid of at most
 * RUN_MANY_CELLS cells (build_patch may try it on finer ones if that grid
 * fails): its cells are its thinnest shaft's all along it, and up the bench
 * tree's trunk (fig7-bh-0.54, seed 1, 16 steps) a run grew to eleven forks
 * and a million cells, 33 ms of the tree's 84 (with this bound a run of
 * nine there takes 3 ms more than runs of at most eight); a bush's short
 * axis with its twigs takes up to MERP_RUN_FORKS forks in far fewer
 * (abop-1.24a's runs of 13-16 forks: 56,000-172,000 cells; abop-1.24b's
 * of 19-23, whose twigs lie in one plane: 258,000-575,000, each closing
 * on its first grid in 18-37 ms). */
#define RUN_FORKS 8u
#define RUN_MANY_CELLS 600000u

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
 * one, its tip inside the patch). An internode of no length may be crossed
 * and may be a fork's parent: where an L-system string branches at one
 * point more often than an internode holds laterals (ABOP's Fig. 2.8a, a
 * ternary tree: F[...]/[...]/[...]), the branches past the second leave an
 * internode of no length, at the same J (one fork: fork_laterals), and
 * with those refused no fork of such a plant got a patch (abop-2.8a, seed
 * 1: none; 13, every fork, with them). follow() never cuts in one (a cut
 * lies past the arc so far), so no cut ring falls where no tube is. */
static bool usable(const merp_builder *b, uint32_t id, bool cone)
{
    if (id == MER_NO_NODE || id >= b->node_count || !b->nodes[id].alive || !(b->nodes[id].length >= 0.0f))
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
    for (uint32_t s = MERP_CUT_OUT; s < jt->cuts; s++) /* a relay is a lateral */
        if (s >= MERP_CUT_LATERAL || merp_joint_begins_axis(b->nodes, jt, s))
            h = fminf(h, merp_node_radius(b, jt->start[s]) / CELLS_PER_LATERAL_RADIUS);
    return jt->cell > 0.0f ? fminf(h, jt->cell) : h;
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

/* (mesh_private.h) */
float merp_cut_clearance(const float n[3], const float m[3], float R, float rho)
{
    float c = v3_dot(n, m);
    if (c <= 0.0f)
        return R;
    float s = sqrtf(fmaxf(0.0f, 1.0f - c * c));
    return s < 0.2f ? -1.0f : (R + rho * c) / s;
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
 * inside a patch has lo = its length, hi = 0. own_lo and own_hi say which
 * joint claims each part (UINT32_MAX: none); `blocker` is the joint whose
 * claim the last failed placement met (UINT32_MAX: none). */
typedef struct claims {
    float *lo, *hi;
    uint32_t *own_lo, *own_hi;
    uint32_t blocker;
    uint32_t stopper; /* the fork whose lateral kept the last failed shaft
                         from ending inside its patch (MER_NO_NODE: none) */
    uint32_t bend;    /* the internode at whose tip the last failed shaft's
                         axis bends most (straight; MER_NO_NODE: none) */
    uint8_t *tried; /* by node id: 1 once the planner has come to that fork */
    merp_joint *probe; /* swallows' trial plans (a joint is 75 KB: off the stack) */
} claims;

/* The centre of the cut at `at` along internode id. */
static void point_on(const mer_node *n, float at, float o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = n->base[k] + at * n->dir[k];
}

/* Whether no living lateral leaves internode id (a shaft that ends inside
 * a patch covers its internodes whole, and a lateral's tube would begin
 * inside it). */
static bool bare_internode(const merp_builder *b, uint32_t id)
{
    for (int k = 0; k < 2; k++) {
        uint32_t L = b->nodes[id].lateral_child[k];
        if (L != MER_NO_NODE && b->nodes[L].alive)
            return false;
    }
    return true;
}

/* Ends shaft s inside jt's patch at the tip of internode id, its axis's
 * last, claimed whole (follow): where jt may cap its shafts and no lateral
 * leaves the internodes it covers (`bare`). */
static bool cap_end(const merp_builder *b, uint32_t id, bool bare, merp_joint *jt, uint32_t s)
{
    if (!jt->cap || !bare || s == MERP_CUT_IN)
        return false;
    jt->node[s] = id, jt->at[s] = b->nodes[id].length, jt->capped[s] = 1;
    return true;
}

/* Ends jt's in shaft on the plant's base (jt->base) at root internode id,
 * claimed whole (follow). */
static bool base_end(const merp_builder *b, claims *cl, uint32_t id, bool mark, merp_joint *jt)
{
    assert(b->nodes[id].parent == MER_NO_NODE);
    jt->node[MERP_CUT_IN] = id, jt->at[MERP_CUT_IN] = 0.0f, jt->base = true;
    if (mark)
        cl->lo[id] = b->nodes[id].length, cl->hi[id] = 0.0f;
    return true;
}

/* Cut s of jt: `need` along its shaft's axis from J, forwards from J at the
 * base of `first` or, `back`, backwards from J at its tip; across as many
 * internodes as that takes (short internodes of a thick axis), none of them
 * claimed by another patch, none a living tip's cone (but a relayed fork's
 * parent, whose tip the patch covers). Sets node[s], at[s];
 * with `mark`, claims what the shaft covers. Where the axis ends first, or
 * would leave its tip's cone under a radius long, an out or lateral shaft
 * ends inside the patch (cap_end, capped[s]) if it may. Where the in cut
 * would fall below the plant's base, or within BASE_GAP of it, the in shaft
 * ends on the base (base_end): there is no tube below to stitch to, and
 * the patch's cut there is flat, the trunk's base disk (fig6-sylleptic's
 * root internode is half its thick trunk's in cut long, and its lowest,
 * thickest fork stayed tubes, its laterals' base disks showing). False when
 * it does not fit. */
static bool follow(const merp_builder *b, claims *cl, uint32_t first, bool back, float need, bool mark,
                   merp_joint *jt, uint32_t s)
{
    float arc = 0.0f;
    uint32_t id = first, forked = MER_NO_NODE; /* the first internode passed that a lateral leaves */
    bool bare = true; /* no living lateral leaves the internodes passed so far */
    jt->capped[s] = 0;
    if (back)
        jt->base = false;
    for (uint32_t passed = 0;; passed++) {
        /* a relayed fork's parent may be a tip's cone: the patch covers its tip */
        bool cone = !back || (jt->relay && id == first);
        if (!usable(b, id, cone) || passed > MAX_SPAN)
            return false;
        const mer_node *n = &b->nodes[id];
        float len = n->length, gap = CUT_GAP * merp_node_radius(b, id);
        float at = back ? len - (need - arc) : need - arc;
        /* An in cut within a gap of its internode's base, which no patch
         * claims, moves out past the base, a gap into the internode below
         * (as far from the ring between them): there is no other cut to
         * keep it from (a bush's short internodes: in abop-1.24a, seed 1,
         * fork 139's in cut fell within a tenth of a radius of a base, and
         * the fork stayed tubes). */
        const uint32_t below_id = n->parent;
        if (back && arc + len > need && at <= gap && cl->lo[id] == 0.0f && !(cl->hi[id] < len) &&
            below_id != MER_NO_NODE && b->nodes[below_id].main_child == id)
            need = arc + len + CUT_GAP * merp_node_radius(b, below_id);
        if (arc + len > need) {
            /* below a tree's root internode is its base disk, no patch's cut */
            bool root = back && n->parent == MER_NO_NODE && cl->lo[id] == 0.0f;
            float below = root ? BASE_GAP * merp_node_radius(b, id) : gap;
            if (root && at <= below && !(cl->hi[id] < len))
                return base_end(b, cl, id, mark, jt);
            bool by_lo = back ? at <= cl->lo[id] + below : cl->lo[id] > 0.0f;
            bool by_hi = back ? cl->hi[id] < len : at >= cl->hi[id] - gap;
            if (by_lo || by_hi) {
                cl->blocker = by_lo ? cl->own_lo[id] : cl->own_hi[id];
                return false;
            }
            if (!back && tip_cone(b, id) && len - at < merp_node_radius(b, id)) {
                /* a tip's cone left under a radius long (a flat disk): the
                 * shaft ends inside the patch, or the fork does not fit */
                if (cl->hi[id] < len) {
                    cl->blocker = cl->own_hi[id];
                    return false;
                }
                if (jt->cap && !(bare && bare_internode(b, id)))
                    cl->stopper = bare ? id : forked;
                if (!cap_end(b, id, bare && bare_internode(b, id), jt, s))
                    return false;
                if (mark)
                    cl->lo[id] = len, cl->hi[id] = 0.0f;
                return true;
            }
            if (mark && back)
                cl->hi[id] = at;
            else if (mark)
                cl->lo[id] = at;
            jt->node[s] = id, jt->at[s] = at;
            return true;
        }
        if (cl->lo[id] > 0.0f || cl->hi[id] < len) {
            cl->blocker = cl->lo[id] > 0.0f ? cl->own_lo[id] : cl->own_hi[id];
            return false;
        }
        if (mark)
            cl->lo[id] = len, cl->hi[id] = 0.0f;
        arc += len;
        if (bare && !bare_internode(b, id))
            forked = id;
        bare = bare && bare_internode(b, id);
        uint32_t next = back ? n->parent : n->main_child;
        if (back && next == MER_NO_NODE)
            return base_end(b, cl, id, mark, jt); /* (claimed above) */
        if (back && b->nodes[next].main_child != id)
            return false;
        if (!back && (next == MER_NO_NODE || !b->nodes[next].alive)) { /* the axis ends before its cut */
            if (jt->cap && !bare)
                cl->stopper = forked; /* a run with that fork may end it inside */
            return cap_end(b, id, bare, jt, s);
        }
        id = next;
    }
}

/* Whether the axis from J to cut s is straight enough to be one segment of
 * the field: every internode boundary between them within STRAIGHT × r of
 * the line from J to the cut's centre (inside the shaft's tube), and the
 * cut's internode, whose tube goes on from the cut ring, along it. Where
 * it is not, *bend is the internode whose tip is the boundary farthest off
 * that line (or, every boundary within it, the cut's internode's base):
 * an elbow there (a fork of a run with no lateral, plan_merged) makes two
 * segments of the shaft; MER_NO_NODE where no boundary lies between. */
static bool straight(const merp_builder *b, const merp_joint *jt, uint32_t first, uint32_t s,
                     const float J[3], float r, uint32_t *bend)
{
    const bool back = s == MERP_CUT_IN;
    const float *dir = b->nodes[jt->node[s]].dir, *u = jt->n[s];
    float D = jt->d[s], farthest = 0.0f;
    *bend = MER_NO_NODE;
    for (uint32_t id = first; id != jt->node[s];) {
        const mer_node *n = &b->nodes[id];
        float q[3], e[3];
        if (back)
            memcpy(q, n->base, sizeof q);
        else
            merp_tip_of(n, q);
        for (int k = 0; k < 3; k++)
            q[k] -= J[k];
        v3_cross(q, u, e);
        if (v3_len(e) > STRAIGHT * r && v3_len(e) > farthest)
            farthest = v3_len(e), *bend = back ? n->parent : id;
        id = back ? n->parent : n->main_child;
    }
    if (*bend != MER_NO_NODE)
        return false;
    if (D > 0.0f && fabsf(v3_dot(u, dir)) >= STRAIGHT_COS)
        return true;
    if (jt->node[s] != first)
        *bend = back ? jt->node[s] : b->nodes[jt->node[s]].parent;
    return false;
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
static void shaft_segment(const merp_builder *b, const merp_joint *jt, uint32_t s, const float J_at[3], float r0,
                          float h, merp_seg *g)
{
    float J[3]; /* J_at may be g's own end (the in shaft's J) */
    memcpy(J, J_at, sizeof J);
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

/* Shaft s's segment where it ends inside the patch (capped): from J to
 * the axis's end, its radius r0 at J and the end's, drawn back so that its
 * round end reaches the end point (a disk's end, where the tube was flat)
 * or, with a fifth of that radius, comes to it as the tip's cone did. */
static void capped_segment(const merp_builder *b, const merp_joint *jt, uint32_t s, const float J[3], float r0,
                           merp_seg *g)
{
    assert(s != MERP_CUT_IN); /* so g is not the in segment whose end J may be */
    float r_end = merp_cut_radius(b, jt, s);
    if (tip_cone(b, jt->node[s]))
        r_end *= 0.2f;
    float back = fminf(r_end, 0.5f * jt->d[s]);
    memcpy(g->a, J, sizeof g->a);
    for (int k = 0; k < 3; k++)
        g->b[k] = jt->o[s][k] - back * jt->n[s][k];
    g->ra = r0, g->rb = r_end;
}

/* Places jt's cuts (see follow), `need` each from J, and with them its
 * field's shafts; with `mark`, claims them. False when one does not fit. */
static bool place_cuts(const merp_builder *b, claims *cl, const float *need, float h, bool mark, merp_joint *jt)
{
    const uint32_t *first = jt->start;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        bool back = s == MERP_CUT_IN, lateral = jt->cut_slot[s] < MERP_SLOT_IN;
        if (!follow(b, cl, first[s], back, need[s], mark, jt, s))
            return false;
        point_on(&b->nodes[jt->node[s]], jt->at[s], jt->o[s]);
        /* The cut plane is square to the shaft's segment, and so is the
         * tube's cut ring (tube.c), which is then a cross-section of the
         * segment's capsule however the axis bends beyond it. */
        const float *J = jt->field[jt->cut_fork[s]].in.b;
        const float *from = lateral ? b->nodes[first[s]].base : J;
        for (int a = 0; a < 3; a++)
            jt->n[s][a] = jt->o[s][a] - from[a];
        jt->d[s] = v3_len(jt->n[s]);
        if (!v3_normalize(jt->n[s]))
            return false;
        if (!mark && !straight(b, jt, first[s], s, from, merp_node_radius(b, first[s]), &cl->bend))
            return false;
    }
    if (!mark) {
        for (uint32_t s = 0; s < jt->cuts; s++) {
            merp_junction *f = &jt->field[jt->cut_fork[s]];
            uint32_t k = jt->cut_slot[s];
            merp_seg *g = k == MERP_SLOT_IN ? &f->in : k == MERP_LINK_OUT ? &f->out : &f->lateral[k];
            const float *from = k < MERP_SLOT_IN ? b->nodes[first[s]].base : f->in.b;
            float r0 = s == MERP_CUT_IN ? in_radius(b, jt) : merp_node_radius(b, first[s]);
            if (jt->capped[s])
                capped_segment(b, jt, s, from, r0, g);
            else
                shaft_segment(b, jt, s, from, r0, h, g);
        }
    }
    return true;
}

/* A primitive of a run's field as its cuts' clearance sees it: from o along
 * unit m for len (a shaft: its axis's reach past the patch, INFINITY for
 * the in shaft or an axis longer than MAX_SPAN internodes), its
 * support R; `axis` the group whose axis it is part of (its in and out
 * shafts and the segments between its forks, one solid), or -1 (a
 * lateral). */
typedef struct run_prim {
    float o[3], m[3], len, R;
    int axis;
} run_prim;

static float prim_distance(const run_prim *q, const float p[3])
{
    float d[3];
    for (int a = 0; a < 3; a++)
        d[a] = p[a] - q->o[a];
    float t = merp_clampf(v3_dot(d, q->m), 0.0f, q->len);
    for (int a = 0; a < 3; a++)
        d[a] -= t * q->m[a];
    return v3_len(d);
}

/* How far the plane through p square to shaft s's direction lies ahead
 * of primitive q (every point of q is at least this far behind it;
 * -INFINITY when q reaches past it). */
static float plane_gap(const run_prim *q, const run_prim *s, const float p[3])
{
    float ahead = 0.0f, c = v3_dot(q->m, s->m);
    for (int a = 0; a < 3; a++)
        ahead += (p[a] - q->o[a]) * s->m[a];
    if (c <= 0.0f)
        return ahead;
    return isinf(q->len) ? -INFINITY : ahead - q->len * c;
}

/* How far from its J along its direction shaft s's cut must lie (see
 * merp_cut_clearance, which a single fork's shafts, all from one J, solve in closed
 * form): the first d from r in steps of h/2 where the cut's disk (radius ρ)
 * is at least R from every other primitive (but the axis's, for an axis
 * shaft); -1 when none within RUN_CLEAR × r. The disk is that far when
 * its centre is R + ρ from the primitive, or when the primitive lies
 * wholly R behind the disk's plane (a lateral leaving a J below an in
 * cut's, say: the disk is then clear of it however wide). The plane is
 * square to the line from the shaft's start to the cut's centre: along
 * the shaft's direction where the cut falls within its `first` internode,
 * up to TILT off it past that. */
static float clear_of_run(const run_prim *prim, uint32_t n, uint32_t s, float r, float rho, float h, float first)
{
    for (float d = r; d <= RUN_CLEAR * r; d += 0.5f * h) {
        float tilt = d + 2.0f * h < first ? 0.0f : TILT * rho; /* the cut lies 2h past d (place_clear) */
        float p[3];
        for (int a = 0; a < 3; a++)
            p[a] = prim[s].o[a] + d * prim[s].m[a];
        bool clear = true;
        for (uint32_t o = 0; o < n && clear; o++)
            if (o != s && !(prim[o].axis >= 0 && prim[o].axis == prim[s].axis))
                clear = fmaxf(prim_distance(&prim[o], p) - rho, plane_gap(&prim[o], &prim[s], p) - tilt) >= prim[o].R;
        if (clear)
            return d;
    }
    return -1.0f;
}

/* What a patch's cuts must clear: a single fork's shafts all leave one J
 * (merp_cut_clearance, from their directions and supports), a run's leave several
 * (clear_of_run over its primitives, when `prim` is set). */
typedef struct clearance {
    float dir[MERP_PATCH_CUTS][3], R[MERP_PATCH_CUTS];
    const run_prim *prim;
    uint32_t prims;
} clearance;

/* How far from its J cut s of jt must lie, its reach rho, with the shafts
 * along dir (a single fork's); -1 when no distance clears the others (a
 * run's shaft on an axis shorter than that: the axis's length, to end
 * inside the patch). */
static float clear_distance(const merp_builder *b, const merp_joint *jt, const clearance *c, uint32_t s,
                            float rho, float h, const float (*dir)[3])
{
    float d = merp_node_radius(b, jt->start[s]);
    if (c->prim != NULL) {
        float x = clear_of_run(c->prim, c->prims, s, d, rho, h, b->nodes[jt->start[s]].length);
        /* a short axis that clears nowhere ends inside the patch (follow) */
        return x < 0.0f && s != MERP_CUT_IN && isfinite(c->prim[s].len) ? c->prim[s].len : x;
    }
    for (uint32_t o = 0; o < jt->cuts; o++) {
        if (o == s || (s < 2 && o < 2)) /* in and out are one solid (max) */
            continue;
        float x = merp_cut_clearance(dir[s], dir[o], c->R[o], rho);
        if (x < 0.0f)
            return -1.0f;
        d = fmaxf(d, x);
    }
    return d;
}

/* Where shaft s of jt leaves the parent's axis: its fork's J. */
static const float *shaft_origin(const merp_joint *jt, uint32_t s)
{
    return jt->field[jt->cut_fork[s]].in.b;
}

/* The grid's samples lie on a lattice fixed to the fork's J (a run's first),
 * so the crotch is sampled alike wherever the cuts fall: however the cuts
 * move, its samples keep their place about J in cells (from the box's corner,
 * an out cut a cell nearer J moved every sample of the patch, and
 * fork_ages' tenth-year crotch lost or kept its ridge vertices by that
 * chance). J lies J_OFF of a cell past a lattice plane on each axis, and
 * past the shifted grid's (SHIFT, joints.c) too: a sample at J, where the
 * shafts' fields meet on the bud scale scar's contact plane, cost 5 % more
 * vertices (fig7-bh-0.54, seeds 1-2). */
#define J_OFF 0.2f

/* The box (lo, hi) that shaft s of jt's surface stays in: its segment, from
 * its radius at J to the tube's at the cut, from J to two cells past the
 * cut, grown by the shell (merp_joint_grid's and need_boxes'). */
static void shaft_box(const merp_builder *b, const merp_joint *jt, uint32_t s, float h, float lo[3], float hi[3])
{
    const float *J = shaft_origin(jt, s);
    float r = fmaxf(merp_node_radius(b, jt->start[s]), merp_cut_radius(b, jt, s));
    float e = MERP_JOINT_SHELL * fmaxf(r, s < 2 ? merp_node_radius(b, jt->start[0]) : 0.0f) + 2.0f * h;
    for (int k = 0; k < 3; k++) {
        float end = jt->o[s][k] + 2.0f * h * jt->n[s][k];
        lo[k] = fminf(J[k], end) - e, hi[k] = fmaxf(J[k], end) + e;
    }
}

bool merp_joint_grid(const merp_builder *b, const merp_joint *jt, float h, float shift, merp_grid *g)
{
    assert(shift >= 0.0f && shift < 1.0f);
    const float *J0 = jt->field[0].in.b;
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = hi[k] = J0[k];
    for (uint32_t s = 0; s < jt->cuts; s++) {
        float slo[3], shi[3];
        shaft_box(b, jt, s, h, slo, shi);
        for (int k = 0; k < 3; k++)
            lo[k] = fminf(lo[k], slo[k]), hi[k] = fmaxf(hi[k], shi[k]);
    }
    for (uint32_t i = 1; i < jt->forks; i++) { /* a run's J, which may have no shaft of its own */
        const merp_seg *in = &jt->field[i].in;
        float e = MERP_JOINT_SHELL * fmaxf(in->ra, in->rb) + 2.0f * h;
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], in->b[k] - e);
            hi[k] = fmaxf(hi[k], in->b[k] + e);
        }
    }
    uint64_t cells = 1;
    g->h = h, g->warp = NULL;
    for (int k = 0; k < 3; k++) {
        g->origin[k] = J0[k] - h * (ceilf((J0[k] - lo[k]) / h) + J_OFF) - shift * h;
        g->n[k] = (uint32_t)ceilf((hi[k] - g->origin[k]) / h);
        g->n[k] = g->n[k] < 1 ? 1 : g->n[k];
        cells *= g->n[k];
    }
    return cells <= MERP_JOINT_MAX_CELLS;
}

/* A box along the axes (lo, hi) that needs cells of at most `need`. */
typedef struct need_box {
    float lo[3], hi[3], need;
} need_box;

/* The boxes of jt's shafts (shaft_box) and of each later fork's in
 * segment (the axis between its J and the one before: merp_joint_grid
 * takes its J alone), each with the cells its shaft needs (merp_joint_cell's
 * rule, shaft by shaft); at most MERP_PATCH_CUTS + MERP_RUN_FORKS. */
static uint32_t need_boxes(const merp_builder *b, const merp_joint *jt, float h, need_box *nb)
{
    uint32_t count = 0;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        bool lateral = s >= MERP_CUT_LATERAL || merp_joint_begins_axis(b->nodes, jt, s);
        need_box *x = &nb[count++];
        x->need = merp_node_radius(b, jt->start[s]) / (lateral ? CELLS_PER_LATERAL_RADIUS : CELLS_PER_RADIUS);
        if (merp_cut_has_ring(jt, s)) /* a thin ring, THIN_CELLS cells in radius at least (settle_cuts) */
            x->need = fminf(x->need, merp_cut_radius(b, jt, s) / THIN_CELLS);
        shaft_box(b, jt, s, h, x->lo, x->hi);
    }
    for (uint32_t i = 1; i < jt->forks; i++) {
        const merp_seg *in = &jt->field[i].in;
        float e = MERP_JOINT_SHELL * fmaxf(in->ra, in->rb) + 2.0f * h;
        need_box *x = &nb[count++];
        x->need = fminf(in->ra, in->rb) / CELLS_PER_RADIUS;
        for (int k = 0; k < 3; k++)
            x->lo[k] = fminf(in->a[k], in->b[k]) - e, x->hi[k] = fmaxf(in->a[k], in->b[k]) + e;
    }
    return count;
}

/* The warp and its arrays, in one allocation (merp_joint_grade). */
typedef struct graded {
    merp_grid_warp warp;
    float at[]; /* the levels, then their ratios */
} graded;

bool merp_joint_grade(const merp_builder *b, const merp_joint *jt, merp_grid *g, void **store)
{
    *store = NULL;
    int A = 0; /* the grid's longest axis: a run's, up its trunk */
    for (int a = 1; a < 3; a++)
        A = g->n[a] > g->n[A] ? a : A;
    const uint32_t n = g->n[A], room = n + 2;
    const float h = g->h;
    need_box *nb = merp_malloc((MERP_PATCH_CUTS + MERP_RUN_FORKS) * sizeof *nb);
    float *fine = merp_malloc((size_t)n * sizeof *fine);
    graded *gr = merp_malloc(sizeof *gr + 2 * (size_t)room * sizeof(float));
    bool ok = nb != NULL && fine != NULL && gr != NULL;
    if (ok) {
        uint32_t boxes = need_boxes(b, jt, h, nb);
        for (uint32_t i = 0; i < n; i++)
            fine[i] = MERP_GRADE_WIDEST;
        for (uint32_t x = 0; x < boxes; x++) {
            float lo = floorf((nb[x].lo[A] - g->origin[A]) / h), hi = floorf((nb[x].hi[A] - g->origin[A]) / h);
            if (hi < 0.0f || lo >= (float)n)
                continue; /* wholly beyond the grid */
            uint32_t first = lo < 0.0f ? 0 : (uint32_t)lo, last = hi >= (float)n ? n - 1 : (uint32_t)hi;
            float allow = fmaxf(1.0f, nb[x].need / h);
            for (uint32_t i = first; i <= last; i++)
                fine[i] = fminf(fine[i], allow);
        }
        /* the first fork's J: the lattice plane below it (J_OFF) */
        const float *J0 = jt->field[0].in.b;
        float j = floorf((J0[A] - g->origin[A]) / h);
        uint32_t anchor = j < 0.0f ? 0 : j >= (float)n ? n - 1 : (uint32_t)j;
        float *ratio = gr->at + room;
        /* the levels in cells of h from the origin, made coordinates below */
        uint32_t cells = merp_grade_levels(fine, n, anchor, room, gr->at, ratio);
        ok = cells > 0 && cells < n; /* graded, and fewer levels */
        if (ok) {
            merp_grid_warp *w = &gr->warp;
            *w = (merp_grid_warp){.axis = A, .level = gr->at, .ratio = ratio};
            float widest = 0.0f, lean = 0.0f;
            for (uint32_t l = 0; l <= cells; l++) {
                gr->at[l] = g->origin[A] + gr->at[l] * h;
                widest = fmaxf(widest, ratio[l]);
                if (l < cells)
                    lean = fmaxf(lean, fabsf(ratio[l + 1] - ratio[l]));
            }
            for (int a = 0; a < 3; a++) {
                w->center[a] = J0[a];
                float far = fmaxf(fabsf(g->origin[a] - J0[a]), fabsf(g->origin[a] + (float)g->n[a] * h - J0[a]));
                w->reach[a] = widest * h + lean * far;
            }
            w->reach[A] = 0.0f;
            for (uint32_t l = 0; l < cells; l++)
                w->reach[A] = fmaxf(w->reach[A], gr->at[l + 1] - gr->at[l]);
            g->origin[A] = gr->at[0];
            g->n[A] = cells;
            g->warp = w;
            *store = gr, gr = NULL;
        }
    }
    merp_free(nb), merp_free(fine), merp_free(gr);
    return ok;
}

/* Places jt's cuts (place_cuts, not claimed), each clear of the other
 * primitives by its reach, into need[]. Each cut's reach is sized by the
 * tube's radius at the cut (joints.c), which is known only once the cut is
 * placed: first the radius at J, then, while a cut lands where its axis is
 * thicker, again with that radius (the cut moves out, clear of the others
 * by the wider reach). A single fork's shafts are first taken along their
 * first internodes; once placed, each runs straight from J through its
 * cut's centre (place_cuts), and a cut nearer J than those directions
 * clear (an axis that bends) moves out by its shortfall (at least half a
 * cell) until it clears them. Cuts only move out. False when the cuts do
 * not fit. */
static bool place_clear(const merp_builder *b, claims *cl, merp_joint *jt, const clearance *c, float h, float *need)
{
    float r_reach[MERP_PATCH_CUTS], push[MERP_PATCH_CUTS] = {0};
    for (uint32_t s = 0; s < jt->cuts; s++)
        r_reach[s] = merp_node_radius(b, jt->start[s]);
    for (uint32_t pass = 0;; pass++) {
        for (uint32_t s = 0; s < jt->cuts; s++) {
            float d = clear_distance(b, jt, c, s, MERP_JOINT_REACH * r_reach[s] + h, h, c->dir);
            if (d < 0.0f)
                return false;
            need[s] = fmaxf(d + 2.0f * h, pass > 0 ? need[s] : 0.0f) + push[s];
            push[s] = 0.0f;
        }
        if (!place_cuts(b, cl, need, h, false, jt))
            return false;
        bool again = false;
        for (uint32_t s = 0; s < jt->cuts; s++) {
            float r = merp_cut_radius(b, jt, s);
            if (r > r_reach[s])
                r_reach[s] = r, again = true;
        }
        for (uint32_t s = 0; c->prim == NULL && s < jt->cuts; s++) {
            float d = clear_distance(b, jt, c, s, MERP_JOINT_REACH * r_reach[s] + h, h,
                                     (const float(*)[3])jt->n);
            if (d < 0.0f)
                return false;
            /* The placed segments clear the others from d on
             * (merp_cut_clearance is exact for them); the first placement's
             * 2h past d is a margin. The chord is at most the arc, so the
             * shortfall is a least move. A capped shaft has no cut, and
             * the base no room to move, nor a ring to match: it is not
             * held clear of the others, and a lateral that leaves within
             * its reach of the ground is clipped flat there, on the
             * ground, as the trunk is. */
            if (merp_cut_has_ring(jt, s) && jt->d[s] < d)
                push[s] = fmaxf(0.5f * h, d - jt->d[s]), again = true;
        }
        if (!again)
            break;
        if (pass + 1 == REPLANS)
            return false; /* still thickening or bending: the axis is no shaft for a patch */
    }
    return true;
}

static float thinnest_cut(const merp_builder *b, const merp_joint *jt)
{
    float thin = INFINITY;
    for (uint32_t s = 0; s < jt->cuts; s++)
        if (merp_cut_has_ring(jt, s))
            thin = fminf(thin, merp_cut_radius(b, jt, s));
    return thin;
}

/* Places jt's cuts as place_clear does, with cells of *h. A cut ring under
 * THIN_CUT cells in radius has a loop of a cell or two on the grid, on
 * which no polygonizer's patch closed (fig6-sylleptic, whose continuations
 * are far thinner than their laterals and taper fast beyond them: 119 of
 * 171 open patches). A continuation far thinner than its laterals must
 * reach past them, to where its axis has thinned (fig6-sylleptic: rings of
 * 0.13-0.4 cells, 4-11 of its radii from J), while the cells are sized by
 * the parent and the laterals: the patch's cells are then made finer
 * (jt->cell, *h), to THIN_CELLS across that ring, and the cuts placed again
 * (nearer J, where the rings are thicker). A fork that would need cells
 * more than THIN_FINER times finer is not planned, so its shafts are free
 * for the forks beside it. False when the cuts do not fit. */
static bool settle_cuts(const merp_builder *b, claims *cl, merp_joint *jt, const clearance *c, float *h,
                        float *need)
{
    assert(jt->cell == 0.0f);
    if (!place_clear(b, cl, jt, c, *h, need))
        return false;
    float thin = thinnest_cut(b, jt);
    if (thin >= THIN_CUT * *h)
        return true;
    if (thin / THIN_CELLS < *h / THIN_FINER)
        return false;
    jt->cell = thin / THIN_CELLS;
    *h = merp_joint_cell(b, jt);
    return place_clear(b, cl, jt, c, *h, need) && thinnest_cut(b, jt) >= THIN_CUT * *h;
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

/* Where an L-system string branches at one point more often than an
 * internode holds laterals (ABOP's Fig. 2.8a: F[..]/[..]/[..]), the branches
 * leave a chain of internodes along one axis, each but the first of no
 * length, whose tips are all one J: one fork. Its owner is the chain's last
 * internode, the one whose continuation (if any) has a length; the owner's
 * patch takes the laterals of the whole chain (fork_laterals). Planned at
 * each internode instead, the last one's patch (a relay of its one lateral,
 * when the axis ends there) covered J and left every other branch of the
 * fork a tube (abop-2.8a, seed 1: 13 such relays patched, every fork's
 * two other laterals through their skin). */

/* The internode before q in its fork's chain: q's parent where q has no
 * length and is its parent's continuation; else MER_NO_NODE. */
static uint32_t chain_up(const merp_builder *b, uint32_t q)
{
    const mer_node *n = &b->nodes[q];
    if (n->length != 0.0f || n->parent == MER_NO_NODE || b->nodes[n->parent].main_child != q)
        return MER_NO_NODE;
    return n->parent;
}

/* Whether P's tip is J of a fork owned further up its axis: its
 * continuation is living and has no length. */
static bool owned_above(const merp_builder *b, uint32_t P)
{
    uint32_t C = b->nodes[P].main_child;
    return C != MER_NO_NODE && b->nodes[C].alive && b->nodes[C].length == 0.0f;
}

/* Whether internode q is a lateral hop: a lateral of no length, whose own
 * branches leave its parent's J (a guiding-vector node with more children
 * than slots holds the rest on a hop of none, and that hop the rest on
 * another; a string's branch may begin with one). Its fork is its
 * parent's: the laterals it holds, and its hops' in turn, join that fork's
 * (fork_laterals). Planned as a fork of its own, its in shaft had no
 * length before its parent's axis (gv-fig2-small-2, seeds 1-5: 100 of 108
 * forks left tubes, each but a few beside a patched parent fork). */
static bool lateral_hop(const merp_builder *b, uint32_t q)
{
    const mer_node *n = &b->nodes[q];
    return n->alive && n->length == 0.0f && n->parent != MER_NO_NODE && b->nodes[n->parent].main_child != q;
}

/* Whether P's fork is another internode's: one further up its axis
 * (owned_above) or, P a lateral hop, its parent's chain's. */
static bool owned_elsewhere(const merp_builder *b, uint32_t P)
{
    return owned_above(b, P) || lateral_hop(b, P);
}

/* The internode that owns the fork at id's tip (its chain's last, up its
 * continuations of no length) or, id a lateral hop, at its parent's: id
 * where its fork is its own. */
static uint32_t fork_owner(const merp_builder *b, uint32_t id)
{
    for (uint32_t hops = 0; lateral_hop(b, id) && hops <= MAX_SPAN; hops++)
        id = b->nodes[id].parent;
    for (uint32_t hops = 0; owned_above(b, id) && hops <= MAX_SPAN; hops++)
        id = b->nodes[id].main_child;
    return id;
}

#define CHAIN_LATERALS 8 /* fork_laterals gathers at most this many */

/* Adds to lat (n so far, at most CHAIN_LATERALS) the laterals held down the
 * hops from H (lateral_hop: each holds its parent's further laterals) that
 * may be shafts at J (patch_lateral, as thick beside internode `at`). */
static void hop_laterals(const merp_builder *b, const mer_node *at, const float J[3], uint32_t H, uint32_t *lat,
                         uint32_t *n)
{
    for (uint32_t depth = 0; H != MER_NO_NODE && lateral_hop(b, H) && depth <= MAX_SPAN; depth++) {
        uint32_t next = MER_NO_NODE;
        for (int h = 0; h < 2; h++) {
            uint32_t G = b->nodes[H].lateral_child[h];
            if (*n < CHAIN_LATERALS && patch_lateral(b, at, J, G))
                lat[(*n)++] = G;
            if (G != MER_NO_NODE && lateral_hop(b, G))
                next = G;
        }
        H = next;
    }
}

/* The laterals that may be shafts of the patch of the fork owned by P
 * (patch_lateral): P's, then its chain's up from P, each internode's in
 * its own order, each lateral hop's own laterals after it (hop_laterals);
 * at most CHAIN_LATERALS (kept_laterals then chooses). The count. */
static uint32_t fork_laterals(const merp_builder *b, uint32_t P, const float J[3], uint32_t *lat)
{
    uint32_t n = 0;
    for (uint32_t q = P, hops = 0; q != MER_NO_NODE && hops <= MAX_SPAN; q = chain_up(b, q), hops++) {
        const mer_node *at = &b->nodes[q];
        for (int k = 0; k < 2 && n < CHAIN_LATERALS; k++) {
            uint32_t L = at->lateral_child[k];
            if (patch_lateral(b, at, J, L))
                lat[n++] = L;
            hop_laterals(b, at, J, L, lat, &n);
        }
    }
    return n;
}

/* Whether unit directions n and m are too close to parallel for two
 * shafts of one patch (merp_cut_clearance's test). */
static bool alongside(const float n[3], const float m[3])
{
    float c = v3_dot(n, m);
    return c > 0.0f && 1.0f - c * c < 0.04f;
}

/* The laterals of a fork (fork_laterals; lat[0..n), in their order) that
 * its patch holds, in the same order: the thickest first (the first of
 * equals), at most MERP_JUNCTION_LATERALS, none alongside the continuation
 * C or a thicker one kept. A string may draw two branches from one point
 * along one line (abop-1.24c, whose nested brackets start branches of two
 * derivation levels at one J in the same two directions; abop-1.24f's
 * [[X]+X]), which no field tells apart; the one left out stays a tube from
 * J, as the laterals past the field's room do. That a fork of its own may
 * leave one out too (not only a chain's, whose laterals may be more than
 * two) patched 15 of abop-1.24f's 21 unfit forks and 6 of abop-1.24c's 11
 * (seed 1), where merp_cut_clearance found no cut to clear two shafts so
 * close. The count kept. */
static uint32_t kept_laterals(const merp_builder *b, uint32_t *lat, uint32_t n, uint32_t C)
{
    bool kept[CHAIN_LATERALS] = {false};
    for (uint32_t room = MERP_JUNCTION_LATERALS; room > 0; room--) {
        uint32_t t = n;
        for (uint32_t k = 0; k < n; k++) {
            if (kept[k] || (t < n && !(b->nodes[lat[k]].diameter > b->nodes[lat[t]].diameter)))
                continue;
            bool clear = !alongside(b->nodes[lat[k]].dir, b->nodes[C].dir);
            for (uint32_t o = 0; o < n && clear; o++)
                clear = !kept[o] || !alongside(b->nodes[lat[k]].dir, b->nodes[lat[o]].dir);
            if (clear)
                t = k;
        }
        if (t == n)
            break;
        kept[t] = true;
    }
    uint32_t m = 0;
    for (uint32_t k = 0; k < n; k++)
        if (kept[k])
            lat[m++] = lat[k];
    return m;
}

/* The shafts beside its in shaft of the patch of the fork owned by P:
 * *C, the one that goes on, and lat[0..n), its laterals in the order of
 * its field's lateral slots (a run's links name them); n, or -1 when the
 * fork has none to go on. Where P has no living continuation, or with
 * `swap` (plan_one), the thickest of fork_laterals (the first of equals)
 * relays the axis: it goes on, and with `swap` the continuation takes its
 * place among the laterals (-1 unless that is usable and thinner, and
 * kept_laterals keeps it). kept_laterals chooses which laterals the
 * patch keeps. */
static int fork_shafts(const merp_builder *b, uint32_t P, bool swap, uint32_t lat[CHAIN_LATERALS], uint32_t *C)
{
    const mer_node *p = &b->nodes[P];
    float J[3];
    merp_tip_of(p, J);
    *C = p->main_child;
    const uint32_t own = *C; /* the continuation */
    const bool none = *C == MER_NO_NODE || !b->nodes[*C].alive;
    uint32_t nl = fork_laterals(b, P, J, lat);
    if (none || swap) {
        if (nl == 0)
            return -1;
        uint32_t t = 0;
        for (uint32_t k = 1; k < nl; k++)
            if (b->nodes[lat[k]].diameter > b->nodes[lat[t]].diameter)
                t = k;
        uint32_t L = lat[t];
        if (swap) { /* the continuation, thinner, in the relay's place among the laterals */
            if (none || !usable(b, *C, true) || !(b->nodes[*C].diameter < b->nodes[L].diameter))
                return -1;
            lat[t] = *C;
        } else {
            for (uint32_t k = t; k + 1 < nl; k++)
                lat[k] = lat[k + 1];
            nl--;
        }
        *C = L;
    }
    nl = kept_laterals(b, lat, nl, *C);
    /* A swapped continuation left out would leave its axis inside the
     * patch, with no cut ring to go on from (gv-shrub, seed 1). */
    bool kept = !swap;
    for (uint32_t k = 0; k < nl && !kept; k++)
        kept = lat[k] == own;
    return kept ? (int)nl : -1;
}

/* Plans the fork at P's tip into jt (cuts, field) and, with `claim`,
 * claims what its patch covers; false when it does not fit between the
 * patches planned so far.
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
static bool plan_one(merp_builder *b, claims *cl, uint32_t P, bool swap, bool claim, merp_joint *jt)
{
    const mer_node *p = &b->nodes[P];
    uint32_t C = p->main_child;
    const bool none = C == MER_NO_NODE || !b->nodes[C].alive, relay = none || swap;
    float J[3];
    merp_tip_of(p, J);
    if (owned_elsewhere(b, P))
        return false; /* the fork's owner plans it */
    uint32_t lat[CHAIN_LATERALS];
    int got = fork_shafts(b, P, swap, lat, &C);
    if (got < 0)
        return false;
    uint32_t nl = (uint32_t)got;
    if (!usable(b, P, none) || !usable(b, C, true) || (nl == 0 && !relay))
        return false;
    *jt = (merp_joint){.start = {P, C},
                       .cuts = 2,
                       .relay = relay,
                       .cap = true,
                       .forks = 1,
                       .fork_node = {P},
                       .cut_slot = {MERP_SLOT_IN, MERP_LINK_OUT}};
    merp_junction *f = jt->field;
    segment_of(b, P, &f->in);
    segment_of(b, C, &f->out);
    f->in.rb = in_radius(b, jt); /* a relayed parent keeps its own */
    f->w = PCM_WIDTH;
    for (uint32_t k = 0; k < nl; k++) {
        segment_of(b, lat[k], &f->lateral[f->laterals]);
        jt->cut_slot[jt->cuts] = (uint8_t)f->laterals++;
        jt->start[jt->cuts++] = lat[k];
    }
    float h = merp_joint_cell(b, jt);
    /* Each shaft's direction away from J, and its primitives' supports. */
    clearance c = {.prim = NULL};
    for (int i = 0; i < 3; i++)
        c.dir[MERP_CUT_IN][i] = -p->dir[i];
    for (uint32_t s = 1; s < jt->cuts; s++)
        memcpy(c.dir[s], b->nodes[jt->start[s]].dir, sizeof c.dir[s]);
    for (uint32_t s = 0; s < jt->cuts; s++) {
        const merp_seg *g = s == 0 ? &f->in : s == 1 ? &f->out : &f->lateral[s - 2];
        c.R[s] = SUPPORT_SEEN * merp_seg_support(g);
    }
    float need[MERP_PATCH_CUTS];
    if (!settle_cuts(b, cl, jt, &c, &h, need))
        return false;
    if (claim)
        place_cuts(b, cl, need, h, true, jt);
    float ridge_up[3];
    memcpy(ridge_up, b->nodes[C].dir, sizeof ridge_up);
    /* The bark ages with the oldest lateral (G04 Fig. 7). The parent's bud
     * scale scar exists only where J ends one season's shoot and C begins the
     * next's, and ages with C's shoot. */
    uint32_t born = b->nodes[C].born; /* a relay's own, where it has no lateral */
    for (uint32_t k = 0; k < f->laterals; k++)
        born = k == 0 || b->nodes[jt->start[2 + k]].born < born ? b->nodes[jt->start[2 + k]].born : born;
    merp_junction_age(f, ridge_up, years_since(b, born));
    f->scar_weight = b->nodes[C].born == p->born
                         ? 0.0f
                         : merp_junction_scar_weight(years_since(b, b->nodes[C].born));
    return true;
}

/* Whether the axis from C up to P (both included, along main children) may
 * lie inside a run's patch: living internodes, no tip's cone (but P's, with
 * `cone`: a relayed fork's, whose tip the patch covers), claimed by no
 * patch, every boundary between them within STRAIGHT × r of the line from
 * J0 to J1 (the run's segment there). Where a boundary is not, cl->bend is
 * the internode whose tip is the one farthest off (straight's elbow). */
static bool run_middle(const merp_builder *b, claims *cl, uint32_t C, uint32_t P, bool cone, const float J0[3],
                       const float J1[3], float r)
{
    float u[3], farthest = 0.0f;
    for (int a = 0; a < 3; a++)
        u[a] = J1[a] - J0[a];
    if (!v3_normalize(u))
        return false;
    uint32_t bend = MER_NO_NODE;
    for (uint32_t id = C, passed = 0;; id = b->nodes[id].main_child, passed++) {
        if (!usable(b, id, cone && id == P) || passed > MAX_SPAN)
            return false;
        if (cl->lo[id] > 0.0f || cl->hi[id] < b->nodes[id].length) {
            cl->blocker = cl->lo[id] > 0.0f ? cl->own_lo[id] : cl->own_hi[id];
            return false;
        }
        if (id == P) {
            cl->bend = bend;
            return bend == MER_NO_NODE;
        }
        float q[3], e[3];
        merp_tip_of(&b->nodes[id], q);
        for (int a = 0; a < 3; a++)
            q[a] -= J0[a];
        v3_cross(q, u, e);
        if (v3_len(e) > STRAIGHT * r && v3_len(e) > farthest)
            farthest = v3_len(e), bend = id;
    }
}

/* How far the axis from internode id up its continuations reaches: its
 * length there, INFINITY past MAX_SPAN internodes. A shaft on a short axis
 * (a bush's few internodes) ends inside its patch (follow), so the run's
 * other cuts need clear only that much of it. */
static float axis_reach(const merp_builder *b, uint32_t id)
{
    float arc = 0.0f;
    for (uint32_t passed = 0; id != MER_NO_NODE && b->nodes[id].alive; id = b->nodes[id].main_child, passed++) {
        if (passed > MAX_SPAN)
            return INFINITY;
        arc += b->nodes[id].length;
    }
    return arc;
}

/* Internode id wholly claimed by `owner` (UINT32_MAX: freed). */
static void claim_whole(const merp_builder *b, claims *cl, uint32_t id, uint32_t owner)
{
    bool set = owner != UINT32_MAX;
    cl->lo[id] = set ? b->nodes[id].length : 0.0f, cl->hi[id] = set ? 0.0f : INFINITY;
    cl->own_lo[id] = cl->own_hi[id] = owner;
}

/* Claims for joint `owner` (or, with UINT32_MAX, frees) what jt's patch
 * covers: each shaft's internodes from J to its cut (as follow marks them),
 * a run's axes between its forks. */
static void claim_joint(const merp_builder *b, claims *cl, const merp_joint *jt, uint32_t owner)
{
    bool set = owner != UINT32_MAX;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        bool back = s == MERP_CUT_IN;
        uint32_t id = jt->start[s];
        for (; id != jt->node[s]; id = back ? b->nodes[id].parent : b->nodes[id].main_child)
            claim_whole(b, cl, id, owner);
        if (!merp_cut_has_ring(jt, s)) /* its last internode too (follow: capped, or on the base) */
            claim_whole(b, cl, id, owner);
        else if (back)
            cl->hi[id] = set ? jt->at[s] : INFINITY, cl->own_hi[id] = owner;
        else
            cl->lo[id] = set ? jt->at[s] : 0.0f, cl->own_lo[id] = owner;
    }
    for (uint32_t i = 1; i < jt->forks; i++)
        for (uint32_t id = jt->link_start[i];; id = b->nodes[id].main_child) {
            claim_whole(b, cl, id, owner);
            if (id == jt->fork_node[i])
                break;
        }
}

/* Which shaft of the patch of the fork owned by P begins with internode
 * L, another than P's continuation (fork_shafts): its lateral slot,
 * MERP_LINK_OUT where L relays the axis, or -1 when the patch holds none
 * that begins with L. */
static int shaft_slot(const merp_builder *b, uint32_t P, uint32_t L)
{
    uint32_t lat[CHAIN_LATERALS], C;
    int n = fork_shafts(b, P, false, lat, &C);
    if (n >= 0 && C == L)
        return MERP_LINK_OUT;
    for (int k = 0; k < n; k++)
        if (lat[k] == L)
            return k;
    return -1;
}

/* Whether a run's fork at internode id's tip is an elbow: no living
 * lateral leaves it (bare_internode) and its axis goes on (a shaft's bend,
 * plan_merged's `bend`); no fork a run gains. */
static bool elbow(const merp_builder *b, uint32_t id)
{
    uint32_t C = b->nodes[id].main_child;
    return bare_internode(b, id) && C != MER_NO_NODE && b->nodes[C].alive;
}

/* Plans a run of K forks (the internodes P[0..K), each ending at its fork's
 * J and going on to a continuation; fork i > 0 going on from fork
 * link[i].from up the axis that begins with internode start[i]: its
 * continuation or lateral link[i].slot; listed as merp_jprep_init_run
 * needs) as one patch into jt. Forks a few radii apart (a whorl's
 * neighbours, a season's short internodes, a fork near the base of
 * another's lateral) do not fit as single patches: each one's cut would fall
 * inside the other's. The patch holds the first fork's in shaft, each
 * axis's out shaft above its last fork, every lateral no fork goes on up,
 * and the axes between the forks (straight, inside the patch). A fork with
 * no living continuation (a sympodium's flowered tip an internode above the
 * fork it goes on from; a string's axis that ends in branches, as
 * abop-1.24b's in [-F][F]) is relayed as plan_one relays it: its thickest
 * lateral goes on as its axis, up to the run's next fork on it (link slot
 * MERP_LINK_OUT) or to its out shaft, its tip inside the patch. A fork's
 * laterals are fork_shafts', a chain's or a hop's among them. Its cuts
 * are placed as plan_one's, clear of every primitive of the run. False when
 * it does not fit (cl->blocker: the joint in the way, if one is;
 * cl->stopper: the fork up a shaft's short axis, if that stopped it) or would
 * need cells finer than RUN_FINEST per its in shaft's radius on a grid of
 * more than RUN_FINE_CELLS. Claims
 * nothing: the caller does (claim_joint). */
static bool plan_run(merp_builder *b, claims *cl, const uint32_t *P, const merp_link *link, const uint32_t *start,
                     uint32_t K, merp_joint *jt)
{
    assert(K >= 2 && K <= MERP_RUN_FORKS);
    for (uint32_t i = 0; i < K; i++)
        for (uint32_t j = i + 1; j < K; j++)
            assert(P[i] != P[j]);
    *jt = (merp_joint){.forks = K, .start = {P[0]}, .cuts = 2, .cap = true, .cut_slot = {MERP_SLOT_IN, MERP_LINK_OUT}};
    float J[MERP_RUN_FORKS][3];
    int group[MERP_RUN_FORKS], groups = 0;
    bool goes_on[MERP_RUN_FORKS] = {false}; /* a fork goes on from it up its continuation (or relay) */
    bool relayed[MERP_RUN_FORKS];
    for (uint32_t i = 1; i < K; i++)
        goes_on[link[i].from] |= link[i].slot == MERP_LINK_OUT;
    /* Each fork's continuation (out[i]) and laterals (lat[i]), as plan_one
     * has them (fork_shafts: its hops' laterals too): a fork with no living
     * continuation is relayed, its thickest lateral going on (to its out
     * cut, or up to the run's next fork on it), its tip in the patch. */
    uint32_t out[MERP_RUN_FORKS], lat[MERP_RUN_FORKS][MERP_JUNCTION_LATERALS], laterals = 0;
    for (uint32_t i = 0; i < K; i++) {
        const mer_node *p = &b->nodes[P[i]];
        uint32_t C = p->main_child, shafts[CHAIN_LATERALS];
        relayed[i] = C == MER_NO_NODE || !b->nodes[C].alive;
        int got = fork_shafts(b, P[i], false, shafts, &C);
        if (got < 0)
            return false;
        uint32_t nl = (uint32_t)got;
        assert(nl <= MERP_JUNCTION_LATERALS); /* (kept_laterals keeps so many) */
        memcpy(lat[i], shafts, nl * sizeof *shafts);
        /* (an axis a fork goes on up is run_middle's to check). A fork of
         * the run may hold no lateral: one up a short axis whose laterals are
         * twigs or too thin for a shaft (merp_mesh_joints_plan's stoppers),
         * or whose one is alongside its continuation (kept_laterals). Its
         * laterals are tubes from J, as at a fork no patch serves. */
        if (!usable(b, P[i], relayed[i]) || !usable(b, C, true))
            return false;
        laterals += nl + relayed[i];
        out[i] = C;
        merp_tip_of(p, J[i]);
        jt->fork_node[i] = P[i], jt->link[i] = link[i], jt->link_start[i] = start[i];
        group[i] = i == 0 || link[i].slot != MERP_LINK_OUT ? groups++ : group[link[i].from];
        merp_junction *f = &jt->field[i];
        f->w = PCM_WIDTH;
        for (uint32_t k = 0; k < nl; k++)
            segment_of(b, lat[i][k], &f->lateral[f->laterals++]);
    }
    if (laterals == 0)
        return false; /* no branch to blend */
    segment_of(b, P[0], &jt->field[0].in);
    jt->field[0].in.rb = in_radius(b, jt);
    for (uint32_t i = 1; i < K; i++) { /* the straight axis from the fork it goes on from */
        uint32_t from = link[i].from;
        merp_seg *g = &jt->field[i].in;
        *g = (merp_seg){.ra = merp_node_radius(b, start[i]), .rb = merp_node_end_radius(b, P[i])};
        memcpy(g->a, J[from], sizeof g->a);
        memcpy(g->b, J[i], sizeof g->b);
        if (!run_middle(b, cl, start[i], P[i], relayed[i], J[from], J[i], g->ra))
            return false;
        if (link[i].slot == MERP_LINK_OUT)
            jt->field[from].out = *g;
        else
            jt->field[from].lateral[link[i].slot] = *g;
    }
    /* The shafts: the first fork's in (cut 0), each axis's out above its last
     * fork (the first axis's is cut 1), every lateral no fork goes on up. */
    for (uint32_t i = 0; i < K; i++) {
        bool up[MERP_JUNCTION_LATERALS] = {false};
        for (uint32_t c = 1; c < K; c++)
            if (link[c].from == i && link[c].slot != MERP_LINK_OUT)
                up[link[c].slot] = true;
        for (uint32_t k = 0; k < jt->field[i].laterals; k++)
            if (!up[k]) {
                /* in and out, each fork's laterals (at most MERP_JUNCTION_LATERALS)
                 * less one per lateral a group goes on up, and that group's out:
                 * at most MERP_PATCH_CUTS, the forks being distinct */
                assert(jt->cuts < MERP_PATCH_CUTS);
                jt->cut_fork[jt->cuts] = (uint8_t)i, jt->cut_slot[jt->cuts] = (uint8_t)k;
                jt->start[jt->cuts++] = lat[i][k];
            }
        if (goes_on[i])
            continue;
        assert(group[i] == 0 || jt->cuts < MERP_PATCH_CUTS);
        uint32_t s = group[i] == 0 ? MERP_CUT_OUT : jt->cuts++;
        jt->cut_fork[s] = (uint8_t)i, jt->cut_slot[s] = MERP_LINK_OUT, jt->start[s] = out[i];
        segment_of(b, out[i], &jt->field[i].out);
    }
    float h = merp_joint_cell(b, jt);
    /* The primitives: each shaft from its J, then the axes between the forks. */
    run_prim prim[MERP_PATCH_CUTS + MERP_RUN_FORKS];
    uint32_t n = jt->cuts;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        uint32_t i = jt->cut_fork[s], k = jt->cut_slot[s], l;
        const merp_seg *g = merp_joint_shaft(jt, s, NULL, &l);
        const float *dir = b->nodes[jt->start[s]].dir;
        run_prim *q = &prim[s];
        *q = (run_prim){.len = s == MERP_CUT_IN ? INFINITY : axis_reach(b, jt->start[s]) + EXTEND * h,
                        .R = SUPPORT_SEEN * merp_seg_support(g), .axis = k < MERP_SLOT_IN ? -1 : group[i]};
        memcpy(q->o, J[i], sizeof q->o);
        for (int a = 0; a < 3; a++)
            q->m[a] = s == MERP_CUT_IN ? -dir[a] : dir[a];
    }
    for (uint32_t i = 1; i < K; i++, n++) {
        const merp_seg *g = &jt->field[i].in;
        run_prim *q = &prim[n];
        *q = (run_prim){.R = SUPPORT_SEEN * merp_seg_support(g), .axis = group[i]};
        memcpy(q->o, g->a, sizeof q->o);
        for (int a = 0; a < 3; a++)
            q->m[a] = g->b[a] - g->a[a];
        q->len = v3_len(q->m);
        v3_normalize(q->m);
    }
    const clearance c = {.prim = prim, .prims = n};
    float need[MERP_PATCH_CUTS];
    /* A run across two axes can span much: its grid must fit. Its cells are
     * its thinnest shaft's over the whole run: a thick trunk fork's run up a
     * lateral to a fork with thin laterals may need 17 a trunk radius and
     * cost as much as forty single forks; such a run is not planned where
     * its grid is large too. Refused wherever its cells were finer than
     * RUN_FINEST per radius, runs left 71 of fig6-sylleptic's forks (seeds
     * 1-5) tubes, those forks' laterals far thinner than their parents;
     * admitted on grids of up to RUN_FINE_CELLS, 62, their junctions meshed
     * in 7 % more time (seed 1); on any grid, 52 at 36 % more (a run of five
     * forks on 7.9 M cells, 134 ms, graded), and a guiding-vector tree's
     * (gv-fig4-4000) at 140 % more for 11 forks. */
    merp_grid grid;
    if (!settle_cuts(b, cl, jt, &c, &h, need) || !merp_joint_grid(b, jt, h, 0.0f, &grid))
        return false;
    uint64_t cells = (uint64_t)grid.n[0] * grid.n[1] * grid.n[2];
    if ((merp_node_radius(b, P[0]) > RUN_FINEST * h && cells > RUN_FINE_CELLS) ||
        (K > RUN_FORKS && cells > RUN_MANY_CELLS))
        return false;
    /* Each fork's bark ages as a single fork's (plan_one). An elbow is no
     * fork, and draws no bud scale scar: neither do the tubes round it. */
    for (uint32_t i = 0; i < K; i++) {
        const bool bend = elbow(b, P[i]);
        jt->elbows |= (uint64_t)bend << i;
        merp_junction *f = &jt->field[i];
        const mer_node *C = &b->nodes[out[i]];
        uint32_t born = C->born; /* a relay's own, where it has no lateral */
        for (uint32_t k = 0; k < f->laterals; k++)
            born = k == 0 || b->nodes[lat[i][k]].born < born ? b->nodes[lat[i][k]].born : born;
        merp_junction_age(f, C->dir, years_since(b, born));
        f->scar_weight = bend || C->born == b->nodes[P[i]].born ? 0.0f
                                                                : merp_junction_scar_weight(years_since(b, C->born));
    }
    return true;
}

/* A fork that may get a patch (id), and its thickest lateral's diameter (key). */
typedef merp_ranked candidate;

int merp_ranked_cmp(const void *x, const void *y)
{
    const merp_ranked *a = x, *b = y;
    if (a->key != b->key)
        return a->key > b->key ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* The diameter of the thickest living lateral of LATERAL_RATIO at the
 * fork at id's tip, over its chain (fork_laterals); 0 where it has none.
 * *thick gets the chain's thickest internode. */
static float fork_key(const merp_builder *b, uint32_t id, float *thick)
{
    float key = 0.0f;
    *thick = 0.0f;
    for (uint32_t q = id, hops = 0; q != MER_NO_NODE && hops <= MAX_SPAN; q = chain_up(b, q), hops++) {
        *thick = fmaxf(*thick, b->nodes[q].diameter);
        for (int k = 0; k < 2; k++) {
            uint32_t L = b->nodes[q].lateral_child[k];
            if (L != MER_NO_NODE && b->nodes[L].alive && b->nodes[L].diameter >= LATERAL_RATIO * b->nodes[q].diameter)
                key = fmaxf(key, b->nodes[L].diameter);
        }
    }
    return key;
}

/* What a fork's patch is worth where runs and forks compete for shafts
 * (plan_merged): the bark it reshapes, its thickest lateral's diameter by
 * its parent's (fork_key: the thickest internode of its chain). Counted as
 * forks, a trunk's fork lost to two forks of a branch half as thick
 * (fig7-bh-0.54, seed 1: the trunk's forks 9, 10, 22 and 51 were tubes). */
static double fork_weight(const merp_builder *b, uint32_t id)
{
    float thick, key = fork_key(b, id, &thick);
    return (double)key * (double)thick; /* exact in double; sums of a few round far below a fork's weight */
}

/* The forks at least `threshold` thick with a lateral of LATERAL_RATIO,
 * thickest lateral first (fork_key; ties by id): where patches compete for
 * the short internodes of an axis, the thickest branches get them. *count
 * is set. */
static candidate *candidates(const merp_builder *b, float threshold, uint32_t *count)
{
    uint32_t n = 0;
    candidate *c = merp_malloc((b->node_count ? b->node_count : 1) * sizeof *c);
    if (c == NULL)
        return NULL;
    for (uint32_t id = 0; id < b->node_count; id++) {
        if (!b->nodes[id].alive || owned_elsewhere(b, id))
            continue;
        float thick, key = fork_key(b, id, &thick);
        if (key > 0.0f && thick >= threshold)
            c[n++] = (candidate){key, id};
    }
    qsort(c, n, sizeof *c, merp_ranked_cmp);
    *count = n;
    return c;
}

/* Whether P's tip is a fork a patch may serve: P at least `threshold`
 * thick, with a lateral that may be a shaft of its patch. */
static bool is_fork(const merp_builder *b, uint32_t P, float threshold)
{
    const mer_node *p = &b->nodes[P];
    if (!p->alive || p->diameter < threshold)
        return false;
    float J[3];
    merp_tip_of(p, J);
    uint32_t lat[CHAIN_LATERALS];
    return fork_laterals(b, P, J, lat) > 0;
}

/* The forks a run is being gathered from (plan_merged), in no order. */
typedef struct gathered {
    uint32_t fork[MERP_RUN_FORKS], n;
    float threshold;
} gathered;

static int gathered_index(const gathered *g, uint32_t id)
{
    for (uint32_t i = 0; i < g->n; i++)
        if (g->fork[i] == id)
            return (int)i;
    return -1;
}

/* From fork f down its axis (and down the axis it is a lateral of, and so
 * on) to the first fork of `to` (or, with `to` NULL, to fork `target`):
 * the index reached (0 with a target), how the walk arrived (*link: up
 * that fork's continuation, or relay, or its patch lateral (shaft_slot),
 * *start: the axis's first internode), and the forks passed on the way
 * (between, at most `room`). A chain's or a hop's lateral is crossed as a
 * lateral of the fork that owns it (fork_owner), and the chain's
 * internodes below its owner as that fork's J.
 * -1 when the walk leaves the tree, crosses a lateral no patch holds, or
 * passes more forks than there is room for. */
static int walk_down(const merp_builder *b, uint32_t f, const gathered *to, uint32_t target, float threshold,
                     uint32_t room, uint32_t *between, uint32_t *nb, merp_link *link, uint32_t *start)
{
    *nb = 0;
    for (uint32_t id = f, passed = 0; passed <= 2 * MAX_SPAN; passed++) {
        uint32_t p = b->nodes[id].parent;
        if (p == MER_NO_NODE)
            return -1;
        uint8_t slot = MERP_LINK_OUT;
        if (b->nodes[p].main_child != id) { /* a lateral: the run crosses only a patch's */
            p = fork_owner(b, p); /* a hop's or a chain's laterals are its owner's */
            int k = shaft_slot(b, p, id);
            if (k < 0)
                return -1;
            slot = (uint8_t)k;
        } else if (owned_above(b, p)) { /* down a chain: the same J as id's fork */
            id = p;
            continue;
        }
        int at = to != NULL ? gathered_index(to, p) : p == target ? 0 : -1;
        if (at >= 0) {
            *link = (merp_link){0, slot}, *start = id;
            return at;
        }
        if (slot != MERP_LINK_OUT || is_fork(b, p, threshold)) { /* the run passes its J */
            if (!is_fork(b, p, threshold) || *nb == room)
                return -1;
            between[(*nb)++] = p;
        }
        id = p;
    }
    return -1;
}

/* Adds fork F to the gathering with the forks between it and the others:
 * down from F to them, or down from one of them to F. False when F is on
 * no such way, or the run would have more than MERP_RUN_FORKS forks. */
static bool gather(const merp_builder *b, gathered *g, uint32_t F)
{
    F = fork_owner(b, F); /* (a stopper may be a chain's or a hop's) */
    if (gathered_index(g, F) >= 0)
        return true;
    uint32_t between[MERP_RUN_FORKS], nb, start, room = MERP_RUN_FORKS - 1 - g->n;
    merp_link link;
    if (g->n == MERP_RUN_FORKS)
        return false;
    bool found = walk_down(b, F, g, 0, g->threshold, room, between, &nb, &link, &start) >= 0;
    for (uint32_t i = 0; i < g->n && !found; i++)
        found = walk_down(b, g->fork[i], NULL, F, g->threshold, room, between, &nb, &link, &start) >= 0;
    if (!found)
        return false;
    g->fork[g->n++] = F;
    for (uint32_t i = 0; i < nb; i++) /* a walk from a gathered fork may pass others */
        if (gathered_index(g, between[i]) < 0)
            g->fork[g->n++] = between[i];
    return true;
}

/* Lists the gathered forks as plan_run takes them: the one the others go
 * on from first, each axis's forks together up it, a fork up a lateral
 * after the fork it goes on from; their links and the first internode of
 * the axis each goes on up. False unless the forks make one tree whose
 * ways between them pass no other fork. */
static bool order_run(const merp_builder *b, const gathered *g, uint32_t *P, merp_link *link, uint32_t *start)
{
    int from[MERP_RUN_FORKS], root = -1;
    merp_link via[MERP_RUN_FORKS];
    uint32_t first[MERP_RUN_FORKS];
    for (uint32_t i = 0; i < g->n; i++) {
        first[i] = MER_NO_NODE; /* the root's: it goes on from none */
        uint32_t between[1], nb;
        from[i] = walk_down(b, g->fork[i], g, 0, g->threshold, 0, between, &nb, &via[i], &first[i]);
        if (from[i] < 0) {
            if (root >= 0)
                return false; /* two trees */
            root = (int)i;
        }
    }
    if (root < 0)
        return false;
    /* Axis by axis from the root: each one's forks up its continuations, then
     * the axes up their laterals, in the order reached. */
    int order[MERP_RUN_FORKS], at[MERP_RUN_FORKS];
    uint32_t n = 0, queue[MERP_RUN_FORKS], qn = 0;
    queue[qn++] = (uint32_t)root;
    for (uint32_t q = 0; q < qn; q++) {
        for (int f = (int)queue[q]; f >= 0;) {
            at[f] = (int)n, order[n++] = f;
            int next = -1;
            for (uint32_t i = 0; i < g->n; i++)
                if (from[i] == f && via[i].slot == MERP_LINK_OUT)
                    next = (int)i;
            for (uint32_t k = 0; k < MERP_JUNCTION_LATERALS; k++)
                for (uint32_t i = 0; i < g->n; i++)
                    if (from[i] == f && via[i].slot == k)
                        queue[qn++] = i;
            f = next;
        }
    }
    if (n != g->n)
        return false;
    for (uint32_t i = 0; i < n; i++) {
        int f = order[i];
        P[i] = g->fork[f], start[i] = first[f];
        link[i] = i == 0 ? (merp_link){0, MERP_LINK_OUT} : (merp_link){(uint8_t)at[from[f]], via[f].slot};
    }
    return true;
}

void merp_joint_forget(merp_builder *b, merp_joint *jt)
{
    jt->ok = false;
    for (uint32_t i = 0; i < jt->forks; i++) {
        b->joint_at[jt->fork_node[i]] = UINT32_MAX;
        if (i > 0 && jt->link[i].slot != MERP_LINK_OUT)
            b->lateral_in[jt->link_start[i]] = UINT32_MAX;
    }
    if (jt->base)
        b->lateral_in[jt->node[MERP_CUT_IN]] = UINT32_MAX;
    else
        b->cut_begin[jt->node[MERP_CUT_IN]] = UINT32_MAX;
    for (uint32_t s = 1; s < jt->cuts; s++) {
        if (!jt->capped[s])
            b->cut_end[jt->node[s]] = UINT32_MAX;
        if (merp_joint_begins_axis(b->nodes, jt, s))
            b->lateral_in[jt->start[s]] = UINT32_MAX;
    }
}

/* Joint `at` (jt) in the maps tube.c follows, and its claims. */
static void remember(merp_builder *b, claims *cl, const merp_joint *jt, uint32_t at)
{
    claim_joint(b, cl, jt, at);
    for (uint32_t i = 0; i < jt->forks; i++) {
        b->joint_at[jt->fork_node[i]] = at;
        uint32_t L = jt->link_start[i];
        if (i > 0 && b->nodes[b->nodes[L].parent].main_child != L) /* an axis that begins in the patch, uncut: a lateral or a relay */
            b->lateral_in[L] = at * MERP_PATCH_CUTS;
    }
    if (jt->base) /* the trunk's axis starts in the patch, which holds its base */
        b->lateral_in[jt->node[MERP_CUT_IN]] = at * MERP_PATCH_CUTS + MERP_CUT_IN;
    else
        b->cut_begin[jt->node[MERP_CUT_IN]] = at;
    for (uint32_t s = 1; s < jt->cuts; s++) {
        if (!jt->capped[s]) /* a capped shaft's axis stays inside to its end (tube.c) */
            b->cut_end[jt->node[s]] = at * MERP_PATCH_CUTS + s;
        if (merp_joint_begins_axis(b->nodes, jt, s)) /* an axis that begins in the patch */
            b->lateral_in[jt->start[s]] = at * MERP_PATCH_CUTS + s;
    }
}

/* The J a shaft of a patch passes in internode id, wholly inside it: the
 * tip of an out or lateral shaft's internode, the base of an in shaft's
 * (its parent's fork; MER_NO_NODE at the root). */
static uint32_t passed_fork(const merp_builder *b, uint32_t s, uint32_t id)
{
    return s == MERP_CUT_IN ? b->nodes[id].parent : id;
}

static uint32_t shaft_next(const merp_builder *b, uint32_t s, uint32_t id)
{
    return s == MERP_CUT_IN ? b->nodes[id].parent : b->nodes[id].main_child;
}

/* The forks jt's patch would leave tubes that could have a patch of their
 * own, weighed (fork_weight): forks its shafts pass (not its own), not yet
 * tried, for which plan_one finds room with the claims as they are. Each
 * counted once (cl->tried marks them 2 meanwhile), into *np, the first
 * MERP_RUN_FORKS of them into passed. */
static double swallows(merp_builder *b, claims *cl, const merp_joint *jt, float threshold, uint32_t *passed,
                       uint32_t *np)
{
    double weight = 0.0;
    *np = 0;
    for (uint32_t s = 0; s < jt->cuts; s++)
        for (uint32_t id = jt->start[s]; id != jt->node[s]; id = shaft_next(b, s, id)) {
            uint32_t F = passed_fork(b, s, id);
            bool own = false;
            for (uint32_t i = 0; i < jt->forks; i++)
                own |= jt->fork_node[i] == F;
            if (!own && F != MER_NO_NODE && !cl->tried[F] && is_fork(b, F, threshold) &&
                plan_one(b, cl, F, false, false, cl->probe)) {
                cl->tried[F] = 2, weight += fork_weight(b, F);
                if (*np < MERP_RUN_FORKS)
                    passed[*np] = F;
                ++*np;
            }
        }
    for (uint32_t s = 0; s < jt->cuts; s++)
        for (uint32_t id = jt->start[s]; id != jt->node[s]; id = shaft_next(b, s, id)) {
            uint32_t F = passed_fork(b, s, id);
            if (F != MER_NO_NODE && cl->tried[F] == 2)
                cl->tried[F] = 0;
        }
    return weight;
}

/* Whether run jt patches forks that outweigh those it would leave tubes
 * (swallows). Greedy as the planner is, a run may take in a fork or two at
 * the price of more that come later: its shafts reach far, clear of every
 * primitive of the run, and pass thinner forks' J (default's root run took
 * in forks 0-3 and left 4-8 tubes). Weighed with the claims as they are
 * without it: the joints it takes in (taken[0 .. nt), released) hold theirs
 * meanwhile, and a fork is gained only where none of them patched it (an
 * elbow is none). The forks it would leave tubes are listed in passed
 * (*np, as swallows has them). */
static bool outweighs(merp_builder *b, claims *cl, const merp_joint *jt, float threshold, const uint32_t *taken,
                      uint32_t nt, uint32_t *passed, uint32_t *np)
{
    double gained = 0.0;
    for (uint32_t i = 0; i < jt->forks; i++) {
        uint32_t F = jt->fork_node[i];
        gained += b->joint_at[F] != UINT32_MAX || elbow(b, F) ? 0.0 : fork_weight(b, F);
    }
    for (uint32_t t = 0; t < nt; t++)
        claim_joint(b, cl, &b->joints[taken[t]], taken[t]);
    double lost = swallows(b, cl, jt, threshold, passed, np);
    for (uint32_t t = 0; t < nt; t++)
        claim_joint(b, cl, &b->joints[taken[t]], UINT32_MAX);
    return lost < gained;
}

/* Plans P's fork, which fits no patch of its own because joint X's is in
 * the way, as a run (plan_run) with X's forks and every fork on the ways
 * between them, taking in the joints planned for any of them (released,
 * into taken[0 .. *nt)); while the run meets another joint, it grows to
 * take that in too, up to MERP_RUN_FORKS forks. Where a shaft's axis ends
 * before its cut but past laterals of its own (a bush's short lateral with
 * its twigs, which no shaft may end inside past), `stop` is the first fork
 * up it (MER_NO_NODE: none): the run takes that fork in, and each fork
 * that stops it next, however thin (the gathering's threshold drops to 0),
 * so the short axis ends inside the run's patch with all its forks. Where a
 * shaft's axis (or a run's between two forks) bends off one segment,
 * `bend` is the internode at whose tip it bends most (straight): the run
 * takes it in as an elbow (a fork with no lateral, elbow), its shaft two
 * segments, and each bend that stops it next (a guiding-vector tree's
 * axes bend at every node: gv-fig4-4000, seed 1, left 40 forks tubes
 * without elbows, 16 with them). A relayed fork it takes in
 * is planned as plan_run has it: relayed where it has no living
 * continuation, else as it grew (a swap's continuation, which did not fit a
 * patch of its own, may fit the run's). Where the run would leave forks
 * its shafts pass tubes, forks that would fit alone and are worth as much
 * as the forks it patches that the joints it takes in did not (outweighs,
 * fork_weight), it takes those in too (the run from a fork to the next up
 * the trunk passed its lateral's fork: default, seed 2, whose second fork
 * stayed tubes for a thinner one, as three of default's and
 * fig13-tropism-late's seeds 1-5 did). False when it does not fit (X's
 * forks on no way from P, too many forks, plan_run's refusals) or would
 * leave such forks tubes however it grows: the claims are then as they
 * were. */
static bool plan_merged(merp_builder *b, claims *cl, uint32_t P, float threshold, uint32_t X, uint32_t stop,
                        uint32_t bend, merp_joint *jt, uint32_t *taken, uint32_t *nt)
{
    gathered g = {.fork = {P}, .n = 1, .threshold = stop != MER_NO_NODE ? 0.0f : threshold};
    bool ok = false, stuck = false;
    uint32_t passed[MERP_RUN_FORKS], np = 0; /* the forks the last plan would leave tubes (outweighs) */
    *nt = 0;
    while (!ok && !stuck && (X != UINT32_MAX || stop != MER_NO_NODE || bend != MER_NO_NODE || np > 0)) {
        stuck = np > MERP_RUN_FORKS; /* (more than a run holds) */
        for (uint32_t i = 0; i < np && !stuck; i++)
            stuck = !gather(b, &g, passed[i]);
        for (uint32_t i = 0; X != UINT32_MAX && i < b->joints[X].forks && !stuck; i++)
            stuck = !gather(b, &g, b->joints[X].fork_node[i]);
        if (stop != MER_NO_NODE && !stuck)
            stuck = !gather(b, &g, stop);
        if (bend != MER_NO_NODE && !stuck) { /* an elbow: no way on where it was one already */
            uint32_t had = g.n;
            stuck = !gather(b, &g, bend) || (g.n == had && X == UINT32_MAX && stop == MER_NO_NODE);
        }
        /* every joint planned for a fork of the run joins it */
        for (bool grown = true; grown && !stuck;) {
            grown = false;
            for (uint32_t i = 0; i < g.n && !stuck; i++) {
                uint32_t j = b->joint_at[g.fork[i]], t = 0;
                while (t < *nt && taken[t] != j)
                    t++;
                if (j == UINT32_MAX || t < *nt)
                    continue;
                for (uint32_t k = 0; k < b->joints[j].forks && !stuck; k++)
                    stuck = !gather(b, &g, b->joints[j].fork_node[k]);
                claim_joint(b, cl, &b->joints[j], UINT32_MAX);
                taken[(*nt)++] = j;
                grown = true;
            }
        }
        uint32_t R[MERP_RUN_FORKS], start[MERP_RUN_FORKS];
        merp_link link[MERP_RUN_FORKS];
        stuck = stuck || !order_run(b, &g, R, link, start);
        cl->blocker = UINT32_MAX, cl->stopper = MER_NO_NODE, cl->bend = MER_NO_NODE;
        ok = !stuck && plan_run(b, cl, R, link, start, g.n, jt);
        X = cl->blocker, stop = cl->stopper, bend = cl->bend, np = 0;
        if (ok && !outweighs(b, cl, jt, threshold, taken, *nt, passed, &np))
            ok = false, X = UINT32_MAX, stop = bend = MER_NO_NODE; /* grown by the forks passed, if any */
        if (stop != MER_NO_NODE && g.threshold > 0.0f && !ok && !stuck) {
            /* The forks up a short axis, however thin: gathered again, so
             * that the thin forks the ways between them passed before are
             * taken in too (else order_run found such a way passing a fork
             * of the run's no more, and two trees: abop-1.24d, seed 1, 18
             * forks left tubes for that). */
            gathered again = {.fork = {g.fork[0]}, .n = 1, .threshold = 0.0f};
            for (uint32_t i = 1; i < g.n && !stuck; i++)
                stuck = !gather(b, &again, g.fork[i]);
            g = again;
        }
    }
    /* The joints taken in hold their claims again; a run planned releases
     * them (the caller forgets those joints). */
    for (uint32_t t = 0; t < *nt; t++)
        claim_joint(b, cl, &b->joints[taken[t]], taken[t]);
    if (ok)
        for (uint32_t t = 0; t < *nt; t++)
            claim_joint(b, cl, &b->joints[taken[t]], UINT32_MAX);
    return ok;
}

mer_result merp_mesh_joints_plan(merp_builder *b, mer_error *err)
{
    size_t n = b->node_count, m = n ? n : 1;
    b->joint_at = merp_malloc(m * sizeof *b->joint_at);
    b->lateral_in = merp_malloc(m * sizeof *b->lateral_in);
    b->cut_end = merp_malloc(m * sizeof *b->cut_end);
    b->cut_begin = merp_malloc(m * sizeof *b->cut_begin);
    claims cl = {merp_malloc(m * sizeof *cl.lo), merp_malloc(m * sizeof *cl.hi),
                 merp_malloc(m * sizeof *cl.own_lo), merp_malloc(m * sizeof *cl.own_hi), UINT32_MAX,
                 MER_NO_NODE, MER_NO_NODE, merp_calloc(m, 1), merp_malloc(sizeof(merp_joint))};
    merp_joint *jt = merp_malloc(sizeof *jt); /* the joint being planned (off the stack, as cl.probe) */
    float threshold = b->opt.junction_diameter > 0.0f ? b->opt.junction_diameter
                                                      : JUNCTION_DIAMETER_FRACTION * b->max_diameter;
    uint32_t cap = 0, count = 0;
    candidate *c = candidates(b, threshold, &count);
    mer_result rc = MER_OK;
    if (!b->joint_at || !b->lateral_in || !b->cut_end || !b->cut_begin || !cl.lo || !cl.hi || !cl.own_lo ||
        !cl.own_hi || !cl.tried || !cl.probe || !jt || !c)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory planning junctions");
    for (size_t i = 0; i < n && rc == MER_OK; i++) {
        b->joint_at[i] = b->lateral_in[i] = b->cut_end[i] = b->cut_begin[i] = UINT32_MAX;
        cl.lo[i] = 0.0f, cl.hi[i] = INFINITY;
        cl.own_lo[i] = cl.own_hi[i] = UINT32_MAX;
    }
    for (uint32_t i = 0; i < count && rc == MER_OK; i++) {
        uint32_t id = c[i].id, taken[MERP_RUN_FORKS], nt = 0;
        if (b->joint_at[id] != UINT32_MAX)
            continue; /* a fork of a run planned before */
        cl.blocker = UINT32_MAX, cl.stopper = MER_NO_NODE, cl.bend = MER_NO_NODE;
        cl.tried[id] = 1;
        bool fits = plan_one(b, &cl, id, false, true, jt);
        uint32_t X = cl.blocker, stop = cl.stopper, bend = cl.bend; /* what kept it from a patch of its own as it grew */
        fits = fits || plan_one(b, &cl, id, true, true, jt) ||
               plan_merged(b, &cl, id, threshold, X, stop, bend, jt, taken, &nt);
        if (!fits)
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
        for (uint32_t k = 0; k < nt; k++) /* a run took these forks' patches in */
            merp_joint_forget(b, &b->joints[taken[k]]);
        jt->ok = true;
        b->joints[b->joint_count] = *jt;
        remember(b, &cl, &b->joints[b->joint_count], b->joint_count);
        b->joint_count++;
    }
    /* A run planned from a stopper (plan_merged) may hold forks under the
     * threshold, which are no candidates: unfit counts candidates alone. */
    b->joints_unfit = 0;
    for (uint32_t i = 0; i < count && rc == MER_OK; i++)
        b->joints_unfit += b->joint_at[c[i].id] == UINT32_MAX;
    merp_free(c), merp_free(cl.lo), merp_free(cl.hi), merp_free(cl.own_lo), merp_free(cl.own_hi), merp_free(cl.tried);
    merp_free(cl.probe), merp_free(jt);
    return rc;
}
