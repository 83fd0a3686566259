/* meristem — presets named after the papers' figures: P09's here, the
 * L-systems' of ABOP in presets_lsystem.c, the inverse model's in
 * presets_inverse.c. */
#include "config.h"

#include <string.h>

#include <meristem/presets.h>

#include "presets_inverse.h"
#include "presets_lsystem.h"

typedef struct preset {
    const char *name;
    const char *description;
    void (*apply)(mer_params *p);
} preset;

static void set_apical(mer_params *p, uint32_t main_stem, uint32_t first, uint32_t rest)
{
    p->schedule.apical_off[0] = main_stem;
    p->schedule.apical_off[1] = first;
    for (int k = 2; k < MER_ORDERS_MAX; k++)
        p->schedule.apical_off[k] = rest;
}

/* Extended BH (P09 §4.2, Fig. 7): at each branch point v goes to the main axis and
 * the lateral in proportion to λQ_m and (1 − λ)Q_l, Q being the light of the whole
 * supported branch, and a bud given v makes n = ⌊v⌋ metamers. α = 2 is the paper's.
 * Why the leader is lost below λ = 0.5 (this follows from the paper's equations, it is
 * no deviation): a bud's light is at most C + a = 1.1, so the trunk's terminal bud gets
 * v ≈ 1.8 at λ = 0.5 and makes one long metamer a season; below 0.5 every branch point
 * on the trunk multiplies its share by λ(Q_m + Q_l)/(λQ_m + (1 − λ)Q_l) < 1, so after a
 * few seasons v < 1, ⌊v⌋ = 0, a lateral overtops it and its shade keeps it dormant.
 * Above 0.5 the same factor favours every axis's apex. The paper gives no branching
 * angle; we take 60°, a botanist's usual figure for broadleaves, not the default 45°:
 * laterals at 45° climb to the apex's height within a season, so the slightest bias
 * against the apex cost it the lead (leader lost at 0.48 as early as at 0.46, and the
 * crown's height/width flat from 0.46 to 0.50). At 60° the leader holds longer the
 * nearer λ is to 0.5, and the progression is gradual over the whole series. Measured
 * over 8 seeds after 16 steps (5,400–10,800 internodes), λ 0.46 → 0.54: height/width
 * 0.69, 0.74, 0.78, 0.89, 1.15; largest first-order limb 77, 60, 35, 24, 11 % of the
 * tree; trunk top at 0.34, 0.60, 1, 1, 1 of the height. The default grid and shoot cap
 * are kept: shoots of 1–2 metamers are the rule. */
static void bh(mer_params *p, float lambda)
{
    p->fate = MER_FATE_BH;
    p->alpha = 2.0f;        /* α = 2, Fig. 7 */
    p->lambda = lambda;
}

static void fig7(mer_params *p, float lambda)
{
    bh(p, lambda);
    p->branch_angle = 60.0f;
}

static void p_default(mer_params *p) { (void)p; }
static void fig7_046(mer_params *p) { fig7(p, 0.46f); }
static void fig7_048(mer_params *p) { fig7(p, 0.48f); }
static void fig7_050(mer_params *p) { fig7(p, 0.50f); }
static void fig7_052(mer_params *p) { fig7(p, 0.52f); }
static void fig7_054(mer_params *p) { fig7(p, 0.54f); }

