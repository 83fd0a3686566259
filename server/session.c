/* meristemd — live sessions (see session.h). */
#include "config.h"

#include <inttypes.h>
#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "server/codec.h"
#include "server/session.h"
#include "server/spec.h"

struct merd_snapshot {
    atomic_int refs;
    uint8_t *bytes;
    size_t size;
};

struct merd_session {
    atomic_int refs;
    char id[33];
    char path[PATH_MAX];
    const merd_session_config *cfg;
    json_t *spec;            /* the create request, as journaled */

    pthread_mutex_t work;    /* held while the scene changes or is meshed */
    mer_scene *scene;
    merd_journal *journal;

    pthread_mutex_t state;   /* guards what follows */
    uint64_t revision;
    json_t *summary;         /* after the last accepted batch */
    char *summary_text;      /* the same, full, serialized, without its closing brace */
    char *short_text;        /* without params and schedule, likewise */
    uint32_t internodes;
    bool running;
    uint32_t done, total;    /* progress of the running batch */
    atomic_int cancel;
    bool discarded;
    merd_snapshot *snap;      /* the last snapshot */
    char snap_key[64];
};

/* ---------------------------------------------------------------- summary */

/* The summary of the scene as it is (caller holds `work`). */
static json_t *build_summary(merd_session *s, uint64_t revision)
{
    json_t *j = merd_json_summary(s->scene);
    const json_t *preset = json_object_get(s->spec, "preset");
    const json_t *seed = json_object_get(s->spec, "seed");
    json_object_set_new(j, "id", json_string(s->id));
    json_object_set_new(j, "revision", json_integer((json_int_t)revision));
    json_object_set_new(j, "preset", json_string(preset ? json_string_value(preset) : "default"));
    json_object_set_new(j, "seed", json_integer(seed ? json_integer_value(seed) : 0));
    const mer_params *p = mer_scene_params(s->scene);
    uint32_t node, slot;
    json_object_set_new(j, "constraint", mer_scene_constraint(s->scene, &node, &slot)
                                             ? json_pack("{s:i, s:i}", "node", (json_int_t)node,
                                                         "bud", (json_int_t)slot)
                                             : json_null());
    json_object_set_new(j, "params", merd_json_params(p));
    json_object_set_new(j, "schedule", merd_json_schedule(&p->schedule));
    return j;
}

/* Serializes `j` without its closing brace, so "running" can be appended. */
static char *open_text(const json_t *j)
{
    char *text = json_dumps(j, MERD_JSON_DUMP_FLAGS);
    if (text != NULL)
        text[strlen(text) - 1] = '\0';
    return text;
}

static void publish(merd_session *s, uint64_t revision)
{
    json_t *summary = build_summary(s, revision);
    char *full = open_text(summary);
    json_t *brief = json_copy(summary);
    json_object_del(brief, "params");
    json_object_del(brief, "schedule");
    char *short_text = open_text(brief);
    json_decref(brief);
    mer_summary sum;
    mer_scene_summary(s->scene, &sum);
    pthread_mutex_lock(&s->state);
    json_decref(s->summary);
    free(s->summary_text);
    free(s->short_text);
    s->summary = summary;
    s->summary_text = full;
    s->short_text = short_text;
    s->revision = revision;
    s->internodes = sum.internodes;
    pthread_mutex_unlock(&s->state);
}

char *merd_session_summary_text(merd_session *s, bool full, uint64_t *revision)
{
    pthread_mutex_lock(&s->state);
    const char *base = full ? s->summary_text : s->short_text;
    char *text = NULL;
    if (base != NULL &&
        asprintf(&text, "%s,\"running\":{\"active\":%s,\"done\":%u,\"total\":%u}}", base,
                 s->running ? "true" : "false", s->done, s->total) < 0)
        text = NULL;
    *revision = s->revision;
    pthread_mutex_unlock(&s->state);
    return text;
}

json_t *merd_session_summary(merd_session *s, bool full)
{
    pthread_mutex_lock(&s->state);
    json_t *j = json_deep_copy(s->summary);
    json_t *running = json_pack("{s:b, s:i, s:i}", "active", s->running, "done",
                                (json_int_t)s->done, "total", (json_int_t)s->total);
    pthread_mutex_unlock(&s->state);
    json_object_set_new(j, "running", running);
    if (!full) {
        json_object_del(j, "params");
        json_object_del(j, "schedule");
    }
    return j;
}

