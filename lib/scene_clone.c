/* meristem — deep copies of scenes: the state a caller keeps to undo a sequence
 * of calls without replaying how the scene was made. */
#include "config.h"

#include <assert.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "scene_private.h"

mer_result mer_scene_clone(const mer_scene *s, mer_scene **out, mer_error *err)
{
    assert(s != NULL && out != NULL);
    *out = NULL;
    if (s->ops->clone == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "model",
                             "scenes of the model '%s' cannot be copied", s->ops->name);
    mer_scene *c = merp_calloc(1, sizeof *c);
    if (c == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a scene");
    c->p = s->p;
    c->rng = s->rng;
    c->seed = s->seed;
    c->noise = s->noise;
    c->step = s->step;
    c->last = s->last;
    c->ops = s->ops;
    mer_result rc = merp_env_clone(&s->env, &c->env, err);
    if (rc == MER_OK)
        rc = merp_skel_clone(&s->sk, &c->sk, merp_env_bud_changed, &c->env, err);
    if (rc == MER_OK)
        rc = s->ops->clone(s->model, &c->model, err);
    if (rc != MER_OK) {
        mer_scene_free(c);
        return rc;
    }
    *out = c;
    return MER_OK;
}
