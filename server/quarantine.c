/* meristemd — quarantined sessions (see quarantine.h). */
#include "config.h"

#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "server/quarantine.h"

typedef struct entry {
    char id[33];
    char reason[MERD_QUARANTINE_REASON_MAX];
} entry;

struct merd_quarantine {
    pthread_mutex_t lock;
    const char *data_dir;
    entry *items;
    size_t count, cap;
};

merd_quarantine *merd_quarantine_new(const char *data_dir)
{
    merd_quarantine *q = calloc(1, sizeof *q);
    if (q == NULL)
        return NULL;
    pthread_mutex_init(&q->lock, NULL);
    q->data_dir = data_dir;
    return q;
}

void merd_quarantine_free(merd_quarantine *q)
{
    if (q == NULL)
        return;
    pthread_mutex_destroy(&q->lock);
    free(q->items);
    free(q);
}

static int remember(merd_quarantine *q, const char *id, const char *reason)
{
    pthread_mutex_lock(&q->lock);
    int rc = 0;
    for (size_t i = 0; i < q->count; i++)
        if (strcmp(q->items[i].id, id) == 0)
            goto out;
    if (q->count == q->cap) {
        size_t cap = q->cap ? 2 * q->cap : 8;
        entry *grown = realloc(q->items, cap * sizeof *grown);
        if (grown == NULL) {
            rc = -1;
            goto out;
        }
        q->items = grown;
        q->cap = cap;
    }
    snprintf(q->items[q->count].id, sizeof q->items[0].id, "%.32s", id);
    snprintf(q->items[q->count].reason, sizeof q->items[0].reason, "%s", reason);
    q->count++;
out:
    pthread_mutex_unlock(&q->lock);
    return rc;
}

static bool is_hex_id(const char *s)
{
    for (int i = 0; i < 32; i++)
        if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'f')))
            return false;
    return true;
}

static void sync_dir(const char *path)
{
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

static void read_reason(const char *path, char *reason, size_t n)
{
    snprintf(reason, n, "quarantined (no reason recorded)");
    FILE *f = fopen(path, "re");
    if (f == NULL)
        return;
    if (fgets(reason, (int)n, f) != NULL)
        reason[strcspn(reason, "\n")] = '\0';
    fclose(f);
}

long merd_quarantine_load(merd_quarantine *q, FILE *log)
{
    char folder[PATH_MAX];
    snprintf(folder, sizeof folder, "%s/quarantine", q->data_dir);
    DIR *dir = opendir(folder);
    if (dir == NULL)
        return 0;
    long found = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        const char *name = e->d_name;
        if (strlen(name) < 40 || !is_hex_id(name) || strncmp(name + 32, ".journal", 8) != 0 ||
            strstr(name + 40, ".reason") != NULL)
            continue;
        char path[PATH_MAX + 300], reason[MERD_QUARANTINE_REASON_MAX];
        snprintf(path, sizeof path, "%s/%s.reason", folder, name);
        read_reason(path, reason, sizeof reason);
        char id[33];
        snprintf(id, sizeof id, "%.32s", name);
        if (remember(q, id, reason) == 0)
            found++;
    }
    closedir(dir);
    if (found > 0)
        fprintf(log, "meristemd: %ld sessions are quarantined in %s (not served; see the .reason files)\n",
                found, folder);
    return found;
}

/* The checkpoint beside journal `journal` ("<id>.journal[.k]"), in `out`: the
 * same name with .checkpoint for .journal. */
static void checkpoint_name(const char *journal, char *out, size_t n)
{
    const char *dot = strstr(journal, ".journal");
    assert(dot != NULL);
    snprintf(out, n, "%.*s.checkpoint%s", (int)(dot - journal), journal, dot + strlen(".journal"));
}

/* Moves <data-dir>/name into the quarantine folder under a name not taken yet,
 * and the session's checkpoint with it when there is one: a compacted journal
 * starts where its checkpoint ends and means nothing without it. `to` gets the
 * journal's new path. */
static int move_aside(merd_quarantine *q, const char *name, const char *reason, char *to, size_t n)
{
    char folder[PATH_MAX], from[PATH_MAX + 300];
    char ckpt_from[PATH_MAX + 300], ckpt_to[PATH_MAX + 310], ckpt[64];
    snprintf(folder, sizeof folder, "%s/quarantine", q->data_dir);
    snprintf(from, sizeof from, "%s/%s", q->data_dir, name);
    checkpoint_name(name, ckpt, sizeof ckpt);
    snprintf(ckpt_from, sizeof ckpt_from, "%s/%s", q->data_dir, ckpt);
    if (mkdir(folder, 0755) != 0 && errno != EEXIST)
        return -1;
    struct stat st;
    for (int k = 0; k < 1000; k++) {
        if (k == 0)
            snprintf(to, n, "%s/%s", folder, name);
        else
            snprintf(to, n, "%s/%s.%d", folder, name, k);
        checkpoint_name(to + strlen(folder) + 1, ckpt, sizeof ckpt);
        snprintf(ckpt_to, sizeof ckpt_to, "%s/%s", folder, ckpt);
        if (lstat(to, &st) != 0 && errno == ENOENT && lstat(ckpt_to, &st) != 0 && errno == ENOENT)
            break;
        if (k == 999)
            return -1;
    }
    if (rename(from, to) != 0)
        return -1;
    // Without it the journal stays readable as far as it goes; it is still kept.
    if (lstat(ckpt_from, &st) == 0)
        (void)rename(ckpt_from, ckpt_to);
    char why[PATH_MAX + 310];
    snprintf(why, sizeof why, "%s.reason", to);
    FILE *f = fopen(why, "wxe");
    if (f != NULL) {
        fprintf(f, "%s\n", reason);
        fflush(f);
        fsync(fileno(f));
        fclose(f);
    }
    sync_dir(folder);
    sync_dir(q->data_dir);
    return 0;
}

int merd_quarantine_add(merd_quarantine *q, const char *name, const char *id, const char *reason,
                        bool move, FILE *log)
{
    char to[PATH_MAX + 300] = "";
    int rc = move ? move_aside(q, name, reason, to, sizeof to) : 0;
    if (rc != 0)
        fprintf(log, "meristemd: QUARANTINED session %s: %s; it could not be moved aside (%s), so "
                "it stays in place, unchanged and not served\n", id, reason, strerror(errno));
    else if (move)
        fprintf(log, "meristemd: QUARANTINED session %s: %s; its journal is kept byte for byte in "
                "%s and the session is not served\n", id, reason, to);
    else
        fprintf(log, "meristemd: QUARANTINED session %s: %s; its journal stays in place, unchanged, "
                "and the session is not served until a restart can read it\n", id, reason);
    remember(q, id, reason);
    return rc;
}

bool merd_quarantine_find(merd_quarantine *q, const char *id, char *reason, size_t n)
{
    bool found = false;
    pthread_mutex_lock(&q->lock);
    for (size_t i = 0; i < q->count && !found; i++)
        if (strcmp(q->items[i].id, id) == 0) {
            found = true;
            snprintf(reason, n, "%s", q->items[i].reason);
        }
    pthread_mutex_unlock(&q->lock);
    return found;
}

void merd_quarantine_list(merd_quarantine *q, json_t *list)
{
    pthread_mutex_lock(&q->lock);
    for (size_t i = 0; i < q->count; i++)
        json_array_append_new(list, json_pack("{s:s, s:s, s:s}", "id", q->items[i].id, "state",
                                              "quarantined", "reason", q->items[i].reason));
    pthread_mutex_unlock(&q->lock);
}
