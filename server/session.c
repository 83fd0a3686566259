/* meristemd — live sessions: lifecycle, reference counts, applying and
 * journaling batches (see session.h). */
#include "config.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "server/checkpoint.h"
#include "server/clock.h"
#include "server/session_private.h"
#include "server/spec.h"

static merd_session *session_new(const merd_session_config *cfg, const char *id)
{
    merd_session *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    atomic_init(&s->refs, 1);
    atomic_init(&s->cancel, 0);
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
    return s;
}

typedef struct replay_ctx {
    merd_session *s;
    uint64_t revision;
    char *error;
    mer_scene *base;      /* a checkpoint's scene, taken at record 0, or NULL */
    uint64_t base_revision;
    size_t replayed;      /* records applied after the checkpoint */
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
        const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX, true};
        r->s->scene = r->base ? r->base : merd_scene_from_spec(create, &unlimited, &why);
        r->base = NULL;
        r->s->spec = json_deep_copy(create);
        const json_t *expires = json_object_get(doc, "expires_at");
        r->s->expires_at = json_is_number(expires) ? json_number_value(expires) : 0;
        rc = r->s->scene != NULL ? 0 : -1;
        json_t *none = json_array();
        if (rc == 0)
            merd_session_record(r->s, 0, none, r->base_revision > 0 ? doc : NULL);
        json_decref(none);
    } else {
        const json_t *rev = json_object_get(doc, "revision");
        const json_t *edits = json_object_get(doc, "edits");
        if (r->s->scene == NULL || !json_is_integer(rev) || !json_is_array(edits))
            goto done;
        r->revision = (uint64_t)json_integer_value(rev);
        // The checkpoint holds the records up to its revision.
        bool replay = r->revision > r->base_revision;
        const merd_past past = merd_session_past(r->s);
        rc = replay ? merd_batch_replay(edits, &r->s->scene, &past, &why) : 0;
        r->replayed += replay;
        if (rc == 0)
            merd_session_record(r->s, r->revision, edits, replay ? NULL : doc);
    }
done:
    if (rc != 0)
        snprintf(r->error, MERD_JOURNAL_ERROR_MAX, "record %zu: %.200s", index,
                 why.detail[0] ? why.detail : "not a meristem journal record");
    json_decref(doc);
    return rc;
}

/* Builds the session's scene afresh from its journal, the whole of it (caller
 * holds `work`); `r` is fresh and is filled as replay_record does. */
static int rebuild(merd_session *s, replay_ctx *r, merd_journal_report *report)
{
    merd_journal_close(s->journal, false);
    s->journal = NULL;
    mer_scene_free(s->scene);
    s->scene = NULL;
    json_decref(s->spec);
    s->spec = NULL;
    s->journal = merd_journal_open(s->path, s->cfg->fsync, replay_record, r, report, r->error);
    return s->journal != NULL && s->scene != NULL ? 0 : -1;
}

/* Opens the journal of `s` and replays it onto its checkpoint's scene when
 * there is one that the journal reaches; `r` is filled as replay_record does. */
static void replay_from_checkpoint(merd_session *s, replay_ctx *r, merd_journal_report *report)
{
    char why[MERD_JOURNAL_ERROR_MAX] = "";
    r->base = merd_checkpoint_read(s->checkpoint, s->id, &r->base_revision, why);
    if (r->base == NULL)
        r->base_revision = 0; /* replay every record */
    if (r->base == NULL && access(s->checkpoint, F_OK) == 0)
        fprintf(stderr, "meristemd: session %s: the checkpoint is not used: %s\n", s->id, why);
    bool from_checkpoint = r->base != NULL;
    s->journal = merd_journal_open(s->path, s->cfg->fsync, replay_record, r, report, r->error);
    mer_scene_free(r->base); /* not taken: the journal has no first record */
    r->base = NULL;
    if (s->journal == NULL || !from_checkpoint)
        return;
    if (r->revision >= r->base_revision) {
        fprintf(stderr, "meristemd: session %s: restored from its checkpoint at revision %llu "
                "and %zu journal records after it\n", s->id,
                (unsigned long long)r->base_revision, r->replayed);
        return;
    }
    // A journal shorter than its checkpoint (its tail was dropped): trust the journal.
    fprintf(stderr, "meristemd: session %s: the checkpoint (revision %llu) is past the journal "
            "(revision %llu): replaying it all\n", s->id, (unsigned long long)r->base_revision,
            (unsigned long long)r->revision);
    *r = (replay_ctx){.s = s, .error = r->error};
    rebuild(s, r, report);
}

merd_session *merd_session_restore(const merd_session_config *cfg, const char *path,
                                   merd_journal_report *report, char *error)
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
    if (s == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory for a session");
        return NULL;
    }
    replay_ctx r = {.s = s, .error = error};
    replay_from_checkpoint(s, &r, report);
    if (s->journal == NULL || s->scene == NULL) {
        session_free(s, false);
        return NULL;
    }
    merd_session_publish(s, r.revision);
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
    // The checkpoint first: a crash between the two leaves a journal that
    // restores whole, never a checkpoint without its journal.
    if (unlink(s->checkpoint) != 0 && errno != ENOENT)
        fprintf(stderr, "meristemd: session %s: its checkpoint stays: %s\n", s->id, strerror(errno));
    return merd_journal_unlink(s->path, error);
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
 * `work`). A failure costs only restore time: the journal has every record. */
static void checkpoint(merd_session *s, uint64_t revision)
{
    uint32_t every = s->cfg->checkpoint_every;
    if (discarded(s))
        return;
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    if (every > 0 && revision % every == 0 &&
        merd_checkpoint_write(s->checkpoint, s->id, revision, s->scene,
                              s->cfg->fsync == MERD_FSYNC_ALWAYS, error) != 0)
        fprintf(stderr, "meristemd: session %s: no checkpoint at revision %llu: %s\n", s->id,
                (unsigned long long)revision, error);
}

/* Puts back the scene as it was before a refused batch (caller holds `work`):
 * the copy taken then, or the journal replayed, or nothing (see merd_undo). */
static void undo(merd_session *s, merd_undo how, mer_scene *before)
{
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    if (how == MERD_UNDO_COPY) {
        mer_scene_free(s->scene);
        s->scene = before;
    } else if (how == MERD_UNDO_REPLAY && rebuild(s, &(replay_ctx){.s = s, .error = error}, NULL) != 0) {
        fprintf(stderr, "meristemd: session %s could not be rebuilt: %s\n", s->id, error);
    }
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
