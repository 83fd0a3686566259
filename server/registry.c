/* meristemd — the session registry: an array in creation order under a
 * read-write lock, with an open-addressing index by id for O(1) lookups. */
#include "config.h"

#include <dirent.h>
#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>

#include "server/clock.h"
#include "server/decode.h"
#include "server/quarantine.h"
#include "server/registry.h"

struct merd_registry {
    pthread_rwlock_t lock;
    const merd_session_config *cfg;
    uint32_t max_sessions;
    merd_session **list;     /* creation order */
    size_t count, cap;
    merd_session **index;    /* open addressing by id; NULL empty, TOMBSTONE removed */
    size_t slots;           /* power of two */
    size_t used;            /* live + tombstones */
    merd_quarantine *quarantine;
};

static merd_session *const TOMBSTONE = (merd_session *)&TOMBSTONE;

/* Ids are 32 random hex digits (new_id draws them from getrandom), so their first 16
 * already are a uniform hash: read as a number, no hashing needed. A malformed
 * id asked for only has to land in some slot, where it matches nothing. */
static uint64_t hash_id(const char *id)
{
    uint64_t h = 0;
    for (int k = 0; k < 16 && id[k] != '\0'; k++) {
        unsigned c = (unsigned char)id[k];
        h = h << 4 | ((c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10) & 15u);
    }
    return h;
}

static merd_session **find_slot(merd_registry *r, const char *id, bool for_insert)
{
    size_t mask = r->slots - 1, i = (size_t)hash_id(id) & mask;
    merd_session **first_free = NULL;
    for (size_t probes = 0; probes < r->slots; probes++, i = (i + 1) & mask) {
        merd_session *s = r->index[i];
        if (s == NULL)
            return for_insert && first_free ? first_free : &r->index[i];
        if (s == TOMBSTONE) {
            if (first_free == NULL)
                first_free = &r->index[i];
        } else if (strcmp(merd_session_id(s), id) == 0) {
            return &r->index[i];
        }
    }
    return first_free;
}

static int grow_index(merd_registry *r)
{
    size_t slots = r->slots ? r->slots : 64;
    while (slots < 2 * (r->count + 1))
        slots *= 2;
    merd_session **index = calloc(slots, sizeof *index);
    if (index == NULL)
        return -1;
    merd_session **old = r->index;
    size_t old_slots = r->slots;
    r->index = index;
    r->slots = slots;
    r->used = 0;
    for (size_t i = 0; i < old_slots; i++)
        if (old[i] != NULL && old[i] != TOMBSTONE) {
            *find_slot(r, merd_session_id(old[i]), true) = old[i];
            r->used++;
        }
    free(old);
    return 0;
}

/* Adds `s` (taking over its reference). Caller holds the write lock. */
static int insert(merd_registry *r, merd_session *s)
{
    if ((r->used + 1) * 2 > r->slots && grow_index(r) != 0)
        return -1;
    if (r->count == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        merd_session **list = realloc(r->list, cap * sizeof *list);
        if (list == NULL)
            return -1;
        r->list = list;
        r->cap = cap;
    }
    merd_session **slot = find_slot(r, merd_session_id(s), true);
    if (*slot == NULL)
        r->used++;
    *slot = s;
    r->list[r->count++] = s;
    return 0;
}

merd_registry *merd_registry_new(const merd_session_config *cfg, uint32_t max_sessions)
{
    merd_registry *r = calloc(1, sizeof *r);
    if (r == NULL)
        return NULL;
    pthread_rwlock_init(&r->lock, NULL);
    r->cfg = cfg;
    r->max_sessions = max_sessions;
    r->quarantine = merd_quarantine_new(cfg->data_dir);
    if (r->quarantine == NULL || grow_index(r) != 0) {
        merd_quarantine_free(r->quarantine);
        free(r);
        return NULL;
    }
    return r;
}

/* `error` with the journal's full path put as its bare name: the reason is
 * shown to clients, who need not learn where the data folder is. */
