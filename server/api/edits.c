/* meristemd — POST /v1/sessions/{id}/edits: a batch decoded on the HTTP
 * thread, applied by a worker, answered with the summary or the snapshot. */
#include "config.h"

#include "server/api/private.h"
#include "server/clock.h"

/* The summary after the batch, with how it went. */
static struct MHD_Response *summary_response(merd_api_job *j, const merd_batch_outcome *outcome,
                                             size_t *size)
{
    json_t *body = merd_session_summary(j->session, true);
    if (outcome->interrupted != NULL)
        json_object_set_new(body, "interrupted", json_string(outcome->interrupted));
    json_object_set_new(body, "steps_done", json_integer(outcome->steps_done));
    const mer_step_report *last = &outcome->last_step;
    // Only a stalled step says so: a summary that grew is as it always was.
    if (last->stall != MER_STALL_NONE)
        json_object_set_new(body, "stalled",
                            json_pack("{s:s, s:o}", "reason", mer_stall_name(last->stall), "node",
                                      last->node == MER_NO_NODE ? json_null()
                                                                : json_integer(last->node)));
    // Only an edit that got away with something says so (a definition's brackets).
    if (outcome->nwarnings > 0) {
        json_t *list = json_array();
        for (uint32_t i = 0; i < outcome->nwarnings; i++) {
            const merd_edit_warning *w = &outcome->warnings[i];
            json_array_append_new(list, json_pack("{s:s, s:i, s:i, s:s}", "field", w->field,
                                                  "line", (json_int_t)w->w.line, "column",
                                                  (json_int_t)w->w.column, "message",
                                                  w->w.message));
        }
        json_object_set_new(body, "warnings", list);
    }
    struct MHD_Response *r = merd_json_response(body, size);
    json_decref(body);
    return r;
}

static void run_edits(void *arg)
{
    merd_api_job *j = arg;
    merd_refusal why = {0};
    merd_batch_outcome outcome;
    double t0 = merd_now();
    int rc = merd_session_apply(j->session, j->batch, &outcome, &why);
    if (rc == 0 && outcome.steps_done > 0)
        merd_metrics_step(j->app->metrics, merd_now() - t0, outcome.steps_done);
    j->req->revision = (long long)merd_session_revision(j->session);
    if (rc != 0) {
        merd_api_job_refuse(j, &why);
        return;
    }
    size_t size = 0;
    struct MHD_Response *r = NULL;
    if (!j->glb) {
        r = summary_response(j, &outcome, &size);
    } else if (merd_api_job_snapshot(j, &r, &size, &why) != 0) {
        merd_api_job_refuse(j, &why);
        return;
    }
    if (r != NULL && outcome.interrupted != NULL)
        MHD_add_response_header(r, "Meristem-Interrupted", outcome.interrupted);
    merd_api_job_finish(j, 200, r, size);
}

enum MHD_Result merd_api_edits(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    json_t *body = merd_request_json(req, &why);
    merd_batch *batch = NULL;
    merd_snapshot_options snap;
    if (body == NULL ||
        merd_batch_decode(body, &req->app->session_config.limits, &batch, &why) != 0 ||
        merd_api_snapshot_options(req, &snap, &why) != 0) {
        json_decref(body);
        merd_batch_free(batch);
        req->revision = (long long)merd_session_revision(s);
        merd_session_unref(s);
        return merd_reply_refusal(req, &why);
    }
    json_decref(body);
    merd_api_job *j = merd_api_job_new(req, s);
    if (j == NULL) {
        merd_batch_free(batch);
        return MHD_NO;
    }
    j->batch = batch;
    j->glb = merd_api_wants_glb(req);
    j->snap = snap;
    return merd_api_job_submit(j, run_edits);
}
