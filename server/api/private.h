/* meristemd — what the /v1 handlers share: finding a session, snapshot
 * options from the query, and jobs that answer on the worker pool. */
#ifndef MERISTEMD_API_PRIVATE_H
#define MERISTEMD_API_PRIVATE_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>
#include <microhttpd.h>

#include "server/api.h"
#include "server/app.h"

/* The session `id` names, loaded (a reference: merd_session_unref it), or
 * NULL with a 404 or a 503 (quarantined) in `why`. */
merd_session *merd_api_find_session(merd_request *req, const char *id, merd_refusal *why);

/* The snapshot options of the query string (detail, leaves, markers, quantize,
 * texcoords, twig_lines, compress, color): 0, or -1 with a 422 in `why`. */
int merd_api_snapshot_options(merd_request *req, merd_snapshot_options *o, merd_refusal *why);

/* Whether the client accepts model/gltf-binary. */
bool merd_api_wants_glb(merd_request *req);

/* A response sending `snap` (whose reference it takes over) with its ETag. */
struct MHD_Response *merd_api_glb_response(merd_snapshot *snap, const char *etag, size_t *size);

/* Work a worker does for a suspended request. */
typedef struct merd_api_job {
    merd_request *req;
    merd_app *app;
    merd_session *session;  /* a reference, or NULL for create */
    json_t *spec;           /* create */
    merd_batch *batch;      /* edits */
    bool glb;               /* edits: answer with the snapshot */
    merd_snapshot_options snap;
    bool past;              /* snapshot: of `revision`, not the current tree */
    uint64_t revision;
    bool alive_only;        /* skeleton */
    bool json_form;         /* functions: as JSON, not .fset text */
    uint64_t after;         /* revisions: the page after this one ... */
    bool from_start;        /* ... or from revision 0 */
    size_t limit;
    char etag[MERD_ETAG_MAX];
} merd_api_job;

/* The query parameter `key` as an integer from `lo` to `hi` into `*out`
 * (left alone when absent; `*given` says whether it was, may be NULL): 0, or
 * -1 with a 422 naming it. */
int merd_api_query_uint(merd_request *req, const char *key, uint64_t lo, uint64_t hi,
                        uint64_t *out, bool *given, merd_refusal *why);

/* A job for `req` holding `session` (may be NULL), which it takes over: NULL
 * when out of memory, and then `session` is released. */
merd_api_job *merd_api_job_new(merd_request *req, merd_session *session);

/* Suspends the request and hands `j` to a worker that runs `fn` (which ends
 * with merd_api_job_finish or merd_api_job_refuse). A stopping pool refuses
 * it with 503. */
enum MHD_Result merd_api_job_submit(merd_api_job *j, merd_job_fn fn);

/* From the worker: answers with `response` (NULL: 500) and frees the job. */
void merd_api_job_finish(merd_api_job *j, unsigned status, struct MHD_Response *response,
                         size_t size);

/* From the worker: resumes the request without an answer, to be routed
 * again, and frees the job. */
void merd_api_job_reroute(merd_api_job *j);

/* From the worker: answers with the refusal and frees the job. */
void merd_api_job_refuse(merd_api_job *j, const merd_refusal *why);

/* The job's session as GLB with the job's options (counted in the metrics):
 * 0 and *r (NULL when out of memory), or -1 with `why`. Blocks while a batch
 * of the session runs. */
int merd_api_job_snapshot(merd_api_job *j, struct MHD_Response **r, size_t *size,
                          merd_refusal *why);

#endif
