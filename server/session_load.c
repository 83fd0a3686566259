/* meristemd — loading a session from its checkpoint and journal, lazily and
 * once, and compacting the journal behind a checkpoint (see session.h).
 *
 * Compaction (--compact). Once the checkpoint at revision R is on disk (its
 * temporary file flushed, renamed, the folder flushed) and so is the journal's
 * record of R, the journal's records up to R are redundant. The journal is
 * rewritten as its first record alone, marked {"checkpoint": R}, under a
 * temporary name, flushed, renamed over the journal, the folder flushed. No
 * record follows R yet: the checkpoint is written right after R's record is
 * appended, under the session's `work` lock. A crash before the rename leaves
 * the old journal, which the checkpoint fits as any checkpoint does; after it,
 * the new one, which the checkpoint covers. Either way every acknowledged
 * revision is there.
 *
 * So a journal's first record may promise a checkpoint of at least revision R,
 * and its next record must then be R + 1. Loading refuses (the journal is
 * quarantined, never cut) a journal whose records skip a revision that no
 * valid checkpoint holds: records are consecutive, and the first one after
 * the creation is 1, or follows what the header or the checkpoint covers.
 */
#include "config.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "server/checkpoint.h"
#include "server/session_private.h"
#include "server/spec.h"

typedef struct replay_ctx {
    merd_session *s;
    uint64_t revision;    /* of the last record (or what the first one covers) */
    char *error;          /* the journal's reason (MERD_JOURNAL_ERROR_MAX bytes) */
    char detail[200];     /* why record `refused` was refused */
    size_t refused;
    mer_scene *base;      /* a checkpoint's scene, taken at record 0, or NULL */
    uint64_t base_revision;
    uint64_t covered;     /* what the first record says a checkpoint holds (compacted) */
    uint64_t first;       /* the first edit record's revision, 0 before it */
    size_t replayed;      /* records applied after the checkpoint */
} replay_ctx;

static int replay_creation(replay_ctx *r, const json_t *doc, merd_refusal *why)
{
    const json_t *create = json_object_get(doc, "create");
    const json_t *id = json_object_get(doc, "id");
    const json_t *covered = json_object_get(doc, "checkpoint");
    if (create == NULL || !json_is_string(id) || strcmp(json_string_value(id), r->s->id) != 0 ||
        (covered != NULL && (!json_is_integer(covered) || json_integer_value(covered) < 0)))
        return -1;
    r->covered = covered ? (uint64_t)json_integer_value(covered) : 0;
    if (r->covered > 0 && (r->base == NULL || r->base_revision < r->covered)) {
        merd_refuse(why, 0, "", "", "the journal was compacted to revision %llu and no checkpoint "
                    "holds it", (unsigned long long)r->covered);
        return -1;
    }
    r->revision = r->covered;
    // Replay builds what was accepted once, whatever today's limits say.
    const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX, true};
    r->s->scene = r->base ? r->base : merd_scene_from_spec(create, &unlimited, why);
    r->base = NULL;
    r->s->spec = json_deep_copy(create);
    const json_t *expires = json_object_get(doc, "expires_at");
    r->s->expires_at = json_is_number(expires) ? json_number_value(expires) : 0;
    if (r->s->scene == NULL)
        return -1;
    json_t *none = json_array();
    merd_session_record(r->s, 0, none, r->base_revision > 0 ? doc : NULL);
    json_decref(none);
    return 0;
}

static int replay_edits(replay_ctx *r, const json_t *doc, merd_refusal *why)
{
    const json_t *rev = json_object_get(doc, "revision");
    const json_t *edits = json_object_get(doc, "edits");
    if (r->s->scene == NULL || !json_is_integer(rev) || !json_is_array(edits))
        return -1;
    uint64_t revision = (uint64_t)json_integer_value(rev);
    uint64_t held = r->covered > r->base_revision ? r->covered : r->base_revision;
    if (r->first == 0 ? revision < 1 || revision > held + 1 || revision <= r->covered
                      : revision != r->revision + 1) {
        merd_refuse(why, 0, "", "", "revision %llu follows revision %llu and no checkpoint holds "
                    "the ones between", (unsigned long long)revision, (unsigned long long)r->revision);
        return -1;
    }
    if (r->first == 0)
        r->first = revision;
    r->revision = revision;
    // The checkpoint holds the records up to its revision.
    bool replay = revision > r->base_revision;
    const merd_past past = merd_session_past(r->s);
    if (replay && merd_batch_replay(edits, &r->s->scene, &past, why) != 0)
        return -1;
    r->replayed += replay;
    merd_session_record(r->s, revision, edits, replay ? NULL : doc);
    return 0;
}

static int replay_record(void *ctx, size_t index, const char *payload, size_t size)
{
    replay_ctx *r = ctx;
    json_error_t jerr;
    json_t *doc = json_loadb(payload, size, JSON_REJECT_DUPLICATES, &jerr);
    merd_refusal why = {0};
    int rc = doc == NULL ? -1 : index == 0 ? replay_creation(r, doc, &why) : replay_edits(r, doc, &why);
    if (rc != 0) {
        r->refused = index;
        snprintf(r->detail, sizeof r->detail, "%.180s",
                 why.detail[0] ? why.detail : "not a meristem journal record");
    }
    json_decref(doc);
    return rc;
}

