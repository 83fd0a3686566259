/* meristemd — live sessions: lifecycle, reference counts, applying and
 * journaling batches (see session.h). */
#include "config.h"

#include <assert.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "server/checkpoint.h"
#include "server/clock.h"
#include "server/session_private.h"
#include "server/spec.h"

merd_session *merd_session_new(const merd_session_config *cfg, const char *id)
{
    merd_session *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    atomic_init(&s->refs, 1);
    atomic_init(&s->cancel, 0);
    atomic_init(&s->loaded, MERD_NOT_LOADED);
    snprintf(s->id, sizeof s->id, "%s", id);
    snprintf(s->path, sizeof s->path, "%s/%s.journal", cfg->data_dir, id);
    snprintf(s->checkpoint, sizeof s->checkpoint, "%s/%s.checkpoint", cfg->data_dir, id);
    s->cfg = cfg;
    s->revs = merd_revisions_new();
    if (s->revs == NULL) {
        free(s);
        return NULL;
    }
    pthread_mutex_init(&s->work, NULL);
    pthread_mutex_init(&s->state, NULL);
    return s;
}

static void session_free(merd_session *s, bool remove)
{
    merd_journal_close(s->journal, remove);
    if (remove)
        unlink(s->checkpoint);
    mer_scene_free(s->scene);
    json_decref(s->spec);
    json_decref(s->summary);
    free(s->summary_text);
    free(s->short_text);
    merd_snapshot_cache_clear(&s->snaps);
    merd_revisions_free(s->revs);
    pthread_mutex_destroy(&s->work);
    pthread_mutex_destroy(&s->state);
    free(s);
}

/* The step and living internodes of `scene`, as a journal record holds them. */
static void record_counts(json_t *record, const mer_scene *scene)
{
    mer_summary sum;
    mer_scene_summary(scene, &sum);
    json_object_set_new(record, "step", json_integer(sum.step));
    json_object_set_new(record, "internodes", json_integer(sum.internodes));
}

