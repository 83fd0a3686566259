/* meristemd — one HTTP request's state, from the first header to the log line,
 * and the helpers every handler answers with. */
#ifndef MERISTEMD_REQUEST_H
#define MERISTEMD_REQUEST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include <jansson.h>
#include <microhttpd.h>

#include "server/settings.h"

typedef struct mer_server mer_server;

typedef struct mer_request {
    struct MHD_Connection *connection;
    const mer_server *server;
    const char *method;        /* borrowed from libmicrohttpd, valid for the request */
    const char *url;           /* decoded path, no query string */
    char *body;                /* NUL-terminated upload, owned; NULL when none */
    size_t body_size;
    bool body_too_large;       /* the upload passed --max-body and was discarded */
    unsigned status;           /* what was queued, for the log line */
    uint64_t bytes_out;
    struct timespec started;
} mer_request;

/* Queues `body` (copied) with `status` and `content_type`. Returns libmicrohttpd's verdict. */
enum MHD_Result mer_reply_bytes(mer_request *req, unsigned status, const char *content_type,
                                const void *body, size_t size);

/* Queues `json` (borrowed, compact, UTF-8) as application/json. */
enum MHD_Result mer_reply_json(mer_request *req, unsigned status, const json_t *json);

/* Queues an RFC 9457 application/problem+json body. `slug` names the problem
 * type (urn:meristem:problem:SLUG), `detail` says what to do about it. */
enum MHD_Result mer_reply_problem(mer_request *req, unsigned status, const char *slug,
                                  const char *title, const char *detail);

/* 405 with the Allow header listing `allow` (e.g. "GET, HEAD"). */
enum MHD_Result mer_reply_method_not_allowed(mer_request *req, const char *allow);

/* Queues an already-built response and remembers status and size for the log. */
enum MHD_Result mer_reply(mer_request *req, unsigned status, struct MHD_Response *response,
                          uint64_t size);

#endif