/* The priority model at the paper's scale, calibrated on Table 1 (P09 §6: Fig. 10's
 * three trees reach 700,000, 642,000 and 225,000 internodes in 106, 90 and 68
 * steps on a 200³ shadow grid whose cells are "approximately the same length as an
 * internode"). What bounds one step's growth in P09:
 *  - A step is one season, and v = αQ_base is shared out so that a bud given v
 *    makes n = ⌊v⌋ metamers of length l = v/n (§4.2). A bud's light is at most
 *    C = 1, so under BH at λ = 0.5 each bud gets v = αQ ≤ α: with the paper's
 *    α = 2 (Fig. 7), at most 2 metamers a season. The priority model pours the
 *    resource of a whole axis into the head of its list (the leader under apical
 *    control), where v has no such bound; the paper gives no α for it. We carry
 *    BH's bound over as a cap: max_shoot = 2 metamers a season, and take α = 1
 *    (α = 2 grows the crown about 20 % faster per step; see below).
 *  - l = v/n puts internodes between l0 and 2·l0: l0 = 0.7 makes the mean internode
 *    about one voxel (voxel 1 on the paper's 200³ grid, below).
 * Measured with these values (fig10-left, -center, -right; seeds 1, 2): 700,000
 * internodes in 103 steps, 642,000 in 98–101 (about 95 with the centre tree's 60°
 * laterals), 225,000 in 74–76, every tree inside
 * the grid (at most 180 wide, 172 tall); growth falls from about 1.6× a step while
 * the seedling is fully lit to 1.19× (steps 10–30) and 1.04× at the end, as light,
 * not shoot length, becomes the limit. Before (max_shoot 16, l0 1): 29, 29 and 25
 * steps, trees up to 250 wide. `make table1` grows the three at full size. */
static void priority(mer_params *p, float kappa)
{
    p->fate = MER_FATE_PRIORITY;
    p->alpha = 1.0f;
    p->max_shoot = 2;
    p->internode_length = 0.7f;
    /* The paper's 200³ grid (§6), voxel 1. */
    p->bounds_min[0] = p->bounds_min[2] = -100.0f;
    p->bounds_max[0] = p->bounds_max[2] = 100.0f;
    p->bounds_max[1] = 200.0f;
    p->w_max = 1.0f;        /* Fig. 9 */
    p->w_min = 0.006f;
    p->kappa = kappa;
}

static void fig9_050(mer_params *p) { priority(p, 0.5f); }
static void fig9_035(mer_params *p) { priority(p, 0.35f); }
static void fig10_left(mer_params *p)
{
    priority(p, 0.5f);
    set_apical(p, 8, 8, 8); /* removed early from the main stem and the laterals */
}
/* Fig. 10 centre, "apical control limited to the main stem, removed late in
 * development". The paper gives neither the step nor the branching angle; we choose:
 *  - removal at step 80 of the 90 Table 1 grows it for: late, the last ninth of its
 *    life. Under the priority model (§4.2) the main stem's terminal bud gets v ∝ its
 *    own light Q_t (at most C + a = 1.1, and 0.9 beside its own node's buds) while the
 *    head of a lateral is given its branch's Q and then a second share within it, so a
 *    leader does not outgrow the laterals' heads: with shoots capped at 2 metamers
 *    both make 2 a season, and only the leader's vertical course keeps it on top.
 *    The cap is ours (above), not the paper's, but lifting it does not help: at 3 or
 *    4 metamers the laterals' heads use their larger v and overtop the leader by
 *    step 30 even under control. Once control goes, the terminal bud is ranked by
 *    light per bud behind the fully lit buds around it (its share falls to about
 *    one metamer) and is overtopped within 10–20 seasons: removed at step 40 the
 *    trunk's top ends at 0.60 of the height at step 90 (8 seeds), removed at 70
 *    (with 60° laterals) at 0.997 in seed 1 but lost in others.
 *  - 60° laterals, not the default 45°: wide crotch angles go with the excurrent
 *    habit (spruces, firs, sweetgum carry near-horizontal limbs; elms and oaks whose
 *    limbs rise steeply fork into codominant stems). At 45° the laterals, as vigorous
 *    as the capped leader, climb to its height even under control (the leader is lost
 *    by step 60 if control is never removed); at 60° they stay below it.
 * Measured over 8 seeds at step 90 (test_forms_full.c): the trunk's top stands at
 * 0.97 of the height (overtopped in one seed of eight) and the trunk stays the
 * dominant axis (no lateral as large as the trunk above it) to 0.96 of it, against
 * 0.88 and 0.86 on the right tree and 0.42 and 0.28 on the left one; 480,000
 * internodes (409,000 before), so Table 1's 642,000 come at about 95 steps. This is
 * Table 1's centre tree (`table1-center`, the calibration of the step counts); the
 * figure's tree is fig10_center below, which differs only in κ. */
