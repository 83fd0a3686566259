/* meristemd — a session's past and its skeleton: revisions recorded as they
 * are accepted, reverts and past snapshots derived through revisions.h, and
 * the node list scripts read instead of the GLB (see session.h). */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/session_private.h"

static merd_revision_origin origin_of(merd_session *s)
{
    return (merd_revision_origin){.id = s->id, .spec = s->spec, .checkpoint = s->checkpoint};
}

static int past_scene_at(void *ctx, uint64_t revision, const char *field, mer_scene **out,
                         merd_refusal *why)
{
    merd_session *s = ctx;
    const merd_revision_origin o = origin_of(s);
    return merd_revisions_scene(s->revs, &o, revision, field, out, why);
}

/* The scene a revert replaces is the last accepted revision's: kept, so a
 * redo (a revert to it) is a copy. */
static void past_retire(void *ctx, mer_scene *scene)
{
    merd_session *s = ctx;
    merd_revisions_keep(s->revs, merd_revisions_count(s->revs) - 1, scene);
}

merd_past merd_session_past(merd_session *s)
{
    return (merd_past){.scene_at = past_scene_at, .retire = past_retire, .ctx = s};
}

double merd_session_expires(const merd_session *s)
{
    return s->expires_at;
}

static int64_t record_count(const json_t *record, const char *key)
{
    const json_t *v = json_object_get(record, key);
    return json_is_integer(v) ? (int64_t)json_integer_value(v) : -1;
}

void merd_session_record(merd_session *s, uint64_t revision, const json_t *edits,
                         const json_t *record)
{
    int64_t step = record_count(record, "step"), internodes = record_count(record, "internodes");
    if (record == NULL) {
        mer_summary sum;
        mer_scene_summary(s->scene, &sum);
        step = sum.step;
        internodes = sum.internodes;
    }
    if (merd_revisions_add(s->revs, revision, edits, step, internodes) != 0)
        fprintf(stderr, "meristemd: session %s: out of memory for revision %llu's history\n",
                s->id, (unsigned long long)revision);
}

int merd_session_snapshot_at(merd_session *s, uint64_t revision,
                             const merd_snapshot_options *options, merd_snapshot **out,
                             char *etag, bool *cached, merd_refusal *why)
{
    if (revision == merd_session_revision(s))
        return merd_session_snapshot(s, options, out, etag, cached, why);
    pthread_mutex_lock(&s->work);
    merd_session_etag_at(revision, options, etag);
    *out = merd_revisions_glb(s->revs, etag);
    *cached = *out != NULL;
    mer_scene *scene = NULL;
    const merd_revision_origin o = origin_of(s);
    int rc = 0;
    if (*out == NULL && (rc = merd_revisions_scene(s->revs, &o, revision, "revision", &scene, why)) == 0 &&
        (rc = merd_session_build(s, scene, revision, options, out, why)) == 0)
        merd_revisions_glb_put(s->revs, etag, *out);
    mer_scene_free(scene);
    pthread_mutex_unlock(&s->work);
    return rc;
}

json_t *merd_session_revisions(merd_session *s, uint64_t after, bool from_start, size_t limit)
{
    pthread_mutex_lock(&s->work);
    json_t *page = merd_revisions_page(s->revs, after, from_start, limit);
    pthread_mutex_unlock(&s->work);
    return page;
}

/* A float as JSON with the digits a float has (0.3f prints as 0.3). */
static json_t *real(float x)
{
    char text[32];
    snprintf(text, sizeof text, "%.7g", (double)x);
    return json_real(strtod(text, NULL));
}

static json_t *vec3(const float v[3])
{
    return json_pack("[o, o, o]", real(v[0]), real(v[1]), real(v[2]));
}

static json_t *node_json(const mer_node *n, uint32_t step)
{
    float tip[3];
    for (int k = 0; k < 3; k++)
        tip[k] = n->base[k] + n->dir[k] * n->length;
    return json_pack("{s:i, s:o, s:o, s:o, s:o, s:i, s:i, s:b, s:o}", "id", (json_int_t)n->id,
                     "parent", n->parent == MER_NO_NODE ? json_null() : json_integer(n->parent),
                     "base", vec3(n->base), "tip", vec3(tip), "diameter", real(n->diameter),
                     "order", (json_int_t)n->order, "age",
                     (json_int_t)(step >= n->born ? step - n->born : 0), "alive", n->alive != 0,
                     "q", real(n->q));
}

json_t *merd_session_skeleton(merd_session *s, bool alive_only)
{
    pthread_mutex_lock(&s->work);
    json_t *nodes = json_array();
    uint32_t bound = mer_scene_node_bound(s->scene), step = mer_scene_step_index(s->scene);
    for (uint32_t id = 0; nodes != NULL && id < bound; id++) {
        mer_node n;
        mer_error err = {0};
        if (mer_scene_node(s->scene, id, &n, &err) != MER_OK || (alive_only && !n.alive))
            continue;
        if (json_array_append_new(nodes, node_json(&n, step)) != 0) {
            json_decref(nodes);
            nodes = NULL;
        }
    }
    json_t *body = nodes ? json_pack("{s:I, s:o}", "revision", (json_int_t)merd_session_revision(s),
                                     "nodes", nodes)
                         : NULL;
    pthread_mutex_unlock(&s->work);
    return body;
}

/* A malloc'd copy of the definition of a session of model `model`, from the
 * first `from` on (NULL: all of it); NULL for another model or out of memory
 * (*len 0 or 1). */
static char *definition_copy(merd_session *s, mer_model_kind model, const char *from, size_t *len)
{
    pthread_mutex_lock(&s->work);
    size_t n = 0;
    const char *text = mer_scene_params(s->scene)->model == model
                           ? mer_scene_definition(s->scene, &n)
                           : NULL;
    const char *start = text != NULL && from != NULL ? strstr(text, from) : text;
    char *copy = NULL;
    *len = 0;
    if (start != NULL) {
        n -= (size_t)(start - text);
        copy = malloc(n + 1);
        if (copy != NULL) {
            memcpy(copy, start, n + 1);
            *len = n;
        } else {
            *len = 1;
        }
    }
    pthread_mutex_unlock(&s->work);
    return copy;
}

char *merd_session_functions(merd_session *s, size_t *len)
{
    return definition_copy(s, MER_MODEL_INVERSE, "funcgalleryver", len);
}

char *merd_session_lsystem(merd_session *s, size_t *len)
{
    return definition_copy(s, MER_MODEL_LSYSTEM, NULL, len);
}
