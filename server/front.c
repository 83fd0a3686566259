/* meristemd — the front (see front.h). */
#include "config.h"

#include <errno.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <unistd.h>

#include "server/clock.h"
#include "server/front.h"
#include "server/head.h"
#include "server/relay.h"

/* Bytes of a chunked body looked at beyond the first head. */
#define BODY_LOOK 4096
/* How long a refused connection is drained before it is closed. */
#define LINGER_SECONDS 2.0
/* How long accepting pauses when the process is out of descriptors. */
#define PAUSE_SECONDS 0.1
/* How long relayed answers may take to go out once the front stops. */
#define FLUSH_SECONDS 2.0
/* The socket buffer of libmicrohttpd's end of a socketpair, for answers. */
#define ANSWER_BUFFER (1 << 20)
/* How often a relay waiting for libmicrohttpd to read is looked at. */
#define POLL_SECONDS 0.005
/* The most descriptors the completion slots cover. */
#define MAX_SLOTS (1u << 20)

typedef enum where {
    WAITING,   /* its first head arrives (peeked, not read) */
    RELAYED,   /* relayed to libmicrohttpd */
    ENDING,    /* relayed, refusing or flushing the last answers */
    LINGERING, /* answered: draining until closed */
    DEAD,      /* closed; freed after the current batch of events */
} where;

struct conn;
typedef struct end {
    struct conn *c;
} end;

typedef struct conn {
    int fd;
    where at;
    double deadline;
    struct sockaddr_storage address;
    socklen_t address_size;
    merd_relay *relay;
    uint32_t client_events, pair_events; /* in the epoll set now */
    end client, pair;                    /* epoll data of each socket */
    struct conn *prev, *next;
} conn;

/* Connections in arrival order: one deadline for all, so the first is due first. */
typedef struct queue {
    conn *first, *last;
    unsigned count;
} queue;

struct merd_front {
    int listener, epoll, wake;
    pthread_t thread;
    atomic_bool quiescing, stopping;
    bool listening;      /* the listener is in the epoll set */
    double paused_until; /* 0, or when to accept again */
    unsigned port;
    merd_front_config config;
    struct MHD_Daemon *daemon;
    merd_guard *guard;
    queue queues[4]; /* by `where`, DEAD excepted */
    conn *dead;
    char *peek;
    size_t peek_size;
    merd_relay_slot *slots; /* by libmicrohttpd's descriptor */
    unsigned slot_count;
};

static void enqueue(merd_front *f, conn *c, where at)
{
    queue *q = &f->queues[at];
    c->at = at;
    c->prev = q->last;
    c->next = NULL;
    if (q->last != NULL)
        q->last->next = c;
    else
        q->first = c;
    q->last = c;
    q->count++;
}

static void dequeue(merd_front *f, conn *c)
{
    queue *q = &f->queues[c->at];
    if (c->prev != NULL)
        c->prev->next = c->next;
    else
        q->first = c->next;
    if (c->next != NULL)
        c->next->prev = c->prev;
    else
        q->last = c->prev;
    q->count--;
}

/* Closes the connection; its memory goes after the current batch of events,
 * which may still name it. */
static void drop(merd_front *f, conn *c)
{
    dequeue(f, c);
    close(c->fd);
    merd_relay_free(c->relay);
    c->relay = NULL;
    c->at = DEAD;
    c->next = f->dead;
    f->dead = c;
}

static void bury(merd_front *f)
{
    while (f->dead != NULL) {
        conn *c = f->dead;
        f->dead = c->next;
        free(c);
    }
}

/* Makes the epoll set wait for `want` on `fd` (0: leave it out, for even a
 * hang-up would wake the loop again and again); *now is what it waits for.
 * False when the set refuses it. */