merd_session *merd_session_create(const merd_session_config *cfg, const char *id, const json_t *spec,
                                  double expires_at, merd_refusal *why)
{
    merd_session *s = merd_session_new(cfg, id);
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
    s->expires_at = expires_at;
    json_t *record = json_pack("{s:i, s:s, s:O}", "version", 1, "id", id, "create", s->spec);
    record_counts(record, s->scene);
    if (expires_at > 0)
        json_object_set_new(record, "expires_at", json_real(expires_at));
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
    json_t *none = json_array();
    merd_session_record(s, 0, none, NULL);
    json_decref(none);
    merd_session_publish(s, 0);
    atomic_store(&s->loaded, MERD_LOADED);
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

int merd_session_discard(merd_session *s, char *error)
{
    pthread_mutex_lock(&s->state);
    s->discarded = true;
    pthread_mutex_unlock(&s->state);
    atomic_store(&s->cancel, 1);
    // Gone now, not when the running batch lets go: that batch only appends
    // through its open descriptor (to the unlinked file) and never reopens it.
    // The journal first: a crash between the two leaves a checkpoint without
    // its journal, which nothing loads, never a compacted journal without the
    // checkpoint it needs.
    int rc = merd_journal_unlink(s->path, error);
    if (rc == 0 && unlink(s->checkpoint) != 0 && errno != ENOENT)
        fprintf(stderr, "meristemd: session %s: its checkpoint stays: %s\n", s->id, strerror(errno));
    char tmp[PATH_MAX + 8];
    snprintf(tmp, sizeof tmp, "%s.tmp", s->path); /* a compaction a crash cut short */
    unlink(tmp);
    return rc;
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

/* ---------------------------------------------------------------- applying */

static bool discarded(merd_session *s)
{
    pthread_mutex_lock(&s->state);
    bool gone = s->discarded;
    pthread_mutex_unlock(&s->state);
    return gone;
}

typedef struct stop_ctx {
    merd_session *s;
    double started;   /* merd_now() */
} stop_ctx;

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
    if (s->cfg->stopping != NULL && atomic_load(s->cfg->stopping))
        return "shutting down";
    if (c->s->cfg->max_seconds > 0 && merd_now() - c->started > s->cfg->max_seconds)
        return "time limit";
    mer_summary sum;
    mer_scene_summary(s->scene, &sum);
    if (sum.internodes >= s->cfg->max_internodes)
        return "internode limit";
    return NULL;
}

/* Writes a checkpoint every cfg->checkpoint_every revisions (caller holds
 * `work`), then compacts the journal (--compact). A failure costs only restore
 * time: the journal has every record the checkpoints do not. */
static void checkpoint(merd_session *s, uint64_t revision)
{
    uint32_t every = s->cfg->checkpoint_every;
    if (every == 0 || revision % every != 0 || discarded(s))
        return;
    // Compaction drops records on the strength of the checkpoint: both the
    // record of `revision` and the checkpoint must be on disk before it.
    bool sync = s->cfg->fsync == MERD_FSYNC_ALWAYS || s->cfg->compact;
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    if (s->cfg->compact && merd_journal_sync(s->journal) != 0) {
        fprintf(stderr, "meristemd: session %s: no checkpoint at revision %llu: the journal "
                "could not be flushed\n", s->id, (unsigned long long)revision);
        return;
    }
    if (merd_checkpoint_write(s->checkpoint, s->id, revision, s->scene, sync, error) != 0) {
        fprintf(stderr, "meristemd: session %s: no checkpoint at revision %llu: %s\n", s->id,
                (unsigned long long)revision, error);
        return;
    }
    if (s->cfg->compact)
        merd_session_compact(s, revision);
}

/* Puts back the scene as it was before a refused batch (caller holds `work`):
 * the copy taken then, or the journal replayed, or nothing (see merd_undo). */
static void undo(merd_session *s, merd_undo how, mer_scene *before)
{
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    if (how == MERD_UNDO_COPY) {
        mer_scene_free(s->scene);
        s->scene = before;
    } else if (how == MERD_UNDO_REPLAY && merd_session_rebuild(s, error) != 0) {
        fprintf(stderr, "meristemd: session %s could not be rebuilt: %s\n", s->id, error);
    }
}

int merd_session_apply(merd_session *s, const merd_batch *batch, merd_batch_outcome *outcome,
                       merd_refusal *why)
{
    assert(merd_session_is_loaded(s));
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

    merd_undo how = merd_batch_undo(batch);
    mer_scene *before = NULL;
    mer_error err = {0};
    if (how == MERD_UNDO_COPY && mer_scene_clone(s->scene, &before, &err) != MER_OK) {
        merd_refuse_lib(why, err.code, &err, "");
        goto done;
    }
    stop_ctx sc = {s, merd_now()};
    json_t *applied = NULL;
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    const merd_past past = merd_session_past(s);
    if (merd_batch_apply(batch, &s->scene, &past, should_stop, &sc, outcome, &applied, why) != 0) {
        if (discarded(s))
            mer_scene_free(before); /* deleted meanwhile: nothing to put back */
        else
            undo(s, how, before);
        goto done;
    }
    uint64_t revision = merd_session_revision(s);
    if (json_array_size(applied) > 0 && discarded(s)) {
        json_decref(applied);
        mer_scene_free(before);
        merd_refuse(why, 404, "unknown-session", "", "session %s was deleted while this batch ran", s->id);
        goto done;
    }
    if (json_array_size(applied) > 0) {
        json_t *record = json_pack("{s:i, s:O}", "revision", (json_int_t)(revision + 1), "edits", applied);
        record_counts(record, s->scene);
        char *text = json_dumps(record, JSON_COMPACT | JSON_SORT_KEYS);
        if (text == NULL || merd_journal_append(s->journal, text, strlen(text), error) != 0) {
            merd_refuse(why, 503, "journal", "", "the edits could not be journaled, so they were "
                        "undone: %s", text ? error : "out of memory");
            free(text);
            json_decref(record);
            json_decref(applied);
            undo(s, how == MERD_UNDO_NOTHING ? MERD_UNDO_REPLAY : how, before);
            goto done;
        }
        free(text);
        merd_session_record(s, revision + 1, applied, record);
        json_decref(record);
        merd_session_publish(s, revision + 1);
        checkpoint(s, revision + 1);
    }
    json_decref(applied);
    mer_scene_free(before);
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
