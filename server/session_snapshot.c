/* meristemd — a session's snapshots: meshed and encoded under its `work`
 * lock, kept in its cache of variants (see session.h). */
#include "config.h"

#include <assert.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "server/export.h"
#include "server/session_private.h"

static void options_key(const merd_snapshot_options *o, char *out, size_t n)
{
    // Twig lines add "w1" and implicit junctions "j1", so the keys of snapshots
    // without them stay as they were.
    char at[32] = "";
    if (o->at_t)
        snprintf(at, sizeof at, "y%" PRIu64, o->t_micro);
    snprintf(out, n, "d%ul%um%uc%uq%ut%uz%u%s%s%s",
             o->mesh.detail ? o->mesh.detail : MER_MESH_DETAIL_DEFAULT, o->mesh.leaves,
             o->mesh.markers, o->mesh.color, o->unquantized ? 0 : 1, o->mesh.no_uvs ? 0 : 1,
             o->compression, o->mesh.twig_lines ? "w1" : "", o->mesh.junctions ? "j1" : "", at);
}

void merd_session_etag_at(uint64_t revision, const merd_snapshot_options *options, char *etag)
{
    char key[56];
    options_key(options, key, sizeof key);
    snprintf(etag, MERD_ETAG_MAX, "\"r%" PRIu64 "-%s\"", revision, key);
}

void merd_session_etag(merd_session *s, const merd_snapshot_options *options, char *etag)
{
    merd_session_etag_at(merd_session_revision(s), options, etag);
}

int merd_session_build(merd_session *s, const mer_scene *scene, uint64_t revision,
                       const merd_snapshot_options *options, merd_snapshot **out,
                       merd_refusal *why)
{
    const json_t *preset = json_object_get(s->spec, "preset");
    const json_t *seed = json_object_get(s->spec, "seed");
    merd_origin origin = {.session = s->id,
                          .revision = merd_revisions_tree(s->revs, revision),
                          .preset = preset ? json_string_value(preset) : "default",
                          .seed = seed ? (uint64_t)json_integer_value(seed) : 0};
    mer_gltf_options gopt = {.format = MER_GLTF_BINARY,
                             .unquantized = options->unquantized,
                             .compression = options->compression};
    uint8_t *bytes = NULL;
    size_t size = 0;
    mer_error err = {0};
    /* Several workers may mesh at once: each snapshot's patches take the
     * cores the others leave, or a fixed number (the bytes are the same
     * whatever the count). Meshes with tubes use no threads. */
    mer_mesh_options mesh = options->mesh;
    uint32_t lent = 0;
    if (mesh.threads == 0 && mesh.junctions != MER_JUNCTIONS_TUBES) {
        if (s->cfg->patch_threads > 0)
            mesh.threads = s->cfg->patch_threads;
        else if (s->cfg->cores != NULL)
            mesh.threads = lent = merd_cores_take(s->cfg->cores);
    }
    mer_result rc = merd_export_tree(scene, &mesh, &gopt, &origin, &bytes, &size, NULL, &err);
    if (lent > 0)
        merd_cores_give(s->cfg->cores, lent);
    if (rc != MER_OK)
        return merd_refuse_lib(why, rc, &err, "");
    *out = merd_snapshot_new(bytes, size);
    if (*out == NULL)
        return merd_refuse(why, 503, "out-of-memory", "", "out of memory for a snapshot");
    return 0;
}

/* The tree of `scene` at the options' time, meshed from a copy of it. */
static int build_at_t(merd_session *s, uint64_t revision, const merd_snapshot_options *options,
                      merd_snapshot **out, merd_refusal *why)
{
    mer_scene *copy = NULL;
    mer_error err = {0};
    mer_result rc = mer_scene_clone(s->scene, &copy, &err);
    if (rc == MER_OK)
        rc = mer_scene_show_time(copy, (double)options->t_micro / 1e6, &err);
    int r = rc == MER_OK ? merd_session_build(s, copy, revision, options, out, why)
            : rc == MER_ERR_INVALID || rc == MER_ERR_RANGE
                ? merd_refuse(why, 400, "out-of-range", "t", "%s", err.message)
                : merd_refuse_lib(why, rc, &err, "");
    mer_scene_free(copy);
    return r;
}

int merd_session_snapshot(merd_session *s, const merd_snapshot_options *options,
                          merd_snapshot **out, char *etag, bool *cached, merd_refusal *why)
{
    assert(merd_session_is_loaded(s));
    pthread_mutex_lock(&s->work);
    merd_session_etag(s, options, etag);
    *out = merd_snapshot_cache_get(&s->snaps, etag);
    *cached = *out != NULL;
    int rc = 0;
    if (*out == NULL &&
        (rc = options->at_t ? build_at_t(s, merd_session_revision(s), options, out, why)
                            : merd_session_build(s, s->scene, merd_session_revision(s), options,
                                                 out, why)) == 0)
        merd_snapshot_cache_put(&s->snaps, merd_session_revision(s), etag, *out);
    pthread_mutex_unlock(&s->work);
    return rc;
}
