/* meristemd — GET /v1/sessions/{id}/revisions (a page of the session's
 * revisions), GET /v1/sessions/{id}/skeleton (its nodes for scripts),
 * GET /v1/sessions/{id}/functions (an inverse-model session's .fset) and
 * GET /v1/sessions/{id}/lsystem (an L-system session's source). All
 * read the tree's state under its work lock, so a worker answers them. */
#include "config.h"

#include <stdlib.h>
#include <string.h>

#include "server/api/private.h"

/* Revisions per page when ?limit= is not given, and the most one may ask for. */
#define PAGE_DEFAULT 100
#define PAGE_MAX 1000

static void answer_json(merd_api_job *j, json_t *body)
{
    size_t size = 0;
    struct MHD_Response *r = body ? merd_json_response(body, &size) : NULL;
    json_decref(body);
    merd_api_job_finish(j, 200, r, size);
}

/* Finds session `id`, reads the query into a job with `read` (0, or -1 with
 * `why`) and hands the job to a worker that runs `run`. */
static enum MHD_Result submit(merd_request *req, const char *id,
                              int (*read)(merd_request *req, merd_api_job *j, merd_refusal *why),
                              merd_job_fn run)
{
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    req->revision = (long long)merd_session_revision(s);
    merd_api_job asked = {0};
    if (read(req, &asked, &why) != 0) {
        merd_session_unref(s);
        return merd_reply_refusal(req, &why);
    }
    merd_api_job *j = merd_api_job_new(req, s);
    if (j == NULL)
        return MHD_NO;
    asked.req = j->req;
    asked.app = j->app;
    asked.session = j->session;
    *j = asked;
    return merd_api_job_submit(j, run);
}

static void run_revisions(void *arg)
{
    merd_api_job *j = arg;
    answer_json(j, merd_session_revisions(j->session, j->after, j->from_start, j->limit));
}

static int read_revisions(merd_request *req, merd_api_job *j, merd_refusal *why)
{
    uint64_t after = 0, limit = PAGE_DEFAULT;
    bool given = false;
    if (merd_api_query_uint(req, "after", 0, INT64_MAX, &after, &given, why) != 0 ||
        merd_api_query_uint(req, "limit", 1, PAGE_MAX, &limit, NULL, why) != 0)
        return -1;
    j->after = after;
    j->from_start = !given;
    j->limit = (size_t)limit;
    return 0;
}

enum MHD_Result merd_api_revisions(merd_request *req, const char *id)
{
    return submit(req, id, read_revisions, run_revisions);
}

static void run_skeleton(void *arg)
{
    merd_api_job *j = arg;
    answer_json(j, merd_session_skeleton(j->session, j->alive_only));
}

static int read_skeleton(merd_request *req, merd_api_job *j, merd_refusal *why)
{
    uint64_t alive = 0;
    if (merd_api_query_uint(req, "alive", 0, 1, &alive, NULL, why) != 0)
        return -1;
    j->alive_only = alive != 0;
    return 0;
}

enum MHD_Result merd_api_skeleton(merd_request *req, const char *id)
{
    return submit(req, id, read_skeleton, run_skeleton);
}

/* The .fset text the model wrote (well formed: one item a line) as
 * {"functions": [{"name", "kind", "samples", "points": [[x, y, m], ...]}]}.
 * NULL when out of memory. O(text). */
static json_t *functions_json(const char *text)
{
    json_t *list = json_array(), *fn = NULL, *points = NULL;
    unsigned left = 0;
    for (const char *s = text; list != NULL && *s != '\0';) {
        const char *nl = strchr(s, '\n');
        char line[128];
        size_t n = nl != NULL ? (size_t)(nl - s) : strlen(s);
        snprintf(line, sizeof line, "%.*s", (int)(n < sizeof line ? n : sizeof line - 1), s);
        s += n + (nl != NULL);
        double x, y;
        unsigned m = 1, u;
        char name[64];
        if (left > 0 && sscanf(line, "%lf %lf %u", &x, &y, &m) >= 2) {
            json_array_append_new(points, json_pack("[f, f, i]", x, y, (json_int_t)m));
            left--;
        } else if (sscanf(line, "name: %63s", name) == 1) {
            fn = json_pack("{s:s, s:s}", "name", name, "kind", "bspline");
            json_array_append_new(list, fn);
        } else if (fn != NULL && sscanf(line, "samples: %u", &u) == 1) {
            json_object_set_new(fn, "samples", json_integer(u));
        } else if (fn != NULL && strcmp(line, "kind: linear") == 0) {
            json_object_set_new(fn, "kind", json_string("linear"));
        } else if (fn != NULL && sscanf(line, "points: %u", &u) == 1) {
            json_object_set_new(fn, "points", points = json_array());
            left = u;
        }
    }
    return list != NULL ? json_pack("{s:o}", "functions", list) : NULL;
}

/* A definition's copy (len 1: out of memory), or NULL after refusing the job:
 * only sessions of the model `model` have `what`. */
static char *definition_or_refuse(merd_api_job *j, char *text, size_t len, const char *model,
                                  const char *what)
{
    if (text != NULL)
        return text;
    merd_refusal why = {0};
    if (len == 1)
        merd_refuse(&why, 503, "out-of-memory", "", "out of memory for the %s", what);
    else
        merd_refuse(&why, 422, "invalid-field", "model",
                    "only sessions of the model \"%s\" have %s", model, what);
    merd_api_job_refuse(j, &why);
    return NULL;
}

static void run_functions(void *arg)
{
    merd_api_job *j = arg;
    size_t len = 0;
    char *text = merd_session_functions(j->session, &len);
    if (definition_or_refuse(j, text, len, "inverse", "functions") == NULL)
        return;
    if (j->json_form) {
        json_t *body = functions_json(text);
        free(text);
        answer_json(j, body);
        return;
    }
    struct MHD_Response *r = MHD_create_response_from_buffer(len, text, MHD_RESPMEM_MUST_FREE);
    if (r == NULL)
        free(text);
    else
        MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "text/plain; charset=utf-8");
    merd_api_job_finish(j, 200, r, len);
}

/* ?format=json or fset (the default). */
static int read_functions(merd_request *req, merd_api_job *j, merd_refusal *why)
{
    const char *f = MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "format");
    if (f != NULL && strcmp(f, "json") != 0 && strcmp(f, "fset") != 0)
        return merd_refuse(why, 422, "out-of-range", "format",
                           "format must be fset or json, got '%.40s'", f);
    j->json_form = f != NULL && strcmp(f, "json") == 0;
    return 0;
}

enum MHD_Result merd_api_functions(merd_request *req, const char *id)
{
    return submit(req, id, read_functions, run_functions);
}

/* {"source": the cpfg text}, the form a creation request's "lsystem" takes. */
static void run_lsystem(void *arg)
{
    merd_api_job *j = arg;
    size_t len = 0;
    char *text = merd_session_lsystem(j->session, &len);
    if (definition_or_refuse(j, text, len, "lsystem", "an L-system source") == NULL)
        return;
    json_t *body = json_pack("{s:s%}", "source", text, len);
    free(text);
    answer_json(j, body);
}

static int read_nothing(merd_request *req, merd_api_job *j, merd_refusal *why)
{
    (void)req, (void)j, (void)why;
    return 0;
}

enum MHD_Result merd_api_lsystem(merd_request *req, const char *id)
{
    return submit(req, id, read_nothing, run_lsystem);
}