static void table1_center(mer_params *p)
{
    priority(p, 0.5f);
    p->branch_angle = 60.0f;
    set_apical(p, 80, 0, 0); /* only on the main stem, removed late */
}
/* Fig. 10 centre as the figure draws it: a crown clearly taller than wide, narrower
 * than the other two. table1_center's crown is a dome as wide as tall (height/width
 * 0.95 over 8 seeds at step 90; 1.7 at step 10): every lateral's head is as vigorous
 * as the capped leader (above), so the crown widens by about a metamer a side a
 * season while the leader rises by less than two. A botanist narrows the crown by
 * keeping the lateral branches from keeping pace with the main stem, and P09 gives the
 * knob: "assigning large weights to a smaller number of most productive branches (at
 * the beginning of the priority list) results in a more excurrent tree form (Fig. 9)",
 * κ = 0.35 being Fig. 9's slimmer tree. Here κ = 0.33: along every axis only the best
 * lit third of the branches and buds get more than w_min, so fewer shoots grow each
 * season and the limbs reach out less far (the crown widens by 1.3 a season instead
 * of 1.8), while the leader, first in the trunk's list, keeps its two metamers a
 * season. What we tried and left: wider (70°, 75°) or drooping laterals, upward
 * tropism (the laterals climb past the leader), a larger shoot cap, a deeper or
 * darker shadow, shedding, a smaller α: none gave a crown over 1.1 times as tall as
 * wide with the leader kept. The price: the crown is sparser, 90,000 internodes at
 * step 90 where Table 1 has 642,000 (κ 0.35: 150,000 and height/width 1.2; κ 0.30:
 * 60,000 and 1.5), and at step 40 a thin young tree of 2,200 internodes (the right
 * tree: 15,000). Measured over 8 seeds at step 90
 * (test_forms_full.c): height/width 1.28 (table1_center 0.95), 146 tall and 114 wide;
 * the trunk's top at 1.00 of the height and the trunk dominant to 0.99 of it. */
static void fig10_center(mer_params *p)
{
    table1_center(p);
    p->kappa = 0.33f;
}
static void fig10_right(mer_params *p)
{
    priority(p, 0.5f);
    set_apical(p, 8, MER_NEVER, 0); /* removed early on the main stem, kept on order 1 */
}
static void fig11_animation(mer_params *p)
{
    priority(p, 0.5f);
    set_apical(p, 25, 25, 25); /* excurrent when young, decurrent when old */
}
static void fig6_sylleptic(mer_params *p)
{
    bh(p, 0.5f);
    p->sylleptic = 1;
    p->eta = 0.0f;
}
static void fig6_sympodial(mer_params *p)
{
    bh(p, 0.5f);
    p->sympodial = 1;
}
/* Fig. 12 (§4.3): a metamer's direction is d_prev + ξV + ηT, normalized. On an
 * upright axis T is parallel to d_prev: tropism only shortens the sum, and a leader
 * that starts vertical, with V vertical above the crown, stays exactly straight
 * whatever η is: a weeping tree staked for ever. Real shoots never grow exactly
 * straight (nutation, the displacement of the apex by its own leaves), and under a
 * downward pull that outweighs the pull to the light (|η| > ξ) an upright axis is
 * unstable: a tilt θ grows to about θ / (1 + ξ − |η|) a metamer, so the leader arches
 * over and an upper lateral takes its place, the decurrent, gnarled crowns of
 * Fig. 12c, d. Upward tropism (a) corrects the same deviations. So the four trees
 * grow with the same small wandering of every new internode (Perlin noise on
 * directions, amplitude 0.1, about 6°, 3-unit features) and differ only in η and ξ,
 * as in the caption. The paper gives no values: ±0.1 for the small η and ξ; for (c)
 * a large ξ = 0.6 and η = −0.8, a downward pull larger than the pull to the light;
 * for (d) η = −0.4, still four times (b)'s pull and, against the small ξ, a stronger
 * net downward pull than (c)'s. The figure draws (d) as large as the others; at
 * η = −0.5 the leader arches over within ten seasons and never rises again (15 tall
 * at step 20 as at step 30, a third of (a)'s height, height/width 0.42), and at −0.8
 * the shoots droop into their own shade and the tree stalls near 200 internodes. At
 * −0.4 an upper lateral takes over from the arched leader and keeps rising, as the
 * gnarled crowns of (c) and (d) do: over 8 seeds at step 20, 27 tall (a: 37, c: 25),
 * height/width 0.61, 8,600 internodes (a: 8,500). */
