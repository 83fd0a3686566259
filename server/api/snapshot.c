/* meristemd — GET /v1/sessions/{id}/snapshot.glb: options from the query,
 * 304 for a client that has this revision, otherwise meshed by a worker (or
 * taken from the session's cache of variants). */
#include "config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "server/api/private.h"
#include "server/codec.h"

#define GLB_OPTIONS "detail", "leaves", "markers", "quantize", "texcoords", "twig_lines", \
    "compress", "color", "junctions"
const char *const merd_api_glb_option_keys[] = {GLB_OPTIONS, NULL};
const char *const merd_api_snapshot_keys[] = {GLB_OPTIONS, "revision", "t", NULL};

static const char *query(merd_request *req, const char *key)
{
    return MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, key);
}

int merd_api_query_uint(merd_request *req, const char *key, uint64_t lo, uint64_t hi,
                        uint64_t *out, bool *given, merd_refusal *why)
{
    const char *v = query(req, key);
    if (given != NULL)
        *given = v != NULL;
    if (v == NULL)
        return 0;
    char *end = NULL;
    unsigned long long x = v[0] >= '0' && v[0] <= '9' ? strtoull(v, &end, 10) : 0;
    if (end == NULL || end == v || *end != '\0' || x < lo || x > hi)
        return merd_refuse(why, 422, "out-of-range", key,
                           "%s must be an integer from %llu to %llu, got '%.40s'", key,
                           (unsigned long long)lo, (unsigned long long)hi, v);
    *out = (uint64_t)x;
    return 0;
}

static int query_uint(merd_request *req, const char *key, uint32_t lo, uint32_t hi, uint32_t *out,
                      merd_refusal *why)
{
    uint64_t x = *out;
    int rc = merd_api_query_uint(req, key, lo, hi, &x, NULL, why);
    *out = (uint32_t)x;
    return rc;
}

int merd_api_snapshot_options(merd_request *req, merd_snapshot_options *o, merd_refusal *why)
{
    memset(o, 0, sizeof *o);
    o->mesh.detail = MER_MESH_DETAIL_DEFAULT;
    uint32_t quantize = 0, texcoords = 1; /* float: what every importer reads */
    if (query_uint(req, "detail", 1, MER_MESH_DETAIL_MAX, &o->mesh.detail, why) ||
        query_uint(req, "leaves", 0, 1, &o->mesh.leaves, why) ||
        query_uint(req, "markers", 0, 1, &o->mesh.markers, why) ||
        query_uint(req, "quantize", 0, 1, &quantize, why) ||
        query_uint(req, "texcoords", 0, 1, &texcoords, why) ||
        query_uint(req, "twig_lines", 0, 1, &o->mesh.twig_lines, why))
        return -1;
    o->unquantized = !quantize;
    o->mesh.no_uvs = !texcoords;
    const char *compress = query(req, "compress");
    if (compress != NULL) {
        int mode = merd_compression_parse(compress);
        if (mode < 0)
            return merd_refuse(why, 422, "out-of-range", "compress",
                               "compress must be none or meshopt, got '%.40s'", compress);
        o->compression = (uint32_t)mode;
    }
    const char *color = query(req, "color");
    if (color != NULL) {
        int mode = merd_color_mode_parse(color);
        if (mode < 0)
            return merd_refuse(why, 422, "out-of-range", "color",
                               "color must be none, order, light or age, got '%.40s'", color);
        o->mesh.color = (uint32_t)mode;
    }
    const char *junctions = query(req, "junctions");
    if (junctions != NULL) {
        int mode = merd_junctions_parse(junctions);
        if (mode < 0)
            return merd_refuse(why, 422, "out-of-range", "junctions",
                               "junctions must be tubes or implicit, got '%.40s'", junctions);
        o->mesh.junctions = (uint32_t)mode;
    }
    return 0;
}

