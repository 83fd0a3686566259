/* meristemd — response helpers. */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "server/app.h"
#include "server/codec.h"
#include "server/request.h"

enum MHD_Result merd_reply(merd_request *req, unsigned status, struct MHD_Response *response,
                           uint64_t size)
{
    if (response == NULL)
        return MHD_NO;
    MHD_add_response_header(response, "X-Content-Type-Options", "nosniff");
    if (req->revision >= 0) {
        char rev[24];
        snprintf(rev, sizeof rev, "%lld", req->revision);
        MHD_add_response_header(response, "Meristem-Revision", rev);
    }
    const char *cors = req->app != NULL ? req->app->settings->cors_origin : "";
    if (cors[0] != '\0' && strncmp(req->url, "/v1/", 4) == 0) {
        const char *origin = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, "Origin");
        if (origin != NULL && strcmp(origin, cors) == 0) {
            MHD_add_response_header(response, "Access-Control-Allow-Origin", cors);
            MHD_add_response_header(response, "Access-Control-Expose-Headers",
                                    "ETag, Location, Meristem-Revision, Meristem-Interrupted");
            MHD_add_response_header(response, "Vary", "Origin");
        }
    }
    enum MHD_Result ok = MHD_queue_response(req->connection, status, response);
    MHD_destroy_response(response);
    req->status = status;
    req->bytes_out = size;
    return ok;
}

