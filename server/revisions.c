/* meristemd — a session's revisions and its kept states (see revisions.h). */
#include "config.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "server/checkpoint.h"
#include "server/edits.h"
#include "server/journal.h"
#include "server/revisions.h"
#include "server/snapshot.h"
#include "server/spec.h"

typedef struct entry {
    json_t *edits;        /* NULL: not recorded (the journal no longer has it) */
    int64_t step, internodes;
    uint64_t tree;        /* the revision that first made this tree */
} entry;

typedef struct kept_glb {
    char key[MERD_ETAG_MAX];
    merd_snapshot *snap;
    size_t size;
    uint64_t used;
} kept_glb;

struct merd_revisions {
    entry *list;
    size_t count, cap;
    struct {
        mer_scene *scene; /* NULL: a free slot */
        uint64_t revision, used;
    } state[MERD_REVISION_STATES];
    kept_glb *glb;
    size_t glbs, glb_cap, glb_bytes;
    uint64_t clock;
    struct {
        struct timespec mtime; /* of the checkpoint file when last read */
        off_t size;
        uint64_t revision;     /* its revision then */
        bool known;
    } checkpoint;
};

merd_revisions *merd_revisions_new(void)
{
    return calloc(1, sizeof(merd_revisions));
}

void merd_revisions_free(merd_revisions *h)
{
    if (h == NULL)
        return;
    for (size_t i = 0; i < h->count; i++)
        json_decref(h->list[i].edits);
    free(h->list);
    for (size_t k = 0; k < MERD_REVISION_STATES; k++)
        mer_scene_free(h->state[k].scene);
    for (size_t i = 0; i < h->glbs; i++)
        merd_snapshot_release(h->glb[i].snap);
    free(h->glb);
    free(h);
}

int merd_revisions_add(merd_revisions *h, uint64_t revision, const json_t *edits, int64_t step,
                       int64_t internodes)
{
    if (revision >= h->cap) {
        size_t cap = h->cap ? h->cap : 64;
        while (cap <= revision)
            cap *= 2;
        entry *list = realloc(h->list, cap * sizeof *list);
        if (list == NULL)
            return -1;
        memset(list + h->cap, 0, (cap - h->cap) * sizeof *list);
        h->list = list;
        h->cap = cap;
    }
    // A lone revert makes no new tree: it is its target's, whose GLB it gives.
    const json_t *only = json_array_size(edits) == 1 ? json_array_get(edits, 0) : NULL;
    const json_t *op = json_object_get(only, "op"), *to = json_object_get(only, "revision");
    uint64_t tree = revision;
    if (json_is_string(op) && strcmp(json_string_value(op), "revert") == 0 && json_is_integer(to) &&
        (uint64_t)json_integer_value(to) < revision && (uint64_t)json_integer_value(to) < h->count)
        tree = h->list[json_integer_value(to)].tree;
    entry *e = &h->list[revision];
    json_decref(e->edits);
    *e = (entry){json_incref((json_t *)edits), step, internodes, tree};
    if (revision >= h->count)
        h->count = revision + 1;
    return 0;
}

uint64_t merd_revisions_count(const merd_revisions *h)
{
    return h->count;
}

uint64_t merd_revisions_tree(const merd_revisions *h, uint64_t revision)
{
    return revision < h->count ? h->list[revision].tree : revision;
}

static json_t *count_json(int64_t n)
{
    return n >= 0 ? json_integer((json_int_t)n) : json_null();
}

json_t *merd_revisions_page(const merd_revisions *h, uint64_t after, bool from_start, size_t limit)
{
    json_t *list = json_array();
    uint64_t r = from_start ? 0 : after + 1;
    for (; r < h->count && json_array_size(list) < limit; r++) {
        const entry *e = &h->list[r];
        if (e->edits == NULL)
            continue;
        json_array_append_new(list, json_pack("{s:I, s:O, s:o, s:o}", "revision", (json_int_t)r,
                                              "edits", e->edits, "step", count_json(e->step),
                                              "internodes", count_json(e->internodes)));
    }
    json_t *next = r < h->count && json_array_size(list) > 0 ? json_integer((json_int_t)(r - 1))
                                                             : json_null();
    return json_pack("{s:o, s:o}", "revisions", list, "next_after", next);
}

