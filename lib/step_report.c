/* meristem — why a step grew nothing: the report the daemon turns into a
 * summary's "stalled", so that a tree never stops growing without saying why
 * (a model that has finished, a brush constraint left on, the markers used up,
 * deep shade, no buds). */
#include "config.h"

#include <assert.h>

#include "scene_private.h"

/* Whether any living node still has a dormant bud. */
static int has_dormant_bud(const merp_skeleton *sk)
{
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i])
            for (uint32_t k = 0; k < 3; k++)
                if (sk->bud[3 * i + k] == MER_BUD_DORMANT)
                    return 1;
    return 0;
}

/* The reason: a model that has finished first, since nothing else would make it
 * grow; then the constraint, because only the buds at or above it could grow;
 * then whether any bud is left; then what the environment gave the buds there
 * are (P09 §4.1: markers or light). */
static mer_stall stall_reason(const mer_scene *s)
{
    if (s->ops->finished != NULL && s->ops->finished(s->model, &s->p))
        return MER_STALL_DONE;
    if (s->sk.con_node != MER_NO_NODE)
        return MER_STALL_CONSTRAINED;
    if (!has_dormant_bud(&s->sk))
        return MER_STALL_ALL_BUDS_DEAD;
    return s->p.environment == MER_ENV_MARKERS ? MER_STALL_NO_MARKERS : MER_STALL_NO_LIGHT;
}

void merp_scene_report_step(mer_scene *s, uint32_t grown)
{
    mer_step_report r = {.step = s->step, .grown = grown, .stall = MER_STALL_NONE,
                         .node = MER_NO_NODE};
    if (grown == 0) {
        r.stall = stall_reason(s);
        if (r.stall == MER_STALL_CONSTRAINED)
            r.node = s->sk.con_node;
    }
    s->last = r;
}

void mer_scene_step_report(const mer_scene *s, mer_step_report *out)
{
    assert(s != NULL && out != NULL);
    if (s->last.step == 0) {
        *out = (mer_step_report){.stall = MER_STALL_NONE, .node = MER_NO_NODE};
        return;
    }
    *out = s->last;
}

const char *mer_stall_name(uint32_t stall)
{
    static const char *const names[] = {NULL, "constrained", "all-buds-dead", "no-markers",
                                        "no-light", "done"};
    return stall < sizeof names / sizeof names[0] ? names[stall] : NULL;
}
