/* meristemd — jobs: a request answered by a worker while its connection is
 * suspended (see private.h). */
#include "config.h"

#include <stdlib.h>

#include "server/api/private.h"

merd_api_job *merd_api_job_new(merd_request *req, merd_session *session)
{
    merd_api_job *j = calloc(1, sizeof *j);
    if (j == NULL) {
        merd_session_unref(session);
        return NULL;
    }
    j->req = req;
    j->app = req->app;
    j->session = session;
    return j;
}

static void job_free(merd_api_job *j)
{
    merd_session_unref(j->session);
    json_decref(j->spec);
    merd_batch_free(j->batch);
    free(j);
}

void merd_api_job_finish(merd_api_job *j, unsigned status, struct MHD_Response *response,
                         size_t size)
{
    merd_request_finish(j->req, status, response, size);
    job_free(j);
}

void merd_api_job_reroute(merd_api_job *j)
{
    merd_request_reroute(j->req);
    job_free(j);
}

void merd_api_job_refuse(merd_api_job *j, const merd_refusal *why)
{
    size_t size = 0;
    struct MHD_Response *r = merd_refusal_response(why, &size);
    merd_api_job_finish(j, why->status, r, size);
}

enum MHD_Result merd_api_job_submit(merd_api_job *j, merd_job_fn fn)
{
    merd_request_suspend(j->req);
    int rc = merd_jobs_submit(j->app->jobs, fn, j);
    if (rc == 0)
        return MHD_YES;
    merd_refusal why = {0};
    if (rc == MERD_JOBS_FULL)
        merd_refuse(&why, 503, "queue-full", "", "%ld requests already wait for a worker "
                    "(meristemd --max-queue); try again shortly", j->app->settings->max_queue);
    else
        merd_refuse(&why, 503, "shutting-down", "", "meristemd is stopping");
    size_t size = 0;
    struct MHD_Response *r = merd_refusal_response(&why, &size);
    // Either way the daemon is fine a moment later: say when to come back.
    if (r != NULL)
        MHD_add_response_header(r, MHD_HTTP_HEADER_RETRY_AFTER, "1");
    merd_api_job_finish(j, why.status, r, size);
    return MHD_YES;
}