static void fig12(mer_params *p, float eta, float xi)
{
    bh(p, 0.5f);
    p->eta = eta;
    p->xi = xi;
    p->noise_amplitude = 0.1f;
    p->noise_scale = 0.3f;
    p->noise_targets = MER_NOISE_DIRECTIONS;
}
static void fig12a(mer_params *p) { fig12(p, 0.1f, 0.1f); }   /* small up η, small ξ */
static void fig12b(mer_params *p) { fig12(p, -0.1f, 0.1f); }  /* small down η, small ξ */
static void fig12c(mer_params *p) { fig12(p, -0.8f, 0.6f); }  /* large down η, large ξ */
static void fig12d(mer_params *p) { fig12(p, -0.4f, 0.1f); }  /* large down η, small ξ */
/* Fig. 13 (§4.3): the downward tropism raised late in the tree's growth.
 * The paper gives neither the values nor the steps; the tree is shown at about 26
 * steps (22,000 internodes, inside the default 100-wide grid), so η goes from the
 * default 0.05 at step 18 to -1 at step 22: what grows in the last seasons droops
 * (mean vertical direction -0.69 against 0.67 without the change, 8 seeds) over a
 * crown that grew upright. A rise from step 25 to 35 left the last seasons' growth
 * horizontal at best and the tree wider than its grid by step 35. */
static void fig13(mer_params *p)
{
    bh(p, 0.5f);
    p->schedule.eta_key_count = 2;
    p->schedule.eta_keys[0] = (mer_keyframe){18.0f, 0.05f};
    p->schedule.eta_keys[1] = (mer_keyframe){22.0f, -1.0f};
}
static void fig14(mer_params *p)
{
    /* P09 §4.4, Fig. 14: about a thousand metamers (§6), a young tree whose
     * lower branches, shaded by the crown above, are shed (Takenaka: a branch whose
     * light per internode falls below a threshold is a liability). The environment is
     * the default one (a 0.1, b 2, q_max 6, voxel 1; §4.1 leaves a and b to the user
     * and gives q_max 4–8). The paper gives neither λ nor the threshold; we choose:
     *  - λ 0.54, Fig. 7's most excurrent tree: a leader that overtops its laterals,
     *    as in the figure, so the crown sits above the early branches and shades them;
     *  - a threshold of 0.6 light per internode: a branch in full light gathers about
     *    1 per bud, one in the crown's shade under 0.5. Below 0.55 almost nothing is
     *    shed; above 0.65 the crown itself goes and a whip of 200–300 internodes is left.
     * Measured over 8 seeds after 18 steps: about 1,500 internodes, 58 tall, the lowest
     * living branch at 12.8 (at 1.0 without shedding). */
    bh(p, 0.54f);
    p->shed_threshold = 0.6f;
}
static void fig15_brushed(mer_params *p)
{
    p->environment = MER_ENV_MARKERS;
    p->fate = MER_FATE_BH;
    p->lambda = 0.5f;
    /* The first light stroke of Fig. 15a: a thin column of markers above the seedling. */
    p->marker_volume = MER_VOLUME_CYLINDER;
    p->marker_count = 300;
    p->marker_center[0] = 0.0f;
    p->marker_center[1] = 8.0f;
    p->marker_center[2] = 0.0f;
    p->marker_size[0] = 0.8f;
    p->marker_size[1] = 7.0f;
    p->marker_size[2] = 0.8f;
}
static void fig4_colonization(mer_params *p)
{
    p->environment = MER_ENV_MARKERS;
    bh(p, 0.5f);
}

/* P09 Fig. 21a, the original space colonization (Runions et al. 2007), in the
 * envelope of fig4-colonization so that the two can be compared side by side:
 * d_k = ρ = 2 and D = l0 = 1 as there; d_i = 6 reaches from the seedling's tip
 * to the ellipsoid's lowest points (y = 2). */