void merd_revisions_keep(merd_revisions *h, uint64_t revision, mer_scene *scene)
{
    size_t victim = 0;
    for (size_t k = 0; k < MERD_REVISION_STATES; k++) {
        if (h->state[k].scene != NULL && h->state[k].revision == revision) {
            mer_scene_free(scene); /* the same tree is kept already */
            h->state[k].used = ++h->clock;
            return;
        }
        if (h->state[k].scene == NULL ||
            (h->state[victim].scene != NULL && h->state[k].used < h->state[victim].used))
            victim = k;
    }
    mer_scene_free(h->state[victim].scene);
    h->state[victim].scene = scene;
    h->state[victim].revision = revision;
    h->state[victim].used = ++h->clock;
}

/* A copy of the kept state nearest at or before `revision`, and its revision;
 * NULL when none is kept (or out of memory). */
static mer_scene *nearest_state(merd_revisions *h, uint64_t revision, uint64_t *at)
{
    int best = -1;
    for (int k = 0; k < MERD_REVISION_STATES; k++)
        if (h->state[k].scene != NULL && h->state[k].revision <= revision &&
            (best < 0 || h->state[k].revision > h->state[best].revision))
            best = k;
    mer_scene *copy = NULL;
    mer_error err = {0};
    if (best < 0 || mer_scene_clone(h->state[best].scene, &copy, &err) != MER_OK)
        return NULL;
    h->state[best].used = ++h->clock;
    *at = h->state[best].revision;
    return copy;
}

/* Whether reading the checkpoint may help derive `revision`: not when the
 * file, unchanged since it was last read, is of a later revision. */
static bool useful_checkpoint(const merd_revisions *h, const merd_revision_origin *o,
                              uint64_t revision)
{
    struct stat st;
    if (o->checkpoint == NULL || stat(o->checkpoint, &st) != 0)
        return false;
    return !(h->checkpoint.known && h->checkpoint.revision > revision &&
             h->checkpoint.size == st.st_size && h->checkpoint.mtime.tv_sec == st.st_mtim.tv_sec &&
             h->checkpoint.mtime.tv_nsec == st.st_mtim.tv_nsec);
}

static void remember_checkpoint(merd_revisions *h, const merd_revision_origin *o, bool read,
                                uint64_t revision)
{
    struct stat st;
    if (!read || stat(o->checkpoint, &st) != 0)
        return;
    h->checkpoint.mtime = st.st_mtim;
    h->checkpoint.size = st.st_size;
    h->checkpoint.revision = revision;
    h->checkpoint.known = true;
}

/* The scene a derivation of `revision` starts from and its revision: the
 * nearest kept state, or the checkpoint when it is nearer, or the creation. */
static mer_scene *start_state(merd_revisions *h, const merd_revision_origin *o, uint64_t revision,
                              uint64_t *at, merd_refusal *why)
{
    mer_scene *scene = nearest_state(h, revision, at);
    if (scene != NULL && *at == revision)
        return scene;
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    uint64_t cp = 0;
    mer_scene *loaded = useful_checkpoint(h, o, revision)
                            ? merd_checkpoint_read(o->checkpoint, o->id, &cp, error)
                            : NULL;
    remember_checkpoint(h, o, loaded != NULL, cp);
    if (loaded != NULL && cp <= revision && cp < h->count && (scene == NULL || cp > *at)) {
        mer_scene_free(scene);
        scene = loaded;
        *at = cp;
    } else {
        mer_scene_free(loaded);
    }
    if (scene != NULL)
        return scene;
    // Replay builds what was accepted once, whatever today's limits say.
    const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX, true};
    *at = 0;
    return merd_scene_from_spec(o->spec, &unlimited, why);
}

typedef struct derive_ctx {
    merd_revisions *h;
    const merd_revision_origin *origin;
} derive_ctx;

