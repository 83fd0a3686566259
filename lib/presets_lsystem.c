/* meristem — L-system presets: the classic plants of Prusinkiewicz & Lindenmayer,
 * "The Algorithmic Beauty of Plants" (ABOP), written in cpfg's syntax from the
 * rules the book prints (figure captions give n and δ; δ goes to ls_delta).
 *
 * Scale: one unit is one metre, so the step lengths are chosen to make trees
 * about 5 to 20 m tall (ls_step for F without a parameter; the ternary tree's
 * F(200) and F(50) are written F(2) and F(0.5)). Widths: the book's !(w) are
 * pixels; ls_width_scale turns them into metres. Where a text sets no width,
 * the pipe model gives the diameters. */
#include "config.h"

#include <stddef.h>
#include <string.h>

#include "presets_lsystem.h"

/* §1.2: the algae (Anabaena catenula, simplified): lengths 1, 2, 3, 5, 8, 13, ... */
static const char algae[] =
    "/* ABOP §1.2: a DOL system whose string lengths are Fibonacci numbers */\n"
    "derivation length: 12\n"
    "axiom: a\n"
    "a -> ab\n"
    "b -> a\n";

/* Fig. 1.24: bracketed OL systems, the edge- and node-rewriting plants. */
static const char fig_1_24a[] =
    "/* ABOP Fig. 1.24a: n = 5, delta = 25.7 */\n"
    "derivation length: 5\naxiom: F\nF -> F[+F]F[-F]F\n";
static const char fig_1_24b[] =
    "/* ABOP Fig. 1.24b: n = 5, delta = 20 */\n"
    "derivation length: 5\naxiom: F\nF -> F[+F]F[-F][F]\n";
static const char fig_1_24c[] =
    "/* ABOP Fig. 1.24c: n = 4, delta = 22.5 */\n"
    "derivation length: 4\naxiom: F\nF -> FF-[-F+F+F]+[+F-F-F]\n";
static const char fig_1_24d[] =
    "/* ABOP Fig. 1.24d: n = 7, delta = 20 */\n"
    "derivation length: 7\naxiom: X\nX -> F[+X]F[-X]+X\nF -> FF\n";
static const char fig_1_24e[] =
    "/* ABOP Fig. 1.24e: n = 7, delta = 25.7 */\n"
    "derivation length: 7\naxiom: X\nX -> F[+X][-X]FX\nF -> FF\n";
static const char fig_1_24f[] =
    "/* ABOP Fig. 1.24f: n = 5, delta = 22.5 */\n"
    "derivation length: 5\naxiom: X\nX -> F-[[X]+X]+F[+FX]-X\nF -> FF\n";

/* Fig. 1.27: a stochastic OL system, three successors of equal weight. */
static const char fig_1_27[] =
    "/* ABOP Fig. 1.27: n = 5, delta = 20; each seed grows another plant */\n"
    "derivation length: 5\naxiom: F\n"
    "F -> F[+F]F[-F]F : 0.33\n"
    "F -> F[+F]F : 0.33\n"
    "F -> F[-F]F : 0.34\n";

/* Fig. 1.31a: Hogeweg and Hesper's context-sensitive plant (ABOP §1.8). */
static const char fig_1_31a[] =
    "/* ABOP Fig. 1.31a: n = 30, delta = 22.5 */\n"
    "derivation length: 30\n"
    "ignore: +-F\n"
    "axiom: F1F1F1\n"
    "0 < 0 > 0 -> 0\n"
    "0 < 0 > 1 -> 1[+F1F1]\n"
    "0 < 1 > 0 -> 1\n"
    "0 < 1 > 1 -> 1\n"
    "1 < 0 > 0 -> 0\n"
    "1 < 0 > 1 -> 1F1\n"
    "1 < 1 > 0 -> 0\n"
    "1 < 1 > 1 -> 0\n"
    "* < + > * -> -\n"
    "* < - > * -> +\n";

