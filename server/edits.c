/* meristemd — edit batches: decoding a request into checked edits, applying
 * them in order, replaying a journaled batch (see edits.h). What each op does
 * is in the table of edit_ops.c. */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/decode.h"
#include "server/edit_ops.h"
#include "server/edits.h"

struct merd_batch {
    json_t *body;         /* a reference keeping `json` pointers valid */
    merd_edit *edits;
    size_t count;
};

static int decode_one(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                      merd_refusal *why)
{
    e->json = o;
    if (!json_is_object(o))
        return merd_refuse(why, 422, "invalid-field", w[0] ? w : "body", "an edit must be an object");
    const json_t *name = json_object_get(o, "op");
    char f[MERD_FIELD_MAX], names[160];
    merd_path(f, sizeof f, w, "op");
    merd_edit_op_names(names, sizeof names);
    if (!json_is_string(name))
        return merd_refuse(why, 400, "unknown-op", f, "every edit needs \"op\": %s", names);
    e->op = merd_edit_op_find(json_string_value(name));
    if (e->op == NULL)
        return merd_refuse(why, 400, "unknown-op", f, "unknown op '%s'; use %s",
                           json_string_value(name), names);
    if (e->op->fields != NULL && merd_only_fields(o, e->op->fields, e->op->what, w, true, why))
        return -1;
    return e->op->decode != NULL ? e->op->decode(o, w, c, e, why) : 0;
}

int merd_batch_decode(const json_t *body, const merd_edit_limits *lim, merd_batch **out,
                      merd_refusal *why)
{
    *out = NULL;
    if (!json_is_object(body))
        return merd_refuse(why, 422, "invalid-field", "body",
                           "the body must be an edit object or {\"edits\": [...]}");
    const json_t *list = json_object_get(body, "edits");
    bool batch = list != NULL;
    if (batch) {
        static const char *const fields[] = {"edits", NULL};
        if (merd_only_fields(body, fields, "a batch", "", true, why))
            return -1;
        if (!json_is_array(list) || json_array_size(list) == 0 ||
            json_array_size(list) > MERD_BATCH_EDITS_MAX)
            return merd_refuse(why, 422, "invalid-field", "edits",
                               "edits must be an array of 1 to %d edit objects",
                               MERD_BATCH_EDITS_MAX);
    }
    merd_batch *b = calloc(1, sizeof *b);
    size_t n = batch ? json_array_size(list) : 1;
    if (b == NULL || (b->edits = calloc(n, sizeof *b->edits)) == NULL) {
        free(b);
        return merd_refuse(why, 500, "internal", "", "out of memory for edits");
    }
    b->body = json_incref((json_t *)body);
    b->count = n;
    merd_decode_ctx c = {.limits = lim};
    for (size_t i = 0; i < n; i++) {
        char w[32] = "";
        if (batch)
            snprintf(w, sizeof w, "edits[%zu]", i);
        if (decode_one(batch ? json_array_get(list, i) : body, w, &c, &b->edits[i], why) != 0) {
            merd_batch_free(b);
            return -1;
        }
    }
    *out = b;
    return 0;
}

void merd_batch_free(merd_batch *b)
{
    if (b == NULL)
        return;
    for (size_t i = 0; i < b->count; i++)
        free(b->edits[i].points), free(b->edits[i].owned);
    free(b->edits);
    json_decref(b->body);
    free(b);
}

int merd_batch_apply(const merd_batch *b, mer_scene **scene, const merd_past *past,
                     merd_batch_stop_fn stop, void *ctx, merd_batch_outcome *outcome,
                     json_t **applied, merd_refusal *why)
{
    *applied = json_array();
    memset(outcome, 0, sizeof *outcome);
    outcome->last_step.node = MER_NO_NODE;
    bool batch = b->count > 1 || json_object_get(b->body, "edits") != NULL;
    // One context for the batch: a stop once asked for holds for later steps too.
    merd_apply_ctx c = {
        .scene = *scene, .past = past, .stop = stop, .stop_ctx = ctx, .outcome = outcome};
    for (size_t i = 0; i < b->count; i++) {
        const merd_edit *e = &b->edits[i];
        char w[32] = "";
        if (batch)
            snprintf(w, sizeof w, "edits[%zu]", i);
        c.where = w;
        c.first = i == 0;
        uint32_t model = mer_scene_params(c.scene)->model;
        int rc = (e->op->models & (1u << model)) != 0
                     ? e->op->apply(e, &c, why)
                     : merd_refuse(why, 422, "invalid-field", w[0] ? w : "op",
                                   "%s does not apply to a %s session", e->op->what ? e->op->what : e->op->name,
                                   mer_model_name(model));
        *scene = c.scene; /* a revert replaces it */
        if (rc != 0) {
            json_decref(*applied);
            *applied = NULL;
            return -1;
        }
        if (e->op->flags & MERD_OP_STEPS) {
            outcome->steps_asked += e->count;
            outcome->steps_done += c.done;
            if (c.done > 0)
                mer_scene_step_report(*scene, &outcome->last_step);
            if (c.done < e->count) {
                // Stopped at a whole step: journal what was done, nothing after it.
                if (c.done > 0)
                    json_array_append_new(*applied, json_pack("{s:s, s:i}", "op", e->op->name,
                                                              "count", (json_int_t)c.done));
                outcome->interrupted = c.stopped;
                return 0;
            }
        }
        json_array_append(*applied, (json_t *)e->json);
    }
    return 0;
}

merd_undo merd_batch_undo(const merd_batch *b)
{
    const merd_edit *e = &b->edits[0];
    if (b->count > 1 || e->constrain) // a dab that constrains is two calls
        return MERD_UNDO_COPY;
    return e->op->flags & MERD_OP_STEPS ? MERD_UNDO_REPLAY : MERD_UNDO_NOTHING;
}

int merd_batch_replay(const json_t *applied, mer_scene **scene, const merd_past *past,
                      merd_refusal *why)
{
    const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX, true};
    json_t *body = json_pack("{s:O}", "edits", (json_t *)applied);
    merd_batch *b = NULL;
    int rc = merd_batch_decode(body, &unlimited, &b, why);
    json_decref(body);
    if (rc != 0)
        return -1;
    merd_batch_outcome outcome;
    json_t *again = NULL;
    rc = merd_batch_apply(b, scene, past, NULL, NULL, &outcome, &again, why);
    json_decref(again);
    merd_batch_free(b);
    return rc;
}