static void runions_2007(mer_params *p)
{
    p->model = MER_MODEL_RUNIONS;
    p->environment = MER_ENV_MARKERS;
    p->d_i = 6.0f;
    p->d_k = 2.0f;
    p->D = 1.0f;
}

/* The survey's §VII-A: the default tree with Perlin noise bending its shoots,
 * varying its internode lengths and its branch radii (lib/env/noise.h). */
static void perlin_noise(mer_params *p)
{
    p->noise_amplitude = 0.25f;
    p->noise_scale = 0.3f;
    p->noise_octaves = 3;
}

/* Guiding-vector trees after Xu & Mould 2015 (the survey's §II; guiding.h), in
 * an ellipsoid crown like fig4-colonization's (radii 10, 8, 10 at height 14).
 * XM15 gives no numbers the survey reports; these are ours: a graph of one node
 * per unit volume, 14 cones, a cost of |e|·(0.05 + (1 − g·ê)/2)², the later
 * endpoints 3 hops out from the tree among its outer half. */
static void gv(mer_params *p, float rotation, uint32_t iterations)
{
    p->model = MER_MODEL_GUIDING;
    p->marker_volume = MER_VOLUME_ELLIPSOID;
    p->marker_center[1] = 14.0f;
    p->marker_size[0] = p->marker_size[2] = 10.0f;
    p->marker_size[1] = 8.0f;
    p->gv_rotation = rotation;
    p->gv_iterations = iterations;
    p->gv_endpoints = 60;
}
/* Fig. 2: two rotation settings, each after two and after five iterations. A
 * small increment keeps branches near their parent's heading; a large one
 * turns them outwards and down within a few hops. */
static void gv_fig2_small_2(mer_params *p) { gv(p, 2.0f, 2); }
static void gv_fig2_small_5(mer_params *p) { gv(p, 2.0f, 5); }
static void gv_fig2_large_2(mer_params *p) { gv(p, 9.0f, 2); }
static void gv_fig2_large_5(mer_params *p) { gv(p, 9.0f, 5); }
/* Fig. 3: one early endpoint gives a trunk; the second iteration's endpoints are
 * held inside a bounding volume: a sphere high above the ground, or a cone. */
static void gv_fig3_sphere(mer_params *p)
{
    gv(p, 4.0f, 4);
    p->gv_bound = 1;
    p->marker_volume = MER_VOLUME_SPHERE;
    p->marker_center[1] = 16.0f;
    p->marker_size[0] = 7.0f;
}
static void gv_fig3_cone(mer_params *p)
{
    gv(p, 4.0f, 4);
    p->gv_bound = 1;
    p->marker_volume = MER_VOLUME_CONE;
    p->marker_center[1] = 15.0f;
    p->marker_size[0] = 7.0f;
    p->marker_size[1] = 10.0f;
}
/* Fig. 4: 1,000, 2,000 and 4,000 endpoints: one early (the trunk), then five
 * iterations sharing the rest (gv_endpoints_total), each among all the nodes 4
 * hops out (t = 1) inside an ellipsoid crown from 7 to 23 high (so the trunk
 * stays bare), in a graph of 4 nodes per unit volume. A surface that holds fewer
 * than its share passes the rest on; the crown holds enough for 4,000, so every
 * seed gets exactly the count named (a sparser graph or a smaller crown would
 * not: at 3 nodes per unit volume the last surfaces run short near 3,000). */
static void gv_fig4(mer_params *p, uint32_t total)
{
    gv(p, 4.0f, 6);
    p->gv_density = 4.0f;
    p->gv_endpoints_total = total;
    p->gv_k_hops = 4;
    p->gv_t = 1.0f;
    p->gv_bound = 1;
    p->marker_center[1] = 15.0f;
    p->marker_size[0] = p->marker_size[2] = 13.0f;
    p->marker_size[1] = 8.0f;
}
static void gv_fig4_1000(mer_params *p) { gv_fig4(p, 1000); }
static void gv_fig4_2000(mer_params *p) { gv_fig4(p, 2000); }
static void gv_fig4_4000(mer_params *p) { gv_fig4(p, 4000); }
/* Several early endpoints: a shrub (the survey's "early endpoint placement"). */
static void gv_shrub(mer_params *p)
{
    gv(p, 4.0f, 4);
    p->gv_early_endpoints = 6;
}

