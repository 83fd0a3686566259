/* meristemd — routes. One table says which handler answers which method and
 * path, so the Allow header of a 405 is derived, never written by hand. */
#include "config.h"

#include <stdio.h>
#include <string.h>

#include <meristem/version.h>

#include "server/routes.h"
#include "server/static_files.h"

typedef enum MHD_Result (*handler_fn)(mer_request *req);

typedef struct route {
    const char *method;
    const char *path;
    handler_fn handler;
} route;

static enum MHD_Result handle_health(mer_request *req)
{
    json_t *body = json_pack("{s:s, s:s}", "status", "ok", "version", mer_version());
    enum MHD_Result ok = mer_reply_json(req, 200, body);
    json_decref(body);
    return ok;
}

static const route routes[] = {
    {"GET", "/v1/health", handle_health},
    {"HEAD", "/v1/health", handle_health},
};
#define N_ROUTES (sizeof routes / sizeof routes[0])

enum MHD_Result mer_route(mer_request *req, const char *web_root)
{
    if (strncmp(req->url, "/v1/", 4) != 0 && strcmp(req->url, "/v1") != 0) {
        if (strcmp(req->method, "GET") != 0 && strcmp(req->method, "HEAD") != 0)
            return mer_reply_method_not_allowed(req, "GET, HEAD");
        return mer_static_serve(req, web_root);
    }

    char allow[128] = "";
    for (size_t i = 0; i < N_ROUTES; i++) {
        if (strcmp(routes[i].path, req->url) != 0)
            continue;
        if (strcmp(routes[i].method, req->method) == 0)
            return routes[i].handler(req);
        size_t used = strlen(allow);
        snprintf(allow + used, sizeof allow - used, "%s%s", used ? ", " : "", routes[i].method);
    }
    if (allow[0] != '\0')
        return mer_reply_method_not_allowed(req, allow);

    char detail[300];
    snprintf(detail, sizeof detail, "there is no API route %.200s; see proto/openapi.yaml",
             req->url);
    return mer_reply_problem(req, 404, "not-found", "Not Found", detail);
}