static int derive_past(void *ctx, uint64_t revision, const char *field, mer_scene **out,
                       merd_refusal *why)
{
    derive_ctx *d = ctx;
    return merd_revisions_scene(d->h, d->origin, revision, field, out, why);
}

/* Keeps a copy of `scene`, the tree at `revision`; without memory, nothing. */
static void keep_copy(merd_revisions *h, uint64_t revision, const mer_scene *scene)
{
    mer_scene *copy = NULL;
    mer_error err = {0};
    if (mer_scene_clone(scene, &copy, &err) == MER_OK)
        merd_revisions_keep(h, revision, copy);
}

int merd_revisions_scene(merd_revisions *h, const merd_revision_origin *origin, uint64_t revision,
                         const char *field, mer_scene **out, merd_refusal *why)
{
    *out = NULL;
    if (revision >= h->count || h->list[revision].edits == NULL)
        return merd_refuse(why, 422, "unknown-revision", field,
                           "revision %" PRIu64 " is not one of this session's: use 0 to %" PRIu64
                           " (GET /v1/sessions/{id}/revisions lists them)", revision,
                           h->count ? (uint64_t)h->count - 1 : 0);
    uint64_t at = 0;
    mer_scene *scene = start_state(h, origin, revision, &at, why);
    if (scene == NULL)
        return -1;
    derive_ctx d = {h, origin};
    const merd_past past = {.scene_at = derive_past, .ctx = &d};
    for (uint64_t r = at + 1; r <= revision; r++) {
        if (h->list[r].edits == NULL || merd_batch_replay(h->list[r].edits, &scene, &past, why) != 0) {
            if (h->list[r].edits == NULL)
                merd_refuse(why, 422, "unknown-revision", field, "revision %" PRIu64 " can no "
                            "longer be derived: the journal before it is gone", revision);
            mer_scene_free(scene);
            return -1;
        }
        // States at distances 1, 2, 4, ... before the target make scrubbing
        // backwards a short replay from a kept state.
        uint64_t back = revision - r;
        if (back > 0 && (back & (back - 1)) == 0)
            keep_copy(h, r, scene);
    }
    if (at != revision)
        keep_copy(h, revision, scene);
    *out = scene;
    return 0;
}

merd_snapshot *merd_revisions_glb(merd_revisions *h, const char *key)
{
    for (size_t i = 0; i < h->glbs; i++)
        if (strcmp(h->glb[i].key, key) == 0) {
            h->glb[i].used = ++h->clock;
            return merd_snapshot_ref(h->glb[i].snap);
        }
    return NULL;
}

/* Drops the least recently used past snapshot. */
static void drop_oldest_glb(merd_revisions *h)
{
    size_t old = 0;
    for (size_t i = 1; i < h->glbs; i++)
        if (h->glb[i].used < h->glb[old].used)
            old = i;
    h->glb_bytes -= h->glb[old].size;
    merd_snapshot_release(h->glb[old].snap);
    h->glb[old] = h->glb[--h->glbs];
}

void merd_revisions_glb_put(merd_revisions *h, const char *key, merd_snapshot *snap)
{
    size_t size = 0;
    merd_snapshot_bytes(snap, &size);
    if (size > MERD_REVISION_GLB_BYTES)
        return;
    while (h->glbs > 0 && h->glb_bytes + size > MERD_REVISION_GLB_BYTES)
        drop_oldest_glb(h);
    if (h->glbs == h->glb_cap) {
        size_t cap = h->glb_cap ? 2 * h->glb_cap : 16;
        kept_glb *glb = realloc(h->glb, cap * sizeof *glb);
        if (glb == NULL)
            return;
        h->glb = glb;
        h->glb_cap = cap;
    }
    kept_glb *k = &h->glb[h->glbs++];
    snprintf(k->key, sizeof k->key, "%s", key);
    k->snap = merd_snapshot_ref(snap);
    k->size = size;
    k->used = ++h->clock;
    h->glb_bytes += size;
}