static void bare_names(char *error, const char *path, const char *name)
{
    char *at = strstr(error, path);
    if (at == NULL)
        return;
    size_t plen = strlen(path), nlen = strlen(name);
    memmove(at + nlen, at + plen, strlen(at + plen) + 1);
    memcpy(at, name, nlen);
}

/* Takes `s` out of the list and the index (caller holds the write lock).
 * Whether it was there. */
static bool detach(merd_registry *r, merd_session *s)
{
    merd_session **slot = find_slot(r, merd_session_id(s), false);
    if (slot == NULL || *slot != s)
        return false;
    *slot = TOMBSTONE;
    for (size_t i = 0; i < r->count; i++)
        if (r->list[i] == s) {
            memmove(&r->list[i], &r->list[i + 1], (r->count - i - 1) * sizeof *r->list);
            r->count--;
            break;
        }
    return true;
}

/* What the call that loads a session does with the outcome, under the
 * session's lock (see merd_session_load): logs a dropped torn tail, or takes
 * a session that cannot load out of the registry and quarantines its journal,
 * or removes it when it is wholly a torn creation. */
static void loaded(void *ctx, merd_session *s, const merd_journal_report *report, const char *error)
{
    merd_registry *r = ctx;
    const char *id = merd_session_id(s);
    char name[48], path[4200], reason[MERD_JOURNAL_ERROR_MAX];
    snprintf(name, sizeof name, "%s.journal", id);
    snprintf(path, sizeof path, "%s/%s", r->cfg->data_dir, name);
    if (error == NULL) {
        if (report->dropped > 0)
            fprintf(stderr, "meristemd: %s: dropped a torn last record (%zu bytes)\n", name,
                    report->dropped);
        return;
    }
    merd_session *listed = merd_registry_get(r, id);
    merd_session_unref(listed);
    if (listed != s)
        return; /* deleted meanwhile: its journal is gone, not damaged */
    if (report->fault == MERD_JOURNAL_TORN_CREATION) {
        // A creation cut short was never acknowledged: the file is all torn tail.
        fprintf(stderr, "meristemd: %s: dropped a torn first record (a creation never acknowledged)\n", name);
        merd_journal_unlink(path, reason);
    } else {
        snprintf(reason, sizeof reason, "%s", error);
        bare_names(reason, path, name);
        merd_quarantine_add(r->quarantine, name, id, reason, report->fault == MERD_JOURNAL_DAMAGED, stderr);
    }
    // Quarantined before it leaves the registry: a request that misses it
    // there finds it in the quarantine, never a 404 in between.
    pthread_rwlock_wrlock(&r->lock);
    bool ours = detach(r, s);
    pthread_rwlock_unlock(&r->lock);
    if (ours)
        merd_session_unref(s); /* the registry's reference */
}

int merd_registry_load(merd_registry *r, merd_session *s, merd_refusal *why)
{
    if (merd_session_load(s, loaded, r) == 0)
        return 0;
    const char *id = merd_session_id(s);
    if (!merd_registry_quarantined(r, id, why))
        merd_refuse(why, 404, "unknown-session", "", "there is no session %.64s (GET /v1/sessions "
                    "lists them)", id);
    return -1;
}

merd_session *merd_registry_get_loaded(merd_registry *r, const char *id, merd_refusal *why)
{
    merd_session *s = merd_registry_get(r, id);
    if (s == NULL) {
        if (!merd_registry_quarantined(r, id, why))
            merd_refuse(why, 404, "unknown-session", "", "there is no session %.64s (GET "
                        "/v1/sessions lists them)", id);
        return NULL;
    }
    if (merd_registry_load(r, s, why) != 0) {
        merd_session_unref(s);
        return NULL;
    }
    return s;
}

typedef struct found {
    char name[41];
    struct timespec mtime;
} found;

/* Oldest journal first (the time of its last write), then by name, so that
 * the list and the background loader keep the same order every time. */
static int cmp_found(const void *a, const void *b)
{
    const found *x = a, *y = b;
    if (x->mtime.tv_sec != y->mtime.tv_sec)
        return x->mtime.tv_sec < y->mtime.tv_sec ? -1 : 1;
    if (x->mtime.tv_nsec != y->mtime.tv_nsec)
        return x->mtime.tv_nsec < y->mtime.tv_nsec ? -1 : 1;
    return strcmp(x->name, y->name);
}