/* ---------------------------------------------------------------- lifecycle */

static merd_session *session_new(const merd_session_config *cfg, const char *id)
{
    merd_session *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    atomic_init(&s->refs, 1);
    atomic_init(&s->cancel, 0);
    snprintf(s->id, sizeof s->id, "%s", id);
    snprintf(s->path, sizeof s->path, "%s/%s.journal", cfg->data_dir, id);
    s->cfg = cfg;
    pthread_mutex_init(&s->work, NULL);
    pthread_mutex_init(&s->state, NULL);
    return s;
}

static void session_free(merd_session *s, bool remove)
{
    merd_journal_close(s->journal, remove);
    mer_scene_free(s->scene);
    json_decref(s->spec);
    json_decref(s->summary);
    free(s->summary_text);
    free(s->short_text);
    if (s->snap != NULL)
        merd_snapshot_release(s->snap);
    pthread_mutex_destroy(&s->work);
    pthread_mutex_destroy(&s->state);
    free(s);
}

merd_session *merd_session_create(const merd_session_config *cfg, const char *id, const json_t *spec,
                                merd_refusal *why)
{
    merd_session *s = session_new(cfg, id);
    if (s == NULL) {
        merd_refuse(why, 503, "out-of-memory", "", "out of memory for a session");
        return NULL;
    }
    s->scene = merd_scene_from_spec(spec, &cfg->limits, why);
    if (s->scene == NULL) {
        session_free(s, false);
        return NULL;
    }
    s->spec = json_deep_copy(spec);
    json_t *record = json_pack("{s:i, s:s, s:O}", "version", 1, "id", id, "create", s->spec);
    char *text = json_dumps(record, JSON_COMPACT | JSON_SORT_KEYS);
    json_decref(record);
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    s->journal = text ? merd_journal_create(s->path, text, strlen(text), cfg->fsync, error) : NULL;
    free(text);
    if (s->journal == NULL) {
        merd_refuse(why, 500, "journal", "", "the session could not be journaled: %s", error);
        session_free(s, false);
        return NULL;
    }
    publish(s, 0);
    return s;
}

typedef struct replay_ctx {
    merd_session *s;
    uint64_t revision;
    char *error;
} replay_ctx;

static int replay_record(void *ctx, size_t index, const char *payload, size_t size)
{
    replay_ctx *r = ctx;
    json_error_t jerr;
    json_t *doc = json_loadb(payload, size, JSON_REJECT_DUPLICATES, &jerr);
    merd_refusal why = {0};
    int rc = -1;
    if (doc == NULL)
        goto done;
    if (index == 0) {
        const json_t *create = json_object_get(doc, "create");
        const json_t *id = json_object_get(doc, "id");
        if (create == NULL || !json_is_string(id) || strcmp(json_string_value(id), r->s->id) != 0)
            goto done;
        // Replay builds what was accepted once, whatever today's limits say.
        const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX};
        r->s->scene = merd_scene_from_spec(create, &unlimited, &why);
        r->s->spec = json_deep_copy(create);
        rc = r->s->scene != NULL ? 0 : -1;
    } else {
        const json_t *rev = json_object_get(doc, "revision");
        const json_t *edits = json_object_get(doc, "edits");
        if (r->s->scene == NULL || !json_is_integer(rev) || !json_is_array(edits))
            goto done;
        rc = merd_batch_replay(edits, r->s->scene, &why);
        r->revision = (uint64_t)json_integer_value(rev);
    }
done:
    if (rc != 0)
        snprintf(r->error, MERD_JOURNAL_ERROR_MAX, "record %zu: %.200s", index,
                 why.detail[0] ? why.detail : "not a meristem journal record");
    json_decref(doc);
    return rc;
}

/* Builds the session's scene afresh from its journal (caller holds `work`). */
static int rebuild(merd_session *s, char *error)
{
    merd_journal_close(s->journal, false);
    s->journal = NULL;
    mer_scene_free(s->scene);
    s->scene = NULL;
    json_decref(s->spec);
    s->spec = NULL;
    replay_ctx r = {s, 0, error};
    s->journal = merd_journal_open(s->path, s->cfg->fsync, replay_record, &r, NULL, error);
    return s->journal != NULL && s->scene != NULL ? 0 : -1;
}

