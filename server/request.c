/* meristemd — response helpers. */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/request.h"

enum MHD_Result mer_reply(mer_request *req, unsigned status, struct MHD_Response *response,
                          uint64_t size)
{
    if (response == NULL)
        return MHD_NO;
    MHD_add_response_header(response, "X-Content-Type-Options", "nosniff");
    enum MHD_Result ok = MHD_queue_response(req->connection, status, response);
    MHD_destroy_response(response);
    req->status = status;
    req->bytes_out = size;
    return ok;
}

enum MHD_Result mer_reply_bytes(mer_request *req, unsigned status, const char *content_type,
                                const void *body, size_t size)
{
    struct MHD_Response *response =
        MHD_create_response_from_buffer(size, (void *)body, MHD_RESPMEM_MUST_COPY);
    if (response == NULL)
        return MHD_NO;
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    return mer_reply(req, status, response, size);
}

enum MHD_Result mer_reply_json(mer_request *req, unsigned status, const json_t *json)
{
    char *text = json_dumps(json, JSON_COMPACT);
    if (text == NULL)
        return mer_reply_problem(req, 500, "internal", "Internal Server Error",
                                 "the response could not be encoded");
    size_t size = strlen(text);
    struct MHD_Response *response =
        MHD_create_response_from_buffer(size, text, MHD_RESPMEM_MUST_FREE);
    if (response == NULL) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return mer_reply(req, status, response, size);
}

/* Builds (does not queue) an RFC 9457 body; NULL when out of memory. */
static struct MHD_Response *problem_response(unsigned status, const char *slug,
                                             const char *title, const char *detail,
                                             size_t *size)
{
    char type[128];
    snprintf(type, sizeof type, "urn:meristem:problem:%s", slug);
    json_t *problem = json_pack("{s:s, s:s, s:i, s:s}", "type", type, "title", title, "status",
                                (int)status, "detail", detail);
    char *text = problem != NULL ? json_dumps(problem, JSON_COMPACT) : NULL;
    json_decref(problem);
    if (text == NULL)
        return NULL;
    *size = strlen(text);
    struct MHD_Response *response =
        MHD_create_response_from_buffer(*size, text, MHD_RESPMEM_MUST_FREE);
    if (response == NULL) {
        free(text);
        return NULL;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "application/problem+json");
    return response;
}

enum MHD_Result mer_reply_problem(mer_request *req, unsigned status, const char *slug,
                                  const char *title, const char *detail)
{
    size_t size = 0;
    struct MHD_Response *response = problem_response(status, slug, title, detail, &size);
    return mer_reply(req, status, response, size);
}

enum MHD_Result mer_reply_method_not_allowed(mer_request *req, const char *allow)
{
    char detail[160];
    snprintf(detail, sizeof detail, "%s is not allowed on %s; use %s", req->method, req->url,
             allow);
    size_t size = 0;
    struct MHD_Response *response =
        problem_response(405, "method-not-allowed", "Method Not Allowed", detail, &size);
    if (response != NULL)
        MHD_add_response_header(response, MHD_HTTP_HEADER_ALLOW, allow);
    return mer_reply(req, 405, response, size);
}