/* Fig. 2.6: Honda's monopodial trees; the four variants differ in r2, a0, a2. */
#define HONDA(r2, a0, a2)                                                             \
    "/* ABOP Fig. 2.6: Honda's monopodial tree, n = 10 */\n"                          \
    "#define r1 0.9   /* contraction ratio of the trunk */\n"                         \
    "#define r2 " r2 "   /* contraction ratio of the branches */\n"                   \
    "#define a0 " a0 "    /* branching angle from the trunk */\n"                     \
    "#define a2 " a2 "    /* branching angle of the lateral axes */\n"                \
    "#define d 137.5  /* divergence angle */\n"                                       \
    "#define wr 0.707 /* width decrease rate */\n"                                    \
    "derivation length: 10\n"                                                         \
    "axiom: A(1,10)\n"                                                                \
    "A(l,w) : * -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"                    \
    "B(l,w) : * -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"                       \
    "C(l,w) : * -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n"
static const char fig_2_6a[] = HONDA("0.6", "45", "45");
static const char fig_2_6b[] = HONDA("0.9", "45", "45");
static const char fig_2_6c[] = HONDA("0.8", "45", "45");
static const char fig_2_6d[] = HONDA("0.7", "30", "-30");

/* Fig. 2.7: Aono and Kunii's sympodial tree (variant b). */
static const char fig_2_7[] =
    "/* ABOP Fig. 2.7b: a sympodial tree after Aono and Kunii, n = 10 */\n"
    "#define r1 0.9   /* contraction ratio 1 */\n"
    "#define r2 0.7   /* contraction ratio 2 */\n"
    "#define a1 10    /* branching angle 1 */\n"
    "#define a2 60    /* branching angle 2 */\n"
    "#define wr 0.707 /* width decrease rate */\n"
    "derivation length: 10\n"
    "axiom: A(1,10)\n"
    "A(l,w) : * -> !(w)F(l)[&(a1)B(l*r1,w*wr)]/(180)[&(a2)B(l*r2,w*wr)]\n"
    "B(l,w) : * -> !(w)F(l)[+(a1)$B(l*r1,w*wr)][-(a2)$B(l*r2,w*wr)]\n";

/* Fig. 2.8a: a ternary tree with gravitropism (e = 0.22 towards -y). */
static const char fig_2_8a[] =
    "/* ABOP Fig. 2.8a: n = 6; lengths 200 and 50 of the book in metres / 100 */\n"
    "#define d1 94.74  /* divergence angle 1 */\n"
    "#define d2 132.63 /* divergence angle 2 */\n"
    "#define a 18.95   /* branching angle */\n"
    "#define lr 1.109  /* elongation rate */\n"
    "#define vr 1.732  /* width increase rate */\n"
    "derivation length: 6\n"
    "axiom: !(1)F(2)/(45)A\n"
    "A : * -> !(vr)F(0.5)[&(a)F(0.5)A]/(d1)[&(a)F(0.5)A]/(d2)[&(a)F(0.5)A]\n"
    "F(l) : * -> F(l*lr)\n"
    "!(w) : * -> !(w*vr)\n";

/* Tier 2 of cpfg: a shrub clipped to a sphere, after Prusinkiewicz, James and
 * Měch's synthetic topiary (PJM94): every apex A carries a query ?P that the
 * drawing fills with its position, and A grows only while that position is
 * inside the sphere. The string holds internodes I and apices A; the
 * homomorphism draws I as F and each apex as a pair of short needles, so the
 * drawing differs from the string. */
static const char topiary[] =
    "/* A shrub clipped to a sphere by ?P (after Prusinkiewicz, James & Mech 1994),\n"
    "   drawn through a homomorphism */\n"
    "#define R 2.2    /* radius of the sphere */\n"
    "#define C 3      /* height of its centre */\n"
    "#define a 35     /* branching angle */\n"
    "#define d 137.5  /* divergence angle */\n"
    "derivation length: 10\n"
    "axiom: I(1.2)A(0.5)?P(0,0,0)\n"
    "A(l) > ?P(x,y,z) : x*x + (y-C)^2 + z*z < R*R -> I(l)[&(a)A(l*0.9)?P(0,0,0)]/(d)A(l*0.95)\n"
    "homomorphism\n"
    "maximum depth: 1\n"
    "I(l) -> F(l)\n"
    "A(l) -> [&(50)F(0.08)][^(50)F(0.08)]\n"
    "endlsystem\n";

