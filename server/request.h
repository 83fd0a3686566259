/* meristemd — one HTTP request's state, from the first header to the log line,
 * and the helpers every handler answers with. */
#ifndef MERISTEMD_REQUEST_H
#define MERISTEMD_REQUEST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>
#include <microhttpd.h>

#include "server/refusal.h"
#include "server/settings.h"

/* The deepest nesting a JSON body may have. */
#define MERD_JSON_DEPTH_MAX 32

typedef struct merd_app merd_app;

enum merd_async { MERD_ASYNC_NONE = 0, MERD_ASYNC_WAITING, MERD_ASYNC_READY };

typedef struct merd_request {
    struct MHD_Connection *connection;
    merd_app *app;
    const char *method;        /* borrowed from libmicrohttpd, valid for the request */
    const char *url;           /* decoded path, no query string */
    char *body;                /* NUL-terminated upload, owned; NULL when none */
    size_t body_size;
    bool body_too_large;       /* the upload passed --max-body and was discarded */
    unsigned status;           /* what was queued, for the log line */
    uint64_t bytes_out;
    double started;            /* merd_now() at the first header */
    const char *route;         /* the route's label, for metrics */
    long long revision;        /* sent as Meristem-Revision when >= 0 */
    /* A request answered by a worker: the connection is suspended meanwhile. */
    int async;                 /* enum merd_async */
    struct MHD_Response *pending;
    unsigned pending_status;
    uint64_t pending_size;
    bool load_handed_off;      /* its session's first load went to a worker */
} merd_request;

/* Suspends the connection until merd_request_finish; call from the handler. */
void merd_request_suspend(merd_request *req);

/* From a worker: hands over `response` (may be NULL: 500) and resumes the
 * connection, which then queues it. */
void merd_request_finish(merd_request *req, unsigned status, struct MHD_Response *response,
                         uint64_t size);

/* From a worker: resumes the connection without an answer, so that the
 * request is routed again. */
void merd_request_reroute(merd_request *req);

/* The text of an RFC 9457 problem (type urn:meristem:problem:SLUG, title,
 * status, detail, and field unless NULL or ""), newline-terminated; the caller
 * frees it. NULL when out of memory. */
char *merd_problem_body(unsigned status, const char *slug, const char *title, const char *detail,
                        const char *field);

/* Builds, without queueing, an RFC 9457 body (for workers). NULL when out of memory. */
struct MHD_Response *merd_problem_response(unsigned status, const char *slug, const char *title,
                                           const char *detail, const char *field, size_t *size);

/* The reason phrase for a status, for problem titles. */
const char *merd_status_title(unsigned status);

/* Builds, without queueing, `json` (borrowed) as a compact application/json
 * body (for workers). NULL when out of memory. */
struct MHD_Response *merd_json_response(const json_t *json, size_t *size);

/* Queues `json` (borrowed, compact, UTF-8) as application/json. */
enum MHD_Result merd_reply_json(merd_request *req, unsigned status, const json_t *json);

/* Queues `text` (taken over: freed by libmicrohttpd) as `content_type`.
 * MHD_NO when `text` is NULL or out of memory. */
enum MHD_Result merd_reply_text(merd_request *req, unsigned status, char *text,
                                const char *content_type);

/* Builds, without queueing, the problem body of a refusal (for workers). */
struct MHD_Response *merd_refusal_response(const merd_refusal *why, size_t *size);

/* Queues the problem body of a refusal with its status. */
enum MHD_Result merd_reply_refusal(merd_request *req, const merd_refusal *why);

/* The request body as JSON (new reference): an empty body is `{}`; a body
 * must be application/json (415), well-formed (400 naming line and column),
 * without duplicate keys and no deeper than MERD_JSON_DEPTH_MAX (400). NULL
 * with `why` filled otherwise. */
json_t *merd_request_json(merd_request *req, merd_refusal *why);

/* Queues an RFC 9457 application/problem+json body. `slug` names the problem
 * type (urn:meristem:problem:SLUG), `detail` says what to do about it. */
enum MHD_Result merd_reply_problem(merd_request *req, unsigned status, const char *slug,
                                   const char *title, const char *detail);

/* 405 with the Allow header listing `allow` (e.g. "GET, HEAD"). */
enum MHD_Result merd_reply_method_not_allowed(merd_request *req, const char *allow);

/* Queues an already-built response (adding Meristem-Revision and CORS headers)
 * and remembers status and size for the log and metrics. */
enum MHD_Result merd_reply(merd_request *req, unsigned status, struct MHD_Response *response,
                           uint64_t size);

#endif