/* Drops what a failed or superseded load left (caller holds `work`). */
static void unload(merd_session *s)
{
    merd_journal_close(s->journal, false);
    s->journal = NULL;
    mer_scene_free(s->scene);
    s->scene = NULL;
    json_decref(s->spec);
    s->spec = NULL;
}

/* Opens the journal of `s` and replays it onto the scene of `base` (taken,
 * may be NULL) when the journal reaches it (caller holds `work`; nothing is
 * loaded). 0 with the revision in r->revision, or -1 with `report` and
 * r->error saying why. */
static int replay_onto(merd_session *s, replay_ctx *r, merd_journal_report *report)
{
    bool from_checkpoint = r->base != NULL;
    s->journal = merd_journal_open(s->path, s->cfg->fsync, replay_record, r, report, r->error);
    mer_scene_free(r->base); /* not taken: the journal has no first record */
    r->base = NULL;
    if (s->journal == NULL || s->scene == NULL) {
        if (r->detail[0] != '\0')
            snprintf(r->error, MERD_JOURNAL_ERROR_MAX, "record %zu of %s.journal: %.180s",
                     r->refused, s->id, r->detail);
        unload(s);
        return -1;
    }
    if (!from_checkpoint || r->revision >= r->base_revision)
        return 0;
    // A journal shorter than its checkpoint (its tail was dropped after a power
    // cut): trust the journal if it has every record, else nothing is certain.
    unload(s);
    if (r->covered == 0 && r->first <= 1) {
        fprintf(stderr, "meristemd: session %s: the checkpoint (revision %llu) is past the journal "
                "(revision %llu): replaying it all\n", s->id, (unsigned long long)r->base_revision,
                (unsigned long long)r->revision);
        *r = (replay_ctx){.s = s, .error = r->error};
        return replay_onto(s, r, report);
    }
    report->fault = MERD_JOURNAL_DAMAGED;
    snprintf(r->error, MERD_JOURNAL_ERROR_MAX, "the journal ends at revision %llu, before its "
             "checkpoint (revision %llu), and does not start at revision 1",
             (unsigned long long)r->revision, (unsigned long long)r->base_revision);
    return -1;
}

/* Loads the scene, journal and spec of `s` from its checkpoint and journal
 * (caller holds `work`; nothing is loaded), saying so on stderr when `tell`.
 * 0 with the revision in `*revision`, or -1 with `report` and `error`. */
static int load(merd_session *s, merd_journal_report *report, char *error, uint64_t *revision,
                bool tell)
{
    replay_ctx r = {.s = s, .error = error};
    char why[MERD_JOURNAL_ERROR_MAX] = "";
    r.base = merd_checkpoint_read(s->checkpoint, s->id, &r.base_revision, why);
    if (r.base == NULL)
        r.base_revision = 0; /* replay every record */
    if (r.base == NULL && access(s->checkpoint, F_OK) == 0)
        fprintf(stderr, "meristemd: session %s: the checkpoint is not used: %s\n", s->id, why);
    bool from_checkpoint = r.base != NULL;
    if (replay_onto(s, &r, report) != 0)
        return -1;
    if (tell && from_checkpoint && r.base_revision > 0)
        fprintf(stderr, "meristemd: session %s: restored from its checkpoint at revision %llu "
                "and %zu journal records after it\n", s->id,
                (unsigned long long)r.base_revision, r.replayed);
    *revision = r.revision;
    return 0;
}

merd_session *merd_session_unloaded(const merd_session_config *cfg, const char *id)
{
    assert(strlen(id) == 32);
    return merd_session_new(cfg, id);
}

bool merd_session_is_loaded(merd_session *s)
{
    return atomic_load(&s->loaded) == MERD_LOADED;
}

int merd_session_load(merd_session *s, merd_session_loaded_fn done, void *ctx)
{
    int state = atomic_load(&s->loaded);
    if (state != MERD_NOT_LOADED)
        return state == MERD_LOADED ? 0 : -1;
    pthread_mutex_lock(&s->work);
    state = atomic_load(&s->loaded);
    if (state == MERD_NOT_LOADED) {
        char error[MERD_JOURNAL_ERROR_MAX] = "";
        merd_journal_report report = {0};
        uint64_t revision = 0;
        bool ok = load(s, &report, error, &revision, true) == 0;
        if (ok)
            merd_session_publish(s, revision);
        state = ok ? MERD_LOADED : MERD_LOAD_FAILED;
        if (done != NULL)
            done(ctx, s, &report, ok ? NULL : error);
        atomic_store(&s->loaded, state);
    }
    pthread_mutex_unlock(&s->work);
    return state == MERD_LOADED ? 0 : -1;
}

int merd_session_rebuild(merd_session *s, char *error)
{
    unload(s);
    uint64_t revision = 0;
    merd_journal_report report;
    return load(s, &report, error, &revision, false);
}

void merd_session_compact(merd_session *s, uint64_t revision)
{
    json_t *record = json_pack("{s:i, s:s, s:O, s:I}", "version", 1, "id", s->id, "create", s->spec,
                               "checkpoint", (json_int_t)revision);
    char *text = record ? json_dumps(record, JSON_COMPACT | JSON_SORT_KEYS) : NULL;
    json_decref(record);
    char error[MERD_JOURNAL_ERROR_MAX] = "out of memory";
    if (text == NULL || merd_journal_compact(s->journal, text, strlen(text), error) != 0)
        fprintf(stderr, "meristemd: session %s: the journal is not compacted at revision %llu: %s\n",
                s->id, (unsigned long long)revision, error);
    free(text);
}