merd_session *merd_session_restore(const merd_session_config *cfg, const char *path, size_t *dropped,
                                 char *error)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    char id[33];
    if (strlen(base) != 32 + 8 || strcmp(base + 32, ".journal") != 0) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s is not a session journal", path);
        return NULL;
    }
    memcpy(id, base, 32);
    id[32] = '\0';
    merd_session *s = session_new(cfg, id);
    if (s == NULL)
        return NULL;
    replay_ctx r = {s, 0, error};
    s->journal = merd_journal_open(s->path, cfg->fsync, replay_record, &r, dropped, error);
    if (s->journal == NULL || s->scene == NULL) {
        session_free(s, false);
        return NULL;
    }
    publish(s, r.revision);
    return s;
}

void merd_session_ref(merd_session *s)
{
    atomic_fetch_add(&s->refs, 1);
}

void merd_session_unref(merd_session *s)
{
    if (s != NULL && atomic_fetch_sub(&s->refs, 1) == 1)
        session_free(s, s->discarded);
}

void merd_session_discard(merd_session *s)
{
    pthread_mutex_lock(&s->state);
    s->discarded = true;
    pthread_mutex_unlock(&s->state);
    atomic_store(&s->cancel, 1);
}

const char *merd_session_id(const merd_session *s)
{
    return s->id;
}

uint64_t merd_session_revision(merd_session *s)
{
    pthread_mutex_lock(&s->state);
    uint64_t r = s->revision;
    pthread_mutex_unlock(&s->state);
    return r;
}

uint32_t merd_session_internodes(merd_session *s)
{
    pthread_mutex_lock(&s->state);
    uint32_t n = s->internodes;
    pthread_mutex_unlock(&s->state);
    return n;
}

/* ---------------------------------------------------------------- edits */

typedef struct stop_ctx {
    merd_session *s;
    struct timespec started;
} stop_ctx;

static double seconds_since(const struct timespec *t)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - t->tv_sec) + 1e-9 * (double)(now.tv_nsec - t->tv_nsec);
}

/* Why the running batch should stop at this whole step, or NULL. */
static const char *should_stop(void *ctx, uint32_t done, uint32_t total)
{
    stop_ctx *c = ctx;
    merd_session *s = c->s;
    pthread_mutex_lock(&s->state);
    s->done = done;
    s->total = total;
    pthread_mutex_unlock(&s->state);
    if (atomic_load(&s->cancel))
        return "cancelled";
    if (c->s->cfg->max_seconds > 0 && seconds_since(&c->started) > s->cfg->max_seconds)
        return "time limit";
    mer_summary sum;
    mer_scene_summary(s->scene, &sum);
    if (sum.internodes >= s->cfg->max_internodes)
        return "internode limit";
    return NULL;
}

int merd_session_apply(merd_session *s, const merd_batch *batch, merd_batch_outcome *outcome,
                      merd_refusal *why)
{
    pthread_mutex_lock(&s->work);
    int rc = -1;
    if (merd_session_internodes(s) >= s->cfg->max_internodes) {
        merd_refuse(why, 409, "limit", "", "the tree has reached %u internodes, the most a session "
                   "may grow (meristemd --max-internodes); prune it or start another session",
                   s->cfg->max_internodes);
        goto out;
    }
    pthread_mutex_lock(&s->state);
    s->running = true;
    s->done = s->total = 0;
    pthread_mutex_unlock(&s->state);
    atomic_store(&s->cancel, 0);

    stop_ctx sc = {s, {0, 0}};
    clock_gettime(CLOCK_MONOTONIC, &sc.started);
    json_t *applied = NULL;
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    if (merd_batch_apply(batch, s->scene, should_stop, &sc, outcome, &applied, why) != 0) {
        // Refused halfway: undo what was applied by rebuilding from the journal.
        if (rebuild(s, error) != 0)
            fprintf(stderr, "meristemd: session %s could not be rebuilt: %s\n", s->id, error);
        goto done;
    }
    uint64_t revision = merd_session_revision(s);
    if (json_array_size(applied) > 0) {
        json_t *record = json_pack("{s:i, s:O}", "revision", (json_int_t)(revision + 1), "edits", applied);
        char *text = json_dumps(record, JSON_COMPACT | JSON_SORT_KEYS);
        json_decref(record);
        if (text == NULL || merd_journal_append(s->journal, text, strlen(text), error) != 0) {
            merd_refuse(why, 503, "journal", "", "the edits could not be journaled, so they were "
                       "undone: %s", text ? error : "out of memory");
            free(text);
            json_decref(applied);
            if (rebuild(s, error) != 0)
                fprintf(stderr, "meristemd: session %s could not be rebuilt: %s\n", s->id, error);
            goto done;
        }
        free(text);
        publish(s, revision + 1);
    }
    json_decref(applied);
    rc = 0;
done:
    pthread_mutex_lock(&s->state);
    s->running = false;
    pthread_mutex_unlock(&s->state);
out:
    pthread_mutex_unlock(&s->work);
    return rc;
}