static bool watch_fd(merd_front *f, int fd, uint32_t *now, uint32_t want, end *data)
{
    if (want == *now)
        return true;
    struct epoll_event e = {.events = want, .data.ptr = data};
    int op = want == 0 ? EPOLL_CTL_DEL : *now == 0 ? EPOLL_CTL_ADD : EPOLL_CTL_MOD;
    bool done = epoll_ctl(f->epoll, op, fd, &e) == 0;
    if (done || want == 0)
        *now = want;
    return done;
}

static bool same_address(const struct sockaddr_storage *a, const struct sockaddr_storage *b)
{
    if (a->ss_family != b->ss_family)
        return false;
    if (a->ss_family == AF_INET)
        return ((const struct sockaddr_in *)a)->sin_addr.s_addr ==
               ((const struct sockaddr_in *)b)->sin_addr.s_addr;
    if (a->ss_family == AF_INET6)
        return memcmp(&((const struct sockaddr_in6 *)a)->sin6_addr,
                      &((const struct sockaddr_in6 *)b)->sin6_addr, sizeof(struct in6_addr)) == 0;
    return false;
}

/* Connections from `address`, waiting for a head or relayed, counted once:
 * O(connections), a few thousand at most. */
static unsigned open_from(const merd_front *f, const struct sockaddr_storage *address)
{
    unsigned n = 0;
    for (where at = WAITING; at <= ENDING; at++)
        for (const conn *c = f->queues[at].first; c != NULL; c = c->next)
            n += same_address(&c->address, address);
    return n;
}

static void listen_for(merd_front *f, bool on)
{
    if (on == f->listening)
        return;
    struct epoll_event e = {.events = EPOLLIN, .data.ptr = &f->listener};
    epoll_ctl(f->epoll, on ? EPOLL_CTL_ADD : EPOLL_CTL_DEL, f->listener, &e);
    f->listening = on;
}

/* Reads and drops what the client of an answered connection still sends, a
 * bounded amount at a time; closes it at the end of its input. */
static void drain(merd_front *f, conn *c)
{
    char sink[16384];
    for (int i = 0; i < 4; i++) {
        ssize_t n = recv(c->fd, sink, sizeof sink, 0);
        if (n > 0)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR))
            return;
        drop(f, c);
        return;
    }
}

/* Closes gracefully: the write side is shut and what the client still sends
 * is read and dropped for a moment, so that the answer is not lost to a reset. */
static void linger(merd_front *f, conn *c)
{
    merd_relay_free(c->relay);
    c->relay = NULL;
    c->pair_events = 0;
    shutdown(c->fd, SHUT_WR);
    dequeue(f, c);
    c->deadline = merd_now() + LINGER_SECONDS;
    enqueue(f, c, LINGERING);
    watch_fd(f, c->fd, &c->client_events, EPOLLIN | EPOLLRDHUP, &c->client);
    drain(f, c);
}

/* Moves a relayed connection's bytes and follows where it stands. */
static void advance(merd_front *f, conn *c)
{
    switch (merd_relay_pump(c->relay)) {
    case MERD_RELAY_GONE:
        drop(f, c);
        return;
    case MERD_RELAY_DONE:
        linger(f, c);
        return;
    case MERD_RELAY_ENDING:
        if (c->at == RELAYED) {
            dequeue(f, c);
            c->deadline = merd_now() + f->config.idle_seconds;
            enqueue(f, c, ENDING);
        }
        break;
    case MERD_RELAY_OPEN:
        break;
    }
    watch_fd(f, merd_relay_pair(c->relay), &c->pair_events, merd_relay_pair_events(c->relay),
             &c->pair);
    watch_fd(f, c->fd, &c->client_events, merd_relay_client_events(c->relay), &c->client);
}

/* A good first head: libmicrohttpd gets one end of a socketpair, the front
 * relays between it and the client from now on. */
