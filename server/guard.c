/* meristemd — the connection guard (see guard.h). */
#include "config.h"

#include <errno.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>

#include "server/clock.h"
#include "server/guard.h"
#include "server/guard_private.h"

typedef struct entry {
    struct MHD_Connection *connection;
    double deadline;             /* merd_now() */
    bool listed;                 /* waiting for a head, in the list */
    struct entry *prev, *next;   /* arrival order: oldest first */
} entry;

struct merd_guard {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t sweeper;
    bool stopping;
    unsigned soft_limit;
    double head_seconds, idle_seconds;
    unsigned open;               /* connections started and not closed */
    size_t cuts;
    entry *head, *tail;
};

static void unlist(merd_guard *g, entry *e)
{
    if (!e->listed)
        return;
    if (e->prev != NULL)
        e->prev->next = e->next;
    else
        g->head = e->next;
    if (e->next != NULL)
        e->next->prev = e->prev;
    else
        g->tail = e->prev;
    e->prev = e->next = NULL;
    e->listed = false;
}

static void list_at_end(merd_guard *g, entry *e, double deadline)
{
    unlist(g, e);
    e->deadline = deadline;
    e->prev = g->tail;
    if (g->tail != NULL)
        g->tail->next = e;
    else
        g->head = e;
    g->tail = e;
    e->listed = true;
}

/* Shuts the connection's socket (caller holds the lock, so libmicrohttpd has
 * not closed the descriptor yet: it tells us CLOSED first). */
static void cut(merd_guard *g, entry *e)
{
    unlist(g, e);
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(e->connection, MHD_CONNECTION_INFO_CONNECTION_FD);
    if (info != NULL)
        shutdown(info->connect_fd, SHUT_RDWR);
    g->cuts++;
}

/* Cuts every listed connection whose deadline is past at `now` (caller holds
 * the lock). Deadlines differ (head or idle), so the whole list is looked at: a
 * few thousand entries at most, twice a second. */
static void sweep_at(merd_guard *g, double now)
{
    for (entry *e = g->head, *next; e != NULL; e = next) {
        next = e->next;
        if (e->deadline <= now)
            cut(g, e);
    }
}

size_t merd_guard_sweep(merd_guard *g, double now)
{
    pthread_mutex_lock(&g->lock);
    size_t before = g->cuts;
    sweep_at(g, now);
    size_t n = g->cuts - before;
    pthread_mutex_unlock(&g->lock);
    return n;
}

unsigned merd_guard_open(merd_guard *g)
{
    pthread_mutex_lock(&g->lock);
    unsigned n = g->open;
    pthread_mutex_unlock(&g->lock);
    return n;
}

static void *sweep(void *arg)
{
    merd_guard *g = arg;
    pthread_mutex_lock(&g->lock);
    while (!g->stopping) {
        sweep_at(g, merd_now());
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 500 * 1000000L;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&g->wake, &g->lock, &until);
    }
    pthread_mutex_unlock(&g->lock);
    return NULL;
}

merd_guard *merd_guard_start(unsigned soft_limit, double head_seconds, double idle_seconds)
{
    merd_guard *g = calloc(1, sizeof *g);
    if (g == NULL)
        return NULL;
    g->soft_limit = soft_limit;
    g->head_seconds = head_seconds;
    g->idle_seconds = idle_seconds;
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->wake, NULL);
    if (pthread_create(&g->sweeper, NULL, sweep, g) != 0) {
        pthread_mutex_destroy(&g->lock);
        pthread_cond_destroy(&g->wake);
        free(g);
        return NULL;
    }
    return g;
}

void merd_guard_stop(merd_guard *g)
{
    if (g == NULL)
        return;
    pthread_mutex_lock(&g->lock);
    g->stopping = true;
    pthread_cond_signal(&g->wake);
    pthread_mutex_unlock(&g->lock);
    pthread_join(g->sweeper, NULL);
    // The daemon has stopped: every connection was closed and its entry freed.
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->wake);
    free(g);
}

void merd_guard_notify(void *cls, struct MHD_Connection *connection, void **socket_context,
                       enum MHD_ConnectionNotificationCode code)
{
    merd_guard *g = cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        entry *e = calloc(1, sizeof *e);
        pthread_mutex_lock(&g->lock);
        g->open++;
        // Full: the oldest connection not in a request makes room for this one.
        if (g->open > g->soft_limit && g->head != NULL)
            cut(g, g->head);
        if (e != NULL) {
            e->connection = connection;
            list_at_end(g, e, merd_now() + g->head_seconds);
        }
        pthread_mutex_unlock(&g->lock);
        *socket_context = e;
        return;
    }
    entry *e = *socket_context;
    pthread_mutex_lock(&g->lock);
    g->open--;
    if (e != NULL)
        unlist(g, e);
    pthread_mutex_unlock(&g->lock);
    free(e);
    *socket_context = NULL;
}

static entry *entry_of(struct MHD_Connection *connection)
{
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    return info != NULL ? info->socket_context : NULL;
}

void merd_guard_request_began(merd_guard *g, struct MHD_Connection *connection)
{
    entry *e = entry_of(connection);
    if (g == NULL || e == NULL)
        return;
    pthread_mutex_lock(&g->lock);
    unlist(g, e);
    pthread_mutex_unlock(&g->lock);
}

void merd_guard_request_ended(merd_guard *g, struct MHD_Connection *connection)
{
    entry *e = entry_of(connection);
    if (g == NULL || e == NULL)
        return;
    pthread_mutex_lock(&g->lock);
    list_at_end(g, e, merd_now() + g->idle_seconds);
    pthread_mutex_unlock(&g->lock);
}

size_t merd_guard_cuts(merd_guard *g)
{
    pthread_mutex_lock(&g->lock);
    size_t n = g->cuts;
    pthread_mutex_unlock(&g->lock);
    return n;
}