struct MHD_Response *merd_api_glb_response(merd_snapshot *snap, const char *etag, size_t *size)
{
    const uint8_t *bytes = merd_snapshot_bytes(snap, size);
    // The snapshot is shared with the cache: libmicrohttpd sends it in place and
    // releases our reference when the response is gone.
    struct MHD_Response *r = MHD_create_response_from_buffer_with_free_callback_cls(
        *size, (void *)bytes, (MHD_ContentReaderFreeCallback)merd_snapshot_release, snap);
    if (r == NULL) {
        merd_snapshot_release(snap);
        return NULL;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "model/gltf-binary");
    MHD_add_response_header(r, MHD_HTTP_HEADER_ETAG, etag);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    return r;
}

bool merd_api_wants_glb(merd_request *req)
{
    const char *accept = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                     MHD_HTTP_HEADER_ACCEPT);
    return accept != NULL && strstr(accept, "model/gltf-binary") != NULL;
}

int merd_api_job_snapshot(merd_api_job *j, struct MHD_Response **r, size_t *size,
                          merd_refusal *why)
{
    merd_snapshot *snap = NULL;
    bool cached = false;
    if (j->past ? merd_session_snapshot_at(j->session, j->revision, &j->snap, &snap, j->etag,
                                           &cached, why)
                : merd_session_snapshot(j->session, &j->snap, &snap, j->etag, &cached, why))
        return -1;
    merd_metrics_snapshot(j->app->metrics, cached);
    *r = merd_api_glb_response(snap, j->etag, size);
    return 0;
}

static void run_snapshot(void *arg)
{
    merd_api_job *j = arg;
    merd_refusal why = {0};
    struct MHD_Response *r = NULL;
    size_t size = 0;
    j->req->revision = (long long)merd_session_revision(j->session);
    if (merd_api_job_snapshot(j, &r, &size, &why) != 0)
        merd_api_job_refuse(j, &why);
    else
        merd_api_job_finish(j, 200, r, size);
}

/* ?t=: the time (in steps, fractional) of a continuously growing model's tree,
 * to a millionth of a step; 400 naming t when malformed or with ?revision=. */
static int read_t(merd_request *req, merd_snapshot_options *o, bool past, merd_refusal *why)
{
    const char *v = query(req, "t");
    if (v == NULL)
        return 0;
    char *end = NULL;
    double t = strtod(v, &end);
    if (end == v || *end != '\0' || !isfinite(t) || t < 0.0 || t > 1e6)
        return merd_refuse(why, 400, "out-of-range", "t",
                           "t must be a number of years from 0, got '%.40s'", v);
    if (past)
        return merd_refuse(why, 400, "out-of-range", "t", "t is for the current tree, "
                           "not with revision");
    o->at_t = true;
    o->t_micro = (uint64_t)llround(t * 1e6);
    return 0;
}

enum MHD_Result merd_api_snapshot(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    merd_snapshot_options snap;
    req->revision = (long long)merd_session_revision(s);
    uint64_t revision = 0;
    bool past = false;
    if (merd_api_snapshot_options(req, &snap, &why) != 0 ||
        merd_api_query_uint(req, "revision", 0, INT64_MAX, &revision, &past, &why) != 0 ||
        read_t(req, &snap, past, &why) != 0) {
        merd_session_unref(s);
        return merd_reply_refusal(req, &why);
    }
    // A client that has this revision with these options gets 304 without meshing.
    char etag[MERD_ETAG_MAX];
    if (past)
        merd_session_etag_at(revision, &snap, etag);
    else
        merd_session_etag(s, &snap, etag);
    const char *match = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                    MHD_HTTP_HEADER_IF_NONE_MATCH);
    if (match != NULL && (strstr(match, etag) != NULL || strcmp(match, "*") == 0)) {
        req->revision = (long long)merd_session_revision(s);
        merd_session_unref(s);
        struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        if (r != NULL)
            MHD_add_response_header(r, MHD_HTTP_HEADER_ETAG, etag);
        return merd_reply(req, 304, r, 0);
    }
    merd_api_job *j = merd_api_job_new(req, s);
    if (j == NULL)
        return MHD_NO;
    j->snap = snap;
    j->past = past;
    j->revision = revision;
    return merd_api_job_submit(j, run_snapshot);
}
