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
#include <unistd.h>

#include "server/clock.h"
#include "server/front.h"
#include "server/head.h"
#include "server/request.h"

/* Bytes of a chunked body looked at beyond the head. */
#define BODY_LOOK 4096
/* How long a refused connection is drained before it is closed. */
#define LINGER_SECONDS 2.0
/* How long accepting pauses when the process is out of descriptors. */
#define PAUSE_SECONDS 0.1

typedef struct conn {
    int fd;
    bool refused; /* answered: draining until closed */
    double deadline;
    struct sockaddr_storage address;
    socklen_t address_size;
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
    queue waiting, refused;
    char *peek;
    size_t peek_size;
};

static void enqueue(queue *q, conn *c)
{
    c->prev = q->last;
    c->next = NULL;
    if (q->last != NULL)
        q->last->next = c;
    else
        q->first = c;
    q->last = c;
    q->count++;
}

static void dequeue(queue *q, conn *c)
{
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

static void drop(merd_front *f, conn *c)
{
    dequeue(c->refused ? &f->refused : &f->waiting, c);
    close(c->fd);
    free(c);
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

/* Heads waiting from `address`: O(waiting), a few thousand at most. */
static unsigned waiting_from(const merd_front *f, const struct sockaddr_storage *address)
{
    unsigned n = 0;
    for (const conn *c = f->waiting.first; c != NULL; c = c->next)
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

static void hand_on(merd_front *f, conn *c)
{
    epoll_ctl(f->epoll, EPOLL_CTL_DEL, c->fd, NULL);
    dequeue(&f->waiting, c);
    // libmicrohttpd closes the socket itself when it cannot take it (its limits).
    MHD_add_connection(f->daemon, c->fd, (const struct sockaddr *)&c->address, c->address_size);
    free(c);
}

/* Reads and drops what the client of a refused connection still sends, a
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

/* Sends the problem and closes gracefully (front.h). */
static void refuse(merd_front *f, conn *c, const merd_head_verdict *v)
{
    const char *title = merd_status_title(v->status);
    char *body = merd_problem_body(v->status, v->slug, title, v->detail, NULL);
    char head[320];
    int n = snprintf(head, sizeof head,
                     "HTTP/1.1 %u %s\r\nContent-Type: application/problem+json\r\n"
                     "Content-Length: %zu\r\nConnection: close\r\n"
                     "X-Content-Type-Options: nosniff\r\n\r\n",
                     v->status, title, body != NULL ? strlen(body) : 0);
    // A fresh socket's send buffer takes both: short writes are not retried.
    if (send(c->fd, head, (size_t)n, MSG_NOSIGNAL) == n && body != NULL)
        (void)send(c->fd, body, strlen(body), MSG_NOSIGNAL);
    free(body);
    shutdown(c->fd, SHUT_WR);
    dequeue(&f->waiting, c);
    c->refused = true;
    c->deadline = merd_now() + LINGER_SECONDS;
    enqueue(&f->refused, c);
    struct epoll_event e = {.events = EPOLLIN | EPOLLRDHUP, .data.ptr = c};
    epoll_ctl(f->epoll, EPOLL_CTL_MOD, c->fd, &e);
    drain(f, c);
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
    if (waiting_from(f, address) >= f->config.per_ip_limit) {
        close(fd);
        return;
    }
    // Full: the oldest head still arriving makes room (the guard does the same
    // inside libmicrohttpd for connections between requests).
    if (f->waiting.count + merd_guard_open(f->guard) >= f->config.soft_limit &&
        f->waiting.first != NULL)
        drop(f, f->waiting.first);
    conn *c = calloc(1, sizeof *c);
    if (c == NULL) {
        close(fd);
        return;
    }
    c->fd = fd;
    c->address = *address;
    c->address_size = size;
    c->deadline = merd_now() + f->config.head_seconds;
    enqueue(&f->waiting, c);
    // Edge-triggered: each arrival of bytes wakes the front once; adding
    // reports bytes already there.
    struct epoll_event e = {.events = EPOLLIN | EPOLLRDHUP | EPOLLET, .data.ptr = c};
    if (epoll_ctl(f->epoll, EPOLL_CTL_ADD, fd, &e) != 0)
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
            if (f->waiting.first != NULL) {
                drop(f, f->waiting.first);
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
    while (f->waiting.first != NULL && f->waiting.first->deadline <= now)
        drop(f, f->waiting.first);
    while (f->refused.first != NULL && f->refused.first->deadline <= now)
        drop(f, f->refused.first);
    if (f->paused_until != 0 && f->paused_until <= now) {
        f->paused_until = 0;
        if (!atomic_load(&f->quiescing))
            listen_for(f, true);
    }
    double next = now + 0.5;
    if (f->waiting.first != NULL && f->waiting.first->deadline < next)
        next = f->waiting.first->deadline;
    if (f->refused.first != NULL && f->refused.first->deadline < next)
        next = f->refused.first->deadline;
    if (f->paused_until != 0 && f->paused_until < next)
        next = f->paused_until;
    return (int)((next - now) * 1e3) + 1;
}

static void *run(void *arg)
{
    merd_front *f = arg;
    struct epoll_event events[64];
    int wait_ms = 0;
    while (!atomic_load(&f->stopping)) {
        int n = epoll_wait(f->epoll, events, 64, wait_ms);
        bool arrivals = false;
        for (int i = 0; i < n; i++) {
            void *what = events[i].data.ptr;
            if (what == &f->wake) {
                uint64_t ignored;
                (void)!read(f->wake, &ignored, sizeof ignored);
                if (atomic_load(&f->quiescing))
                    listen_for(f, false);
            } else if (what == &f->listener) {
                arrivals = true;  // after the batch: admitting may drop a connection in it
            } else if (((conn *)what)->refused) {
                drain(f, what);
            } else {
                look(f, what, events[i].events);
            }
        }
        if (arrivals && f->listening)
            accept_all(f);
        wait_ms = expire(f, merd_now());
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

merd_front *merd_front_start(const struct sockaddr_storage *address, const merd_front_config *config,
                             struct MHD_Daemon *daemon, merd_guard *guard)
{
    merd_front *f = calloc(1, sizeof *f);
    if (f == NULL)
        return NULL;
    f->config = *config;
    f->daemon = daemon;
    f->guard = guard;
    f->peek_size = config->budget + 1 + BODY_LOOK;
    f->peek = malloc(f->peek_size);
    f->epoll = epoll_create1(EPOLL_CLOEXEC);
    f->wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    f->listener = open_listener(address, &f->port);
    struct epoll_event e = {.events = EPOLLIN, .data.ptr = &f->wake};
    if (f->peek == NULL || f->epoll < 0 || f->wake < 0 || f->listener < 0 ||
        epoll_ctl(f->epoll, EPOLL_CTL_ADD, f->wake, &e) != 0)
        goto fail;
    listen_for(f, true);
    if (pthread_create(&f->thread, NULL, run, f) != 0)
        goto fail;
    return f;
fail:
    if (f->listener >= 0)
        close(f->listener);
    if (f->wake >= 0)
        close(f->wake);
    if (f->epoll >= 0)
        close(f->epoll);
    free(f->peek);
    free(f);
    return NULL;
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
    while (f->waiting.first != NULL)
        drop(f, f->waiting.first);
    while (f->refused.first != NULL)
        drop(f, f->refused.first);
    close(f->listener);
    close(f->wake);
    close(f->epoll);
    free(f->peek);
    free(f);
}