/* The *.journal names in the data folder with their times (caller frees), or
 * NULL with `*n` 0 when there are none or no memory. One lstat each: never
 * opens a journal (a FIFO would block). */
static found *list_journals(merd_registry *r, DIR *dir, size_t *n)
{
    found *names = NULL;
    size_t cap = 0;
    *n = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len != 40 || strcmp(e->d_name + 32, ".journal") != 0)
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 64;
            found *grown = realloc(names, cap * sizeof *names);
            if (grown == NULL)
                break;
            names = grown;
        }
        char path[4200];
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", r->cfg->data_dir, e->d_name);
        memcpy(names[*n].name, e->d_name, 41);
        names[*n].mtime = lstat(path, &st) == 0 ? st.st_mtim : (struct timespec){0};
        (*n)++;
    }
    if (*n > 1)
        qsort(names, *n, sizeof *names, cmp_found);
    return names;
}

long merd_registry_scan(merd_registry *r, FILE *log)
{
    if (mkdir(r->cfg->data_dir, 0755) != 0 && errno != EEXIST) {
        fprintf(log, "meristemd: cannot create --data-dir %s: %s\n", r->cfg->data_dir, strerror(errno));
        return -1;
    }
    DIR *dir = opendir(r->cfg->data_dir);
    if (dir == NULL) {
        fprintf(log, "meristemd: cannot read --data-dir %s: %s\n", r->cfg->data_dir, strerror(errno));
        return -1;
    }
    size_t n = 0;
    found *names = list_journals(r, dir, &n);
    closedir(dir);
    merd_quarantine_load(r->quarantine, log);
    long known = 0;
    pthread_rwlock_wrlock(&r->lock);
    for (size_t i = 0; i < n; i++) {
        char id[33];
        snprintf(id, sizeof id, "%.32s", names[i].name);
        merd_session *s = merd_session_unloaded(r->cfg, id);
        if (s != NULL && insert(r, s) != 0)
            merd_session_unref(s);
        else
            known += s != NULL;
    }
    pthread_rwlock_unlock(&r->lock);
    free(names);
    return known;
}

merd_session **merd_registry_unloaded(merd_registry *r, size_t *n)
{
    pthread_rwlock_rdlock(&r->lock);
    merd_session **out = malloc((r->count ? r->count : 1) * sizeof *out);
    *n = 0;
    for (size_t i = 0; out != NULL && i < r->count; i++)
        if (!merd_session_is_loaded(r->list[i])) {
            merd_session_ref(r->list[i]);
            out[(*n)++] = r->list[i];
        }
    pthread_rwlock_unlock(&r->lock);
    return out;
}

