/* meristem — the L-system as a growth model (lib/models/model.h): its state, and
 * the two passes between the module string and the shared skeleton. Private to
 * lib/models/lsystem.
 *
 * One step is one derivation step (ABOP §1.2), after which the whole string is
 * drawn again by the turtle (ABOP §1.5, §1.6, §2.2) onto the skeleton, which is
 * rebuilt: node ids are the segments' drawing order, stable between two steps
 * (what prune and bend name) and renumbered by a step. Every F (or G) is an
 * internode: parent (the segment drawn before it on its path), order (bracket
 * depth), base, direction, length; its width is !(w) times ls_width_scale where
 * a ! (or ls_width) gives one, else the pipe model's diameter. With ls_blocking,
 * a segment whose end is below the ground or inside an obstacle is not drawn,
 * nor the rest of its branch (the string is not changed: moved obstacles let
 * it be drawn again).
 *
 * Children. A skeleton node has three slots: 0 the main continuation, 1 and 2
 * laterals. A segment's unbracketed successor is its main child (slot 0), its
 * branches take slots 1 and 2 in string order; a third branch and the ones after
 * it hang on a chain of joints: nodes of length 0 at the segment's tip, along its
 * direction, each the slot-0 child of the one before and carrying two more
 * branches, the last one the main continuation. Joints keep prune, bend, the
 * pipe model, meshing (a joint continues its segment's tube with no length) and
 * the skeleton export working unchanged; they draw nothing and no module made
 * them.
 *
 * Edits. Prune and bend change the skeleton only; the next step first folds them
 * into the string, so that they last through every later derivation:
 *  - a pruned node's module and the rest of its branch (up to the closing ']')
 *    are cut from the string, which is exactly the node's subtree (ABOP's % cut),
 *    so the apices it held never grow again;
 *  - a bent node gets the turn that takes the turtle's frame where it drew the
 *    node to the node's new frame, written as +(a) &(b) \(c) modules just before
 *    the module that drew it, so everything the module's branch draws later is
 *    turned with it. Tropism acts in world space and is not turned: a bent
 *    subtree under tropism bends a little differently when it is drawn again.
 * A step past the text's derivation length derives nothing (the edits stay in
 * the skeleton until a step derives).
 *
 * Tier 2 of cpfg. The decomposition is applied to the axiom (when the first
 * definition is given) and after every derivation step; its result is the
 * string. The homomorphism is applied at every drawing only: the turtle reads
 * its result, each segment names the module of the string that gave it (a
 * prune or bend of a segment a homomorphism drew acts on that module, so on
 * all the segments it gave). When the text holds query modules, every drawing
 * writes their answers into the string's own modules (not into modules a
 * homomorphism made), so the next derivation step reads them:
 *  - ?P(x,y,z): the turtle's position in the scene (the plant's base plus the
 *    turtle's coordinates); ?H ?L ?U: its heading, left and up vectors;
 *  - ?E(Q, o): the environment at the turtle's position, in this order: Q, the
 *    light a bud there would perceive, max(C − s + a, 0) of P09 §4.1 with s the
 *    shadow grid's value there (0 without a grid: the L-system's own segments
 *    cast no shadow, obstacles do); o, 1 when the position is below the ground
 *    or inside an obstacle, else 0. A module with fewer parameters gets the
 *    first ones; parameters past the second keep their values.
 * Interpretation is sequential and the environment is only read, so the
 * answers, and the strings derived from them, do not depend on threads.
 */
#ifndef MERISTEM_LSYSTEM_MODEL_PRIVATE_H
#define MERISTEM_LSYSTEM_MODEL_PRIVATE_H

#include "models/lsystem/lsystem.h"
#include "models/model.h"

/* The longest string a step may derive. */
#define MERP_LS_MODULES_MAX (UINT32_C(200) * 1000 * 1000)
/* Marks a joint in merp_model.module. */
#define MERP_LS_JOINT UINT32_MAX

struct merp_model {
    char *text;         /* the definition, NUL-terminated; NULL: none yet */
    size_t tlen;
    merp_lsys *ls;      /* the text, parsed */
    merp_lstr str;      /* the current string */
    uint32_t dstep;     /* derivation steps done */
    uint64_t seed;      /* key of every draw (merp_ls_key), from the scene's stream */
    float base[3];      /* where the turtle starts */
    /* Per node of the last drawing, [0, nn): what drew it and how. */
    uint32_t nn, ncap;
    uint32_t *module;   /* the module that drew it; MERP_LS_JOINT */
    float *frame;       /* 6 per node: direction and side (turtle H and L) as drawn */
    float *width;       /* its diameter from !, 0: the pipe model's */
};

/* draw.c: `segs` (the turtle's drawing of m->str) onto the skeleton, rebuilt
 * whole. MER_ERR_NOMEM, MER_ERR_LIMIT (the skeleton may be partial then). */
mer_result merp_lsm_build(merp_model *m, const merp_world *w, const merp_ls_segs *segs,
                          mer_error *err);
/* draw.c: the turtle's drawing of m->str into `segs`, through the homomorphism
 * and answering the query modules (above). 0, or -1 when out of memory.
 * O(string + the homomorphism's output). */
int merp_lsm_interpret(merp_model *m, const merp_world *w, merp_ls_segs *segs);
/* The turtle of the scene's parameters. */
merp_ls_turtle merp_lsm_turtle(const mer_params *p);
/* draw.c: the string with the skeleton's prunes and bends folded in, into
 * `out` (cleared first); *changed is 0 when there was nothing to fold (out is
 * left empty then). 0, or -1 when out of memory. O(string + nodes). */
int merp_lsm_fold(const merp_model *m, const merp_world *w, merp_lstr *out, int *changed);
/* draw.c: the explicit diameters into the skeleton's d^n. */
void merp_lsm_diameters(const merp_model *m, const merp_world *w);

#endif
