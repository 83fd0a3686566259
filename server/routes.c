/* meristemd — routes. One table says which handler answers which method and
 * path, so the Allow header of a 405 is derived, never written by hand. */
#include "config.h"

#include <stdio.h>
#include <string.h>

#include "server/api.h"
#include "server/app.h"
#include "server/routes.h"
#include "server/static_files.h"

typedef enum MHD_Result (*handler_fn)(merd_request *req, const char *id);

typedef struct route {
    const char *method;
    const char *pattern;  /* "{id}" matches one path segment */
    handler_fn handler;
    bool open;            /* answered without the token */
    const char *const *query; /* the query parameters it reads (NULL-terminated) */
} route;

/* Query parameters: any other is refused with 400, so a typo is never ignored. */
static const char *const no_query[] = {NULL};
static const char *const list_query[] = {"after", "limit", "preset", "state", NULL};
static const char *const revisions_query[] = {"after", "limit", NULL};
static const char *const skeleton_query[] = {"alive", NULL};
static const char *const functions_query[] = {"format", NULL};

static const route routes[] = {
    {"GET", "/v1/health", merd_api_health, true, no_query},
    {"HEAD", "/v1/health", merd_api_health, true, no_query},
    {"GET", "/v1/metrics", merd_api_metrics, false, no_query},
    {"GET", "/v1/presets", merd_api_presets, false, no_query},
    {"GET", "/v1/sessions", merd_api_list, false, list_query},
    {"POST", "/v1/sessions", merd_api_create, false, no_query},
    {"GET", "/v1/sessions/{id}", merd_api_get, false, no_query},
    {"DELETE", "/v1/sessions/{id}", merd_api_delete, false, no_query},
    {"POST", "/v1/sessions/{id}/edits", merd_api_edits, false, merd_api_glb_option_keys},
    {"GET", "/v1/sessions/{id}/snapshot.glb", merd_api_snapshot, false, merd_api_snapshot_keys},
    {"HEAD", "/v1/sessions/{id}/snapshot.glb", merd_api_snapshot, false, merd_api_snapshot_keys},
    {"POST", "/v1/sessions/{id}/cancel", merd_api_cancel, false, no_query},
    {"GET", "/v1/sessions/{id}/revisions", merd_api_revisions, false, revisions_query},
    {"GET", "/v1/sessions/{id}/skeleton", merd_api_skeleton, false, skeleton_query},
    {"GET", "/v1/sessions/{id}/functions", merd_api_functions, false, functions_query},
    {"GET", "/v1/sessions/{id}/lsystem", merd_api_lsystem, false, no_query},
};
#define N_ROUTES (sizeof routes / sizeof routes[0])

/* Matches `url` against `pattern`; copies the {id} segment into `id`. */
static bool match(const char *pattern, const char *url, char *id, size_t id_size)
{
    while (*pattern != '\0') {
        if (strncmp(pattern, "{id}", 4) == 0) {
            size_t n = strcspn(url, "/");
            if (n == 0 || n >= id_size)
                return false;
            memcpy(id, url, n);
            id[n] = '\0';
            url += n;
            pattern += 4;
            continue;
        }
        if (*pattern++ != *url++)
            return false;
    }
    return *url == '\0';
}

/* The route table's pattern for `url` (for metrics labels and 405s), or NULL. */
static const char *route_label(const char *url)
{
    char id[80];
    for (size_t i = 0; i < N_ROUTES; i++)
        if (match(routes[i].pattern, url, id, sizeof id))
            return routes[i].pattern;
    return NULL;
}

/* Constant time in the token's length: a wrong guess takes as long as a right one. */
static bool token_ok(merd_request *req)
{
    const char *want = req->app->settings->token;
    if (want[0] == '\0')
        return true;
    const char *auth = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                   MHD_HTTP_HEADER_AUTHORIZATION);
    if (auth == NULL || strncmp(auth, "Bearer ", 7) != 0)
        return false;
    const char *got = auth + 7;
    size_t n = strlen(want), m = strlen(got);
    unsigned diff = (unsigned)(n ^ m);
    for (size_t i = 0; i < n; i++)
        diff |= (unsigned char)want[i] ^ (unsigned char)(i < m ? got[i] : 0);
    return diff == 0;
}