static const preset presets[] = {
    {"default", "the defaults: shadow propagation, extended BH with λ = 0.5", p_default},
    {"fig7-bh-0.46", "Fig. 7: extended BH, λ = 0.46, α = 2 (decurrent)", fig7_046},
    {"fig7-bh-0.48", "Fig. 7: extended BH, λ = 0.48, α = 2", fig7_048},
    {"fig7-bh-0.50", "Fig. 7: extended BH, λ = 0.50, α = 2", fig7_050},
    {"fig7-bh-0.52", "Fig. 7: extended BH, λ = 0.52, α = 2", fig7_052},
    {"fig7-bh-0.54", "Fig. 7: extended BH, λ = 0.54, α = 2 (excurrent)", fig7_054},
    {"fig9-priority-k0.5", "Fig. 9 left: priority model, w_max 1, w_min 0.006, κ = 0.5", fig9_050},
    {"fig9-priority-k0.35", "Fig. 9 right: priority model, κ = 0.35 (more excurrent)", fig9_035},
    {"fig10-left", "Fig. 10 left: apical control removed early from stem and laterals (step 8)", fig10_left},
    {"fig10-center", "Fig. 10 centre: apical control on the main stem only, removed late (step 80); 60° laterals; κ 0.33 for a crown taller than wide", fig10_center},
    {"fig10-right", "Fig. 10 right: removed early on the main stem, kept on first-order laterals", fig10_right},
    {"table1-left", "Table 1 (Fig. 10 left at full size): about 700,000 internodes in 106 steps", fig10_left},
    {"table1-center", "Table 1 (Fig. 10 centre at full size, κ 0.5: a denser, rounder crown than fig10-center): about 642,000 internodes in 90 steps", table1_center},
    {"table1-right", "Table 1 (Fig. 10 right at full size): about 225,000 internodes in 68 steps", fig10_right},
    {"fig11-animation", "Fig. 11: apical control everywhere until step 25, then removed", fig11_animation},
    {"fig6-sylleptic", "Fig. 6 left: sylleptic development, a decurrent shrub", fig6_sylleptic},
    {"fig6-sympodial", "Fig. 6 right: proleptic, sympodial (terminal buds flower)", fig6_sympodial},
    {"fig12a", "Fig. 12a: small upward tropism η = 0.1, small ξ = 0.1; shoots wander (noise 0.1 on directions)", fig12a},
    {"fig12b", "Fig. 12b: small downward tropism η = -0.1, small ξ = 0.1; shoots wander (noise 0.1 on directions)", fig12b},
    {"fig12c", "Fig. 12c: large downward tropism η = -0.8, large ξ = 0.6; shoots wander (noise 0.1 on directions)", fig12c},
    {"fig12d", "Fig. 12d: large downward tropism η = -0.4, small ξ = 0.1; shoots wander (noise 0.1 on directions)", fig12d},
    {"fig13-tropism-late", "Fig. 13: downward tropism rising from η 0.05 at step 18 to -1 at step 22; grow 26 steps", fig13},
    {"fig14-tall-bole", "Fig. 14: shedding (threshold 0.6) under an excurrent crown (λ 0.54) raises a tall bole; grow 18 steps", fig14},
    {"fig15-brushed", "Fig. 15: space colonization from a seedling and one light stroke; brush to go on", fig15_brushed},
    {"fig4-colonization", "Fig. 4: space colonization in an ellipsoid of 20000 markers", fig4_colonization},
    {"perlin-noise", "Survey §VII-A: the default tree with Perlin noise (amplitude 0.25, scale 0.3, 3 octaves) on directions, lengths and radii", perlin_noise},
    {"runions-2007", "Fig. 21a: the original space colonization of Runions et al. 2007 (d_i 6, d_k 2, D 1) in fig4-colonization's ellipsoid: no buds, no apical control", runions_2007},
    {"gv-fig2-small-2", "Xu & Mould 2015 Fig. 2: guiding vectors turning 2° a hop, after 2 iterations", gv_fig2_small_2},
    {"gv-fig2-small-5", "Xu & Mould 2015 Fig. 2: guiding vectors turning 2° a hop, after 5 iterations", gv_fig2_small_5},
    {"gv-fig2-large-2", "Xu & Mould 2015 Fig. 2: guiding vectors turning 9° a hop, after 2 iterations", gv_fig2_large_2},
    {"gv-fig2-large-5", "Xu & Mould 2015 Fig. 2: guiding vectors turning 9° a hop, after 5 iterations", gv_fig2_large_5},
    {"gv-fig3-sphere", "Xu & Mould 2015 Fig. 3: a trunk, later endpoints bounded by a sphere", gv_fig3_sphere},
    {"gv-fig3-cone", "Xu & Mould 2015 Fig. 3: a trunk, later endpoints bounded by a cone", gv_fig3_cone},
    {"gv-fig4-1000", "Xu & Mould 2015 Fig. 4: 1,000 endpoints in an ellipsoid crown over a trunk; grow 6 steps", gv_fig4_1000},
    {"gv-fig4-2000", "Xu & Mould 2015 Fig. 4: 2,000 endpoints in an ellipsoid crown over a trunk; grow 6 steps", gv_fig4_2000},
    {"gv-fig4-4000", "Xu & Mould 2015 Fig. 4: 4,000 endpoints in an ellipsoid crown over a trunk; grow 6 steps", gv_fig4_4000},
    {"gv-shrub", "Xu & Mould 2015: six early endpoints give a shrub", gv_shrub},
};