static void hand_on(merd_front *f, conn *c)
{
    int pair[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, pair) != 0) {
        drop(f, c);
        return;
    }
    if ((unsigned)pair[1] >= f->slot_count ||
        (c->relay = merd_relay_new(c->fd, pair[0], &f->slots[pair[1]], f->config.budget)) == NULL) {
        close(pair[0]);
        close(pair[1]);
        drop(f, c);
        return;
    }
    // A large answer goes into the socketpair in one go, as it would into a
    // TCP socket, not in many rounds of waking libmicrohttpd (the kernel caps it).
    int room = ANSWER_BUFFER;
    setsockopt(pair[1], SOL_SOCKET, SO_SNDBUF, &room, sizeof room);
    dequeue(f, c);
    enqueue(f, c, RELAYED);
    // libmicrohttpd closes its end itself when it cannot take it (its limits):
    // the relay then sees the end of the connection.
    MHD_add_connection(f->daemon, pair[1], (const struct sockaddr *)&c->address, c->address_size);
    advance(f, c);
}

/* Answers a bad first head with its problem and closes gracefully. */
static void refuse(merd_front *f, conn *c, const merd_head_verdict *v)
{
    char reply[1024];
    size_t n = merd_relay_refusal(v, reply, sizeof reply);
    // A fresh socket's send buffer takes it: a short write is not retried.
    if (n > 0)
        (void)send(c->fd, reply, n, MSG_NOSIGNAL);
    linger(f, c);
}

/* Looks at what a waiting connection has sent so far. */
static void look(merd_front *f, conn *c, uint32_t events)
{
    ssize_t n = recv(c->fd, f->peek, f->peek_size, MSG_PEEK);
    if (n <= 0) {
        bool later = n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
        if (!later || (events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR)) != 0)
            drop(f, c);
        return;
    }
    merd_head_verdict v;
    switch (merd_head_check(f->peek, (size_t)n, f->config.budget, &v)) {
    case MERD_HEAD_MORE:
        // A client that has stopped sending will never complete its head.
        if ((events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR)) != 0)
            drop(f, c);
        return;
    case MERD_HEAD_GOOD:
        hand_on(f, c);
        return;
    case MERD_HEAD_BAD:
        refuse(f, c, &v);
        return;
    }
}

static void admit(merd_front *f, int fd, const struct sockaddr_storage *address, socklen_t size)
{
    if (open_from(f, address) >= f->config.per_ip_limit) {
        close(fd);
        return;
    }
    // Full: the oldest head still arriving makes room (the guard does the same
    // inside libmicrohttpd for connections between requests).
    queue *waiting = &f->queues[WAITING];
    if (waiting->count + merd_guard_open(f->guard) >= f->config.soft_limit && waiting->first != NULL)
        drop(f, waiting->first);
    conn *c = calloc(1, sizeof *c);
    if (c == NULL) {
        close(fd);
        return;
    }
    c->fd = fd;
    c->client.c = c->pair.c = c;
    c->address = *address;
    c->address_size = size;
    c->deadline = merd_now() + f->config.head_seconds;
    enqueue(f, c, WAITING);
    // Edge-triggered while peeking: each arrival of bytes wakes the front
    // once; adding reports bytes already there.
    if (!watch_fd(f, fd, &c->client_events, EPOLLIN | EPOLLRDHUP | EPOLLET, &c->client))
        drop(f, c);
}

static void accept_all(merd_front *f)
{
    for (;;) {
        struct sockaddr_storage address;
        socklen_t size = sizeof address;
        int fd = accept4(f->listener, (struct sockaddr *)&address, &size,
                         SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd >= 0) {
            admit(f, fd, &address, size);
            continue;
        }
        if (errno == EINTR || errno == ECONNABORTED)
            continue;
        if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
            // Out of descriptors: the oldest waiting head gives its own, or
            // accepting pauses (the listener would wake the loop at once).
            if (f->queues[WAITING].first != NULL) {
                drop(f, f->queues[WAITING].first);
                continue;
            }
            listen_for(f, false);
            f->paused_until = merd_now() + PAUSE_SECONDS;
        }
        return;
    }
}