static const merp_ls_preset presets[] = {
    {"abop-1.2-algae", "ABOP §1.2: the algae DOL system; draws nothing, its string lengths are Fibonacci numbers",
     algae, 90.0f, 1.0f, 1.0f, 0.0f},
    {"abop-1.24a", "ABOP Fig. 1.24a: F → F[+F]F[-F]F, n 5, δ 25.7°", fig_1_24a, 25.7f, 0.05f, 1.0f, 0.0f},
    {"abop-1.24b", "ABOP Fig. 1.24b: F → F[+F]F[-F][F], n 5, δ 20°", fig_1_24b, 20.0f, 0.2f, 1.0f, 0.0f},
    {"abop-1.24c", "ABOP Fig. 1.24c: F → FF-[-F+F+F]+[+F-F-F], n 4, δ 22.5°", fig_1_24c, 22.5f, 0.25f, 1.0f, 0.0f},
    {"abop-1.24d", "ABOP Fig. 1.24d: X → F[+X]F[-X]+X, F → FF, n 7, δ 20°", fig_1_24d, 20.0f, 0.05f, 1.0f, 0.0f},
    {"abop-1.24e", "ABOP Fig. 1.24e: X → F[+X][-X]FX, F → FF, n 7, δ 25.7°", fig_1_24e, 25.7f, 0.05f, 1.0f, 0.0f},
    {"abop-1.24f", "ABOP Fig. 1.24f: X → F-[[X]+X]+F[+FX]-X, F → FF, n 5, δ 22.5°", fig_1_24f, 22.5f, 0.15f, 1.0f, 0.0f},
    {"abop-1.27", "ABOP Fig. 1.27: a stochastic bracketed OL system, n 5, δ 20° (the seed picks the plant)",
     fig_1_27, 20.0f, 0.1f, 1.0f, 0.0f},
    {"abop-1.31a", "ABOP Fig. 1.31a: Hogeweg and Hesper's context-sensitive plant, n 30, δ 22.5°",
     fig_1_31a, 22.5f, 0.25f, 1.0f, 0.0f},
    {"abop-2.6a", "ABOP Fig. 2.6a: Honda's monopodial tree, r1 0.9, r2 0.6, a0 45, a2 45, d 137.5",
     fig_2_6a, 90.0f, 1.0f, 0.01f, 0.0f},
    {"abop-2.6b", "ABOP Fig. 2.6b: Honda's tree with r2 0.9", fig_2_6b, 90.0f, 1.0f, 0.01f, 0.0f},
    {"abop-2.6c", "ABOP Fig. 2.6c: Honda's tree with r2 0.8", fig_2_6c, 90.0f, 1.0f, 0.01f, 0.0f},
    {"abop-2.6d", "ABOP Fig. 2.6d: Honda's tree with r2 0.7, a0 30, a2 -30", fig_2_6d, 90.0f, 1.0f, 0.01f, 0.0f},
    {"abop-2.7", "ABOP Fig. 2.7b: Aono and Kunii's sympodial tree, r1 0.9, r2 0.7, a1 10, a2 60",
     fig_2_7, 90.0f, 1.0f, 0.01f, 0.0f},
    {"abop-2.8a", "ABOP Fig. 2.8a: a ternary tree under gravitropism (e 0.22), n 6", fig_2_8a, 90.0f, 1.0f,
     0.01f, 0.22f},
    {"lsystem-topiary", "A shrub clipped to a sphere by the query module ?P, drawn through a homomorphism "
     "(cpfg's tier 2, after Prusinkiewicz, James & Měch 1994)", topiary, 90.0f, 1.0f, 1.0f, 0.0f},
};

#define NPRESETS (sizeof presets / sizeof presets[0])

size_t merp_ls_preset_count(void) { return NPRESETS; }

const merp_ls_preset *merp_ls_preset_at(size_t i) { return i < NPRESETS ? &presets[i] : NULL; }

void merp_ls_preset_apply(const merp_ls_preset *ps, mer_params *p)
{
    p->model = MER_MODEL_LSYSTEM;
    p->ls_delta = ps->delta;
    p->ls_step = ps->step;
    p->ls_width_scale = ps->width_scale;
    p->ls_elasticity = ps->elasticity;
}