#define NPRESETS (sizeof presets / sizeof presets[0])

/* P09's presets first, then the L-systems' (presets_lsystem.c), then the
 * inverse model's (presets_inverse.c). */
size_t mer_preset_count(void)
{
    return NPRESETS + merp_ls_preset_count() + merp_inv_preset_count();
}

/* The inverse model's preset at index i of the whole list, else NULL. */
static const merp_inv_preset *inv_at(size_t i)
{
    size_t before = NPRESETS + merp_ls_preset_count();
    return i >= before ? merp_inv_preset_at(i - before) : NULL;
}

const char *mer_preset_name(size_t i)
{
    const merp_ls_preset *ls = i >= NPRESETS ? merp_ls_preset_at(i - NPRESETS) : NULL;
    const merp_inv_preset *inv = inv_at(i);
    return i < NPRESETS ? presets[i].name : ls != NULL ? ls->name : inv != NULL ? inv->name : NULL;
}

const char *mer_preset_description(size_t i)
{
    const merp_ls_preset *ls = i >= NPRESETS ? merp_ls_preset_at(i - NPRESETS) : NULL;
    const merp_inv_preset *inv = inv_at(i);
    return i < NPRESETS ? presets[i].description
           : ls != NULL ? ls->description
           : inv != NULL ? inv->description
                         : NULL;
}

static const merp_ls_preset *ls_preset(const char *name)
{
    for (size_t i = 0; name != NULL && i < merp_ls_preset_count(); i++)
        if (strcmp(merp_ls_preset_at(i)->name, name) == 0)
            return merp_ls_preset_at(i);
    return NULL;
}

mer_result mer_preset_params(const char *name, mer_params *out, mer_error *err)
{
    for (size_t i = 0; name != NULL && i < NPRESETS; i++) {
        if (strcmp(presets[i].name, name) == 0) {
            *out = mer_params_default();
            presets[i].apply(out);
            return MER_OK;
        }
    }
    const merp_ls_preset *ls = ls_preset(name);
    if (ls != NULL) {
        *out = mer_params_default();
        merp_ls_preset_apply(ls, out);
        return MER_OK;
    }
    const merp_inv_preset *inv = merp_inv_preset_find(name);
    if (inv != NULL) {
        *out = mer_params_default();
        merp_inv_preset_apply(inv, out);
        return MER_OK;
    }
    return mer_error_set(err, MER_ERR_INVALID, "preset", "unknown preset '%s'",
                         name != NULL ? name : "(null)");
}

const char *mer_preset_definition(const char *name)
{
    const merp_ls_preset *ls = ls_preset(name);
    const merp_inv_preset *inv = merp_inv_preset_find(name);
    return ls != NULL ? ls->source : inv != NULL ? inv->definition : NULL;
}