/* Closes what is due at `now`; returns milliseconds until the next deadline. */
static int expire(merd_front *f, double now)
{
    double next = now + 0.5;
    for (where at = WAITING; at <= LINGERING; at++) {
        if (at == RELAYED)
            continue;
        queue *q = &f->queues[at];
        while (q->first != NULL && q->first->deadline <= now)
            drop(f, q->first);
        if (q->first != NULL && q->first->deadline < next)
            next = q->first->deadline;
    }
    for (where at = RELAYED; at <= ENDING; at++)
        for (conn *c = f->queues[at].first, *after; c != NULL; c = after) {
            after = c->next;
            if (c->at == at && merd_relay_polling(c->relay)) {
                advance(f, c);
                if (c->relay != NULL && merd_relay_polling(c->relay) && now + POLL_SECONDS < next)
                    next = now + POLL_SECONDS;
            }
        }
    if (f->paused_until != 0 && f->paused_until <= now) {
        f->paused_until = 0;
        if (!atomic_load(&f->quiescing))
            listen_for(f, true);
    }
    if (f->paused_until != 0 && f->paused_until < next)
        next = f->paused_until;
    return (int)((next - now) * 1e3) + 1;
}

/* Relays that wait for libmicrohttpd's completions look again. */
static void woken(merd_front *f)
{
    uint64_t ignored;
    (void)!read(f->wake, &ignored, sizeof ignored);
    if (atomic_load(&f->quiescing))
        listen_for(f, false);
    for (conn *c = f->queues[ENDING].first, *next; c != NULL; c = next) {
        next = c->next;
        advance(f, c);
    }
}

static void handle(merd_front *f, end *e, uint32_t events)
{
    conn *c = e->c;
    switch (c->at) {
    case WAITING:
        look(f, c, events);
        return;
    case LINGERING:
        drain(f, c);
        return;
    case RELAYED:
    case ENDING:
        if (e == &c->client && (events & (EPOLLHUP | EPOLLERR)) != 0) {
            drop(f, c);
        } else {
            merd_relay_ready(c->relay, e == &c->client);
            advance(f, c);
        }
        return;
    case DEAD:
        return;
    }
}

/* Once stopping: no client is read any more; what libmicrohttpd has answered
 * goes out, for at most FLUSH_SECONDS. */
static void finish_all(merd_front *f)
{
    listen_for(f, false);
    for (where at = RELAYED; at <= ENDING; at++)
        for (conn *c = f->queues[at].first, *next; c != NULL; c = next) {
            next = c->next;
            merd_relay_finish(c->relay);
            advance(f, c);
        }
}

static void *run(void *arg)
{
    merd_front *f = arg;
    struct epoll_event events[64];
    int wait_ms = 0;
    double flush_until = 0;
    for (;;) {
        if (atomic_load(&f->stopping)) {
            if (flush_until == 0) {
                flush_until = merd_now() + FLUSH_SECONDS;
                finish_all(f);
            }
            if (f->queues[RELAYED].count + f->queues[ENDING].count == 0 || merd_now() > flush_until)
                break;
            if (wait_ms > 50)
                wait_ms = 50;
        }
        int n = epoll_wait(f->epoll, events, 64, wait_ms);
        bool arrivals = false;
        for (int i = 0; i < n; i++) {
            void *what = events[i].data.ptr;
            if (what == &f->wake)
                woken(f);
            else if (what == &f->listener)
                arrivals = true;  // after the batch: admitting may drop a connection in it
            else
                handle(f, what, events[i].events);
        }
        if (arrivals && f->listening)
            accept_all(f);
        wait_ms = expire(f, merd_now());
        bury(f);
    }
    return NULL;
}