static int new_id(char id[33])
{
    unsigned char bytes[16];
    size_t got = 0;
    while (got < sizeof bytes) {
        ssize_t n = getrandom(bytes + got, sizeof bytes - got, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        got += (size_t)n;
    }
    static const char hex[] = "0123456789abcdef";
    for (size_t i = 0; i < 16; i++) {
        id[2 * i] = hex[bytes[i] >> 4];
        id[2 * i + 1] = hex[bytes[i] & 15];
    }
    id[32] = '\0';
    return 0;
}

/* The longest time to live a session may ask for: a year. */
#define TTL_MAX (366u * 24 * 3600)

/* `spec` without its ttl_seconds (a new reference, the rest of the request is
 * the scene's) and the Unix time it gives, 0 for none. NULL with `why`. */
static json_t *take_ttl(const json_t *spec, double *expires_at, merd_refusal *why)
{
    *expires_at = 0;
    if (!json_is_object(spec) || json_object_get(spec, "ttl_seconds") == NULL)
        return json_incref((json_t *)spec);
    uint64_t ttl;
    if (merd_get_uint(spec, "ttl_seconds", "", 1, TTL_MAX, true, 0, &ttl, why) != 0)
        return NULL;
    json_t *rest = json_copy((json_t *)spec);
    if (rest == NULL) {
        merd_refuse(why, 503, "out-of-memory", "", "out of memory for a session");
        return NULL;
    }
    json_object_del(rest, "ttl_seconds");
    *expires_at = merd_wall_clock() + (double)ttl;
    return rest;
}

int merd_registry_create(merd_registry *r, const json_t *spec, merd_session **out, merd_refusal *why)
{
    pthread_rwlock_rdlock(&r->lock);
    size_t count = r->count;
    pthread_rwlock_unlock(&r->lock);
    if (count >= r->max_sessions)
        return merd_refuse(why, 429, "too-many-sessions", "",
                           "meristemd holds %u sessions, its limit (--max-sessions); delete one first",
                           r->max_sessions);
    char id[33];
    if (new_id(id) != 0)
        return merd_refuse(why, 503, "no-entropy", "", "the OS gave no random bytes for a session id");
    double expires_at = 0;
    json_t *scene_spec = take_ttl(spec, &expires_at, why);
    merd_session *s = scene_spec ? merd_session_create(r->cfg, id, scene_spec, expires_at, why) : NULL;
    json_decref(scene_spec);
    if (s == NULL)
        return -1;
    pthread_rwlock_wrlock(&r->lock);
    int rc = r->count >= r->max_sessions ? 1 : insert(r, s);
    pthread_rwlock_unlock(&r->lock);
    if (rc != 0) {
        char error[MERD_JOURNAL_ERROR_MAX];
        merd_session_discard(s, error);
        merd_session_unref(s);
        return rc > 0 ? merd_refuse(why, 429, "too-many-sessions", "",
                                    "meristemd holds %u sessions, its limit (--max-sessions)",
                                    r->max_sessions)
                      : merd_refuse(why, 503, "out-of-memory", "", "out of memory for a session");
    }
    merd_session_ref(s);
    *out = s;
    return 0;
}

merd_session *merd_registry_get(merd_registry *r, const char *id)
{
    pthread_rwlock_rdlock(&r->lock);
    merd_session **slot = find_slot(r, id, false);
    merd_session *s = slot != NULL && *slot != NULL && *slot != TOMBSTONE ? *slot : NULL;
    if (s != NULL)
        merd_session_ref(s);
    pthread_rwlock_unlock(&r->lock);
    return s;
}

int merd_registry_delete(merd_registry *r, const char *id, merd_refusal *why)
{
    pthread_rwlock_wrlock(&r->lock);
    merd_session **slot = find_slot(r, id, false);
    merd_session *s = slot != NULL && *slot != NULL && *slot != TOMBSTONE ? *slot : NULL;
    if (s != NULL)
        detach(r, s);
    pthread_rwlock_unlock(&r->lock);
    if (s == NULL)
        return merd_refuse(why, 404, "unknown-session", "", "there is no session %.64s", id);
    char error[MERD_JOURNAL_ERROR_MAX];
    int rc = merd_session_discard(s, error);
    merd_session_unref(s);
    if (rc != 0)
        return merd_refuse(why, 500, "journal", "", "session %s is stopped but its journal could not "
                           "be removed, so it may come back after a restart: %s", id, error);
    return 0;
}

bool merd_registry_quarantined(merd_registry *r, const char *id, merd_refusal *why)
{
    char reason[MERD_QUARANTINE_REASON_MAX];
    if (!merd_quarantine_find(r->quarantine, id, reason, sizeof reason))
        return false;
    merd_refuse(why, 503, "quarantined", "", "session %.32s is quarantined and not served: %.250s "
                "(its journal is kept unchanged in the data folder's quarantine/)", id, reason);
    return true;
}

/* Whether a list item is in the state a listing asks for: its own state
 * ("loaded", "not loaded", "quarantined"), "running" or "idle" (a loaded
 * session with or without a step running), or "live" (any but quarantined). */
static bool in_state(const json_t *item, const char *want)
{
    const char *state = json_string_value(json_object_get(item, "state"));
    if (state == NULL)
        state = "loaded";
    if (strcmp(want, state) == 0)
        return true;
    if (strcmp(want, "live") == 0)
        return strcmp(state, "quarantined") != 0;
    if (strcmp(state, "loaded") != 0)
        return false;
    bool running = json_is_true(json_object_get(json_object_get(item, "running"), "active"));
    return strcmp(want, running ? "running" : "idle") == 0;
}

static bool wanted(const json_t *item, const merd_list_query *q)
{
    const json_t *preset = json_object_get(item, "preset");
    if (q->preset != NULL && (!json_is_string(preset) || strcmp(json_string_value(preset), q->preset) != 0))
        return false;
    return q->state == NULL || in_state(item, q->state);
}

json_t *merd_registry_list(merd_registry *r, const merd_list_query *q)
{
    json_t *all = json_array();
    pthread_rwlock_rdlock(&r->lock);
    for (size_t i = 0; i < r->count; i++) {
        json_t *item = merd_session_summary(r->list[i], false);
        if (json_object_get(item, "state") == NULL)
            json_object_set_new(item, "state", json_string("loaded"));
        json_array_append_new(all, item);
    }
    pthread_rwlock_unlock(&r->lock);
    merd_quarantine_list(r->quarantine, all);
    // A page starts after the session named by `after`, in the order listed.
    json_t *page = json_array();
    size_t i = 0, n = json_array_size(all);
    if (q->after != NULL)
        while (i < n && strcmp(json_string_value(json_object_get(json_array_get(all, i++), "id")),
                               q->after) != 0)
            ;
    const json_t *last = NULL;
    for (; i < n; i++) {
        json_t *one = json_array_get(all, i);
        if (!wanted(one, q))
            continue;
        if (json_array_size(page) == q->limit)
            break;
        json_array_append(page, one);
        last = one;
    }
    json_t *next = i < n && last != NULL ? json_incref(json_object_get(last, "id")) : json_null();
    json_decref(all);
    return json_pack("{s:o, s:o}", "sessions", page, "next_after", next);
}

size_t merd_registry_expire(merd_registry *r, double now, FILE *log)
{
    char (*gone)[33] = NULL;
    size_t n = 0;
    pthread_rwlock_rdlock(&r->lock);
    for (size_t i = 0; i < r->count; i++) {
        double at = merd_session_expires(r->list[i]);
        if (at <= 0 || at > now)
            continue;
        if (gone == NULL && (gone = calloc(r->count, sizeof *gone)) == NULL)
            break;
        snprintf(gone[n++], sizeof gone[0], "%s", merd_session_id(r->list[i]));
    }
    pthread_rwlock_unlock(&r->lock);
    size_t removed = 0;
    for (size_t i = 0; i < n; i++) {
        merd_refusal why = {0};
        if (merd_registry_delete(r, gone[i], &why) == 0) {
            removed++;
            fprintf(log, "meristemd: session %s reached its ttl_seconds and was removed\n", gone[i]);
        } else if (why.status != 404) {
            fprintf(log, "meristemd: session %s reached its ttl_seconds: %s\n", gone[i], why.detail);
        }
    }
    free(gone);
    return removed;
}

void merd_registry_totals(merd_registry *r, uint32_t *sessions, uint64_t *internodes)
{
    pthread_rwlock_rdlock(&r->lock);
    *sessions = (uint32_t)r->count;
    *internodes = 0;
    for (size_t i = 0; i < r->count; i++)
        *internodes += merd_session_internodes(r->list[i]);
    pthread_rwlock_unlock(&r->lock);
}

void merd_registry_sync(merd_registry *r)
{
    pthread_rwlock_rdlock(&r->lock);
    for (size_t i = 0; i < r->count; i++)
        merd_session_sync(r->list[i]);
    pthread_rwlock_unlock(&r->lock);
}

void merd_registry_free(merd_registry *r)
{
    if (r == NULL)
        return;
    for (size_t i = 0; i < r->count; i++)
        merd_session_unref(r->list[i]);
    free(r->list);
    free(r->index);
    merd_quarantine_free(r->quarantine);
    pthread_rwlock_destroy(&r->lock);
    free(r);
}