void merd_session_sync(merd_session *s)
{
    if (pthread_mutex_trylock(&s->work) == 0) {
        merd_journal_sync(s->journal);
        pthread_mutex_unlock(&s->work);
    }
}

bool merd_session_cancel(merd_session *s)
{
    pthread_mutex_lock(&s->state);
    bool running = s->running;
    pthread_mutex_unlock(&s->state);
    if (running)
        atomic_store(&s->cancel, 1);
    return running;
}

/* ---------------------------------------------------------------- snapshots */

static void options_key(const merd_snapshot_options *o, char *out, size_t n)
{
    // Twig lines add "w1", so the keys of snapshots without them stay as they were.
    snprintf(out, n, "d%ul%um%uc%uq%ut%uz%u%s", o->mesh.detail ? o->mesh.detail : 3,
             o->mesh.leaves, o->mesh.markers, o->mesh.color, o->unquantized ? 0 : 1,
             o->mesh.no_uvs ? 0 : 1, o->compression, o->mesh.twig_lines ? "w1" : "");
}

void merd_session_etag(merd_session *s, const merd_snapshot_options *options, char *etag)
{
    char key[48];
    options_key(options, key, sizeof key);
    snprintf(etag, 64, "\"r%" PRIu64 "-%s\"", merd_session_revision(s), key);
}

int merd_session_snapshot(merd_session *s, const merd_snapshot_options *options, merd_snapshot **out,
                         char *etag, merd_refusal *why)
{
    pthread_mutex_lock(&s->work);
    merd_session_etag(s, options, etag);
    if (s->snap != NULL && strcmp(s->snap_key, etag) == 0) {
        atomic_fetch_add(&s->snap->refs, 1);
        *out = s->snap;
        pthread_mutex_unlock(&s->work);
        return 0;
    }
    mer_mesh *mesh = NULL;
    mer_error err = {0};
    mer_result rc = mer_mesh_build(s->scene, &options->mesh, &mesh, &err);
    merd_snapshot *snap = calloc(1, sizeof *snap);
    if (rc == MER_OK && snap != NULL) {
        const json_t *preset = json_object_get(s->spec, "preset");
        const json_t *seed = json_object_get(s->spec, "seed");
        mer_gltf_meta meta = {.session = s->id,
                              .revision = merd_session_revision(s),
                              .step = mer_scene_step_index(s->scene),
                              .preset = preset ? json_string_value(preset) : "default",
                              .seed = seed ? (uint64_t)json_integer_value(seed) : 0,
                              .detail = options->mesh.detail ? options->mesh.detail : 3,
                              .leaves = options->mesh.leaves,
                              .markers = options->mesh.markers,
                              .color = options->mesh.color};
        mer_gltf_options gopt = {.format = MER_GLTF_BINARY,
                                 .unquantized = options->unquantized,
                                 .compression = options->compression};
        rc = mer_gltf_write_tree(mesh, &meta, &gopt, &snap->bytes, &snap->size, &err);
    }
    mer_mesh_free(mesh);
    if (rc != MER_OK || snap == NULL) {
        free(snap);
        pthread_mutex_unlock(&s->work);
        return rc != MER_OK ? merd_refuse_lib(why, rc, &err, "")
                            : merd_refuse(why, 503, "out-of-memory", "", "out of memory for a snapshot");
    }
    atomic_init(&snap->refs, 2);  // the cache's and the caller's
    if (s->snap != NULL)
        merd_snapshot_release(s->snap);
    s->snap = snap;
    snprintf(s->snap_key, sizeof s->snap_key, "%s", etag);
    *out = snap;
    pthread_mutex_unlock(&s->work);
    return 0;
}

const uint8_t *merd_snapshot_bytes(const merd_snapshot *snap, size_t *size)
{
    *size = snap->size;
    return snap->bytes;
}

void merd_snapshot_release(merd_snapshot *snap)
{
    if (snap != NULL && atomic_fetch_sub(&snap->refs, 1) == 1) {
        mer_gltf_free(snap->bytes);
        free(snap);
    }
}