static int open_listener(const struct sockaddr_storage *address, unsigned *port)
{
    socklen_t size = address->ss_family == AF_INET6 ? sizeof(struct sockaddr_in6)
                                                    : sizeof(struct sockaddr_in);
    int fd = socket(address->ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0)
        return -1;
    int on = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (address->ss_family == AF_INET6)
        setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &on, sizeof on);
    struct sockaddr_storage bound;
    socklen_t bound_size = sizeof bound;
    if (bind(fd, (const struct sockaddr *)address, size) != 0 || listen(fd, SOMAXCONN) != 0 ||
        getsockname(fd, (struct sockaddr *)&bound, &bound_size) != 0) {
        close(fd);
        return -1;
    }
    // Both families keep the port at the same offset.
    *port = ntohs(((struct sockaddr_in *)&bound)->sin_port);
    return fd;
}

/* One slot per descriptor the process may open (up to MAX_SLOTS). */
static unsigned slot_count(void)
{
    struct rlimit files;
    if (getrlimit(RLIMIT_NOFILE, &files) != 0 || files.rlim_cur == RLIM_INFINITY ||
        files.rlim_cur > MAX_SLOTS)
        return MAX_SLOTS;
    return (unsigned)files.rlim_cur;
}

static void free_front(merd_front *f)
{
    if (f->listener >= 0)
        close(f->listener);
    if (f->wake >= 0)
        close(f->wake);
    if (f->epoll >= 0)
        close(f->epoll);
    free(f->peek);
    free(f->slots);
    free(f);
}

bool merd_front_start(const struct sockaddr_storage *address, const merd_front_config *config,
                      struct MHD_Daemon *daemon, merd_guard *guard, merd_front **out)
{
    merd_front *f = calloc(1, sizeof *f);
    if (f == NULL)
        return false;
    f->config = *config;
    f->daemon = daemon;
    f->guard = guard;
    f->peek_size = config->budget + 1 + BODY_LOOK;
    f->peek = malloc(f->peek_size);
    f->slot_count = slot_count();
    f->slots = calloc(f->slot_count, sizeof *f->slots);
    f->epoll = epoll_create1(EPOLL_CLOEXEC);
    f->wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    f->listener = open_listener(address, &f->port);
    struct epoll_event e = {.events = EPOLLIN, .data.ptr = &f->wake};
    if (f->peek == NULL || f->slots == NULL || f->epoll < 0 || f->wake < 0 || f->listener < 0 ||
        epoll_ctl(f->epoll, EPOLL_CTL_ADD, f->wake, &e) != 0) {
        free_front(f);
        return false;
    }
    listen_for(f, true);
    // Published before the thread hands anything on: completions may follow at once.
    *out = f;
    if (pthread_create(&f->thread, NULL, run, f) != 0) {
        *out = NULL;
        free_front(f);
        return false;
    }
    return true;
}

unsigned merd_front_port(const merd_front *f)
{
    return f->port;
}

static void wake(merd_front *f)
{
    uint64_t one = 1;
    (void)!write(f->wake, &one, sizeof one);
}

void merd_front_answered(merd_front *f, int fd, bool replied)
{
    if (f == NULL || fd < 0 || (unsigned)fd >= f->slot_count)
        return;
    merd_relay_slot *s = &f->slots[fd];
    if (replied)
        atomic_fetch_add(&s->replied, 1);
    atomic_fetch_add(&s->done, 1);
    if (atomic_load(&s->watch))
        wake(f);
}

void merd_front_quiesce(merd_front *f)
{
    atomic_store(&f->quiescing, true);
    wake(f);
}

void merd_front_stop(merd_front *f)
{
    if (f == NULL)
        return;
    atomic_store(&f->stopping, true);
    wake(f);
    pthread_join(f->thread, NULL);
    for (where at = WAITING; at <= LINGERING; at++)
        while (f->queues[at].first != NULL)
            drop(f, f->queues[at].first);
    bury(f);
}

void merd_front_free(merd_front *f)
{
    if (f != NULL)
        free_front(f);
}