typedef struct query_check {
    const char *const *allowed;
    const char *unknown;  /* the first parameter not allowed, or NULL */
} query_check;

static enum MHD_Result check_key(void *ctx, enum MHD_ValueKind kind, const char *key,
                                 const char *value)
{
    (void)kind;
    (void)value;
    query_check *c = ctx;
    for (const char *const *k = c->allowed; *k != NULL; k++)
        if (strcmp(*k, key) == 0)
            return MHD_YES;
    c->unknown = key;
    return MHD_NO;
}

/* 400 naming the first query parameter `r` does not read, or MHD_YES in `*ok`. */
static enum MHD_Result refuse_unknown_query(merd_request *req, const route *r, bool *ok)
{
    query_check c = {r->query, NULL};
    MHD_get_connection_values(req->connection, MHD_GET_ARGUMENT_KIND, check_key, &c);
    *ok = c.unknown == NULL;
    if (*ok)
        return MHD_YES;
    char known[200] = "";
    for (const char *const *k = r->query; *k != NULL; k++)
        snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s",
                 k == r->query ? "" : ", ", *k);
    merd_refusal why = {0};
    merd_refuse(&why, 400, "unknown-parameter", c.unknown,
                "unknown query parameter '%.60s' for %s %s; %s%s", c.unknown, r->method, r->pattern,
                known[0] ? "it reads " : "it reads none", known);
    return merd_reply_refusal(req, &why);
}

static enum MHD_Result preflight(merd_request *req)
{
    const char *cors = req->app->settings->cors_origin;
    const char *origin = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, "Origin");
    if (cors[0] == '\0' || origin == NULL || strcmp(origin, cors) != 0)
        return merd_reply_method_not_allowed(req, "GET, POST, DELETE, HEAD");
    struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    if (r == NULL)
        return MHD_NO;
    MHD_add_response_header(r, "Access-Control-Allow-Methods", "GET, POST, DELETE, HEAD");
    MHD_add_response_header(r, "Access-Control-Allow-Headers", "Authorization, Content-Type, Accept, If-None-Match");
    MHD_add_response_header(r, "Access-Control-Max-Age", "600");
    return merd_reply(req, 204, r, 0);
}

enum MHD_Result merd_route(merd_request *req, const char *web_root)
{
    if (strncmp(req->url, "/v1/", 4) != 0 && strcmp(req->url, "/v1") != 0) {
        req->route = "static";
        if (strcmp(req->method, "GET") != 0 && strcmp(req->method, "HEAD") != 0)
            return merd_reply_method_not_allowed(req, "GET, HEAD");
        return merd_static_serve(req, web_root);
    }
    const char *label = route_label(req->url);
    req->route = label != NULL ? label : "unknown";
    if (strcmp(req->method, "OPTIONS") == 0 && label != NULL)
        return preflight(req);

    char allow[128] = "", id[80] = "";
    for (size_t i = 0; i < N_ROUTES; i++) {
        if (!match(routes[i].pattern, req->url, id, sizeof id))
            continue;
        if (strcmp(routes[i].method, req->method) == 0) {
            if (!routes[i].open && !token_ok(req)) {
                size_t size = 0;
                struct MHD_Response *r = merd_problem_response(
                    401, "unauthorized", "Unauthorized",
                    "this meristemd wants Authorization: Bearer TOKEN (its --token)", NULL, &size);
                if (r != NULL)
                    MHD_add_response_header(r, MHD_HTTP_HEADER_WWW_AUTHENTICATE, "Bearer");
                return merd_reply(req, 401, r, size);
            }
            bool ok = true;
            enum MHD_Result refused = refuse_unknown_query(req, &routes[i], &ok);
            if (!ok)
                return refused;
            enum MHD_Result deferred;
            if (id[0] != '\0' && merd_api_load_first(req, id, &deferred))
                return deferred;
            return routes[i].handler(req, id[0] ? id : NULL);
        }
        size_t used = strlen(allow);
        snprintf(allow + used, sizeof allow - used, "%s%s", used ? ", " : "", routes[i].method);
    }
    if (allow[0] != '\0')
        return merd_reply_method_not_allowed(req, allow);

    char detail[300];
    snprintf(detail, sizeof detail, "there is no API route %.200s; see proto/openapi.yaml",
             req->url);
    return merd_reply_problem(req, 404, "not-found", "Not Found", detail);
}