struct MHD_Response *merd_json_response(const json_t *json, size_t *size)
{
    char *text = merd_json_body(json);
    if (text == NULL)
        return NULL;
    *size = strlen(text);
    struct MHD_Response *response = MHD_create_response_from_buffer(*size, text, MHD_RESPMEM_MUST_FREE);
    if (response == NULL) {
        free(text);
        return NULL;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return response;
}

enum MHD_Result merd_reply_json(merd_request *req, unsigned status, const json_t *json)
{
    size_t size = 0;
    struct MHD_Response *response = merd_json_response(json, &size);
    if (response == NULL)
        return merd_reply_problem(req, 500, "internal", "Internal Server Error",
                                  "the response could not be encoded");
    return merd_reply(req, status, response, size);
}

enum MHD_Result merd_reply_text(merd_request *req, unsigned status, char *text,
                                const char *content_type)
{
    if (text == NULL)
        return MHD_NO;
    size_t size = strlen(text);
    struct MHD_Response *r = MHD_create_response_from_buffer(size, text, MHD_RESPMEM_MUST_FREE);
    if (r == NULL) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    return merd_reply(req, status, r, size);
}

static char *problem_text(unsigned status, const char *slug, const char *title,
                          const char *detail, const char *field, unsigned line, unsigned column);
static struct MHD_Response *problem_of(char *text, size_t *size);

struct MHD_Response *merd_refusal_response(const merd_refusal *why, size_t *size)
{
    return problem_of(problem_text(why->status, why->slug, merd_status_title(why->status),
                                   why->detail, why->field, why->line, why->column),
                      size);
}

enum MHD_Result merd_reply_refusal(merd_request *req, const merd_refusal *why)
{
    size_t size = 0;
    return merd_reply(req, why->status, merd_refusal_response(why, &size), size);
}

const char *merd_status_title(unsigned status)
{
    switch (status) {
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 409: return "Conflict";
    case 413: return "Content Too Large";
    case 414: return "URI Too Long";
    case 415: return "Unsupported Media Type";
    case 422: return "Unprocessable Content";
    case 429: return "Too Many Requests";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    case 505: return "HTTP Version Not Supported";
    default: return status >= 500 ? "Internal Server Error" : "Error";
    }
}

char *merd_problem_body(unsigned status, const char *slug, const char *title, const char *detail,
                        const char *field)
{
    return problem_text(status, slug, title, detail, field, 0, 0);
}

/* A problem+json body; `line` and `column` (when not 0) place it in a text. */
static char *problem_text(unsigned status, const char *slug, const char *title,
                          const char *detail, const char *field, unsigned line, unsigned column)
{
    char type[128];
    snprintf(type, sizeof type, "urn:meristem:problem:%s", slug);
    json_t *problem = json_pack("{s:s, s:s, s:i, s:s}", "type", type, "title", title, "status",
                                (int)status, "detail", detail);
    if (problem != NULL && field != NULL && field[0] != '\0')
        json_object_set_new(problem, "field", json_string(field));
    if (problem != NULL && line > 0) {
        json_object_set_new(problem, "line", json_integer((json_int_t)line));
        json_object_set_new(problem, "column", json_integer((json_int_t)column));
    }
    char *text = problem != NULL ? merd_json_body(problem) : NULL;
    json_decref(problem);
    return text;
}

/* The response carrying problem body `text` (taken; NULL: none). */
static struct MHD_Response *problem_of(char *text, size_t *size)
{
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

struct MHD_Response *merd_problem_response(unsigned status, const char *slug, const char *title,
                                           const char *detail, const char *field, size_t *size)
{
    return problem_of(merd_problem_body(status, slug, title, detail, field), size);
}

enum MHD_Result merd_reply_problem(merd_request *req, unsigned status, const char *slug,
                                   const char *title, const char *detail)
{
    size_t size = 0;
    struct MHD_Response *response = merd_problem_response(status, slug, title, detail, NULL, &size);
    return merd_reply(req, status, response, size);
}

enum MHD_Result merd_reply_method_not_allowed(merd_request *req, const char *allow)
{
    char detail[160];
    snprintf(detail, sizeof detail, "%s is not allowed on %s; use %s", req->method, req->url,
             allow);
    size_t size = 0;
    struct MHD_Response *response =
        merd_problem_response(405, "method-not-allowed", "Method Not Allowed", detail, NULL, &size);
    if (response != NULL)
        MHD_add_response_header(response, MHD_HTTP_HEADER_ALLOW, allow);
    return merd_reply(req, 405, response, size);
}

void merd_request_suspend(merd_request *req)
{
    req->async = MERD_ASYNC_WAITING;
    MHD_suspend_connection(req->connection);
}

void merd_request_finish(merd_request *req, unsigned status, struct MHD_Response *response,
                         uint64_t size)
{
    if (response == NULL) {
        size_t n = 0;
        status = 500;
        response = merd_problem_response(500, "internal", "Internal Server Error",
                                         "the reply could not be built (out of memory?)", NULL, &n);
        size = n;
    }
    req->pending = response;
    req->pending_status = status;
    req->pending_size = size;
    req->async = MERD_ASYNC_READY;
    MHD_resume_connection(req->connection);
}

void merd_request_reroute(merd_request *req)
{
    req->async = MERD_ASYNC_NONE;
    MHD_resume_connection(req->connection);
}

static int depth_of(const json_t *j)
{
    int deepest = 0;
    if (json_is_object(j)) {
        const char *k;
        const json_t *v;
        json_object_foreach((json_t *)j, k, v) {
            (void)k;
            int d = depth_of(v);
            deepest = d > deepest ? d : deepest;
        }
        return deepest + 1;
    }
    if (json_is_array(j)) {
        size_t i;
        const json_t *v;
        json_array_foreach(j, i, v) {
            int d = depth_of(v);
            deepest = d > deepest ? d : deepest;
        }
        return deepest + 1;
    }
    return 0;
}

json_t *merd_request_json(merd_request *req, merd_refusal *why)
{
    if (req->body == NULL || req->body_size == 0)
        return json_object();
    const char *type = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                   MHD_HTTP_HEADER_CONTENT_TYPE);
    if (type == NULL || strncasecmp(type, "application/json", 16) != 0 ||
        (type[16] != '\0' && type[16] != ';' && type[16] != ' ')) {
        merd_refuse(why, 415, "unsupported-media-type", "",
                    "send the body as application/json (got %s)", type ? type : "no Content-Type");
        return NULL;
    }
    json_error_t err;
    json_t *doc = json_loadb(req->body, req->body_size, JSON_REJECT_DUPLICATES, &err);
    if (doc == NULL) {
        merd_refuse(why, 400, "malformed-json", "", "malformed JSON at line %d, column %d: %s",
                    err.line, err.column, err.text);
        return NULL;
    }
    if (depth_of(doc) > MERD_JSON_DEPTH_MAX) {
        json_decref(doc);
        merd_refuse(why, 400, "malformed-json", "", "JSON nested deeper than %d levels",
                    MERD_JSON_DEPTH_MAX);
        return NULL;
    }
    return doc;
}
