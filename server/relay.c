/* meristemd — one relayed connection (see relay.h). */
#include "config.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <linux/sockios.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "server/framing.h"
#include "server/relay.h"
#include "server/request.h"

/* Bytes of answer held between libmicrohttpd and the client: DOWN_SIZE, and
 * up to DOWN_MAX while a large answer streams (fewer, larger copies). */
#define DOWN_SIZE 65536
#define DOWN_MAX (1 << 20)
/* Bytes of request held beyond the largest head. */
#define UP_EXTRA 16384

struct merd_relay {
    int client, pair;
    merd_relay_slot *slot;
    size_t budget;
    unsigned forwarded;   /* requests whose head went on */
    bool in_body;         /* the last head went on, its body has not ended */
    merd_framing framing;
    bool client_eof;      /* the client has sent everything */
    bool client_gone;     /* the client cannot be written to */
    bool pair_eof;        /* libmicrohttpd has closed, or we are done with it */
    bool pair_shut;       /* libmicrohttpd's input is ended */
    bool refusing, in_flight, refusal_sent;
    bool polling;         /* waits for libmicrohttpd to read before ending its input */
    bool client_dry, pair_dry; /* read to the end; epoll says when there is more */
    merd_head_verdict verdict;
    /* up: [0, sent) gone on, [sent, ok) checked, [ok, fill) not checked yet */
    char *up;
    size_t up_size, up_sent, up_ok, up_fill;
    char *down;
    size_t down_size, down_sent, down_fill;
};

merd_relay *merd_relay_new(int client, int pair, merd_relay_slot *slot, size_t budget)
{
    merd_relay *r = calloc(1, sizeof *r);
    if (r == NULL)
        return NULL;
    r->up_size = budget + 1 + UP_EXTRA;
    r->up = malloc(r->up_size);
    r->down = malloc(DOWN_SIZE);
    r->down_size = DOWN_SIZE;
    if (r->up == NULL || r->down == NULL) {
        free(r->up);
        free(r->down);
        free(r);
        return NULL;
    }
    r->client = client;
    r->pair = pair;
    r->slot = slot;
    r->budget = budget;
    atomic_store(&slot->done, 0);
    atomic_store(&slot->replied, 0);
    atomic_store(&slot->watch, false);
    return r;
}

void merd_relay_free(merd_relay *r)
{
    if (r == NULL)
        return;
    atomic_store(&r->slot->watch, false);
    close(r->pair);
    free(r->up);
    free(r->down);
    free(r);
}

int merd_relay_pair(const merd_relay *r)
{
    return r->pair;
}

static bool again(void)
{
    return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
}

/* Nothing more is read or forwarded after `v`; `in_flight`: it is in the body
 * of a request whose head went on. */
static void refuse(merd_relay *r, const merd_head_verdict *v, bool in_flight)
{
    r->refusing = true;
    r->in_flight = in_flight;
    r->verdict = *v;
    r->up_fill = r->up_ok;
    atomic_store(&r->slot->watch, true);
}

/* Checks what came from the client: heads, then the bodies they announce. */
static void check_up(merd_relay *r)
{
    while (!r->refusing && r->up_ok < r->up_fill) {
        merd_head_verdict v;
        if (!r->in_body) {
            merd_head_state s = merd_head_check(r->up + r->up_ok, r->up_fill - r->up_ok, r->budget, &v);
            if (s == MERD_HEAD_MORE)
                return;
            if (s == MERD_HEAD_BAD) {
                refuse(r, &v, false);
                return;
            }
            r->up_ok += v.head_size;
            r->forwarded++;
            r->in_body = true;
            merd_framing_start(&r->framing, &v, r->budget);
        }
        size_t used = 0;
        merd_head_state s = merd_framing_feed(&r->framing, r->up + r->up_ok, r->up_fill - r->up_ok,
                                              &used, &v);
        r->up_ok += used;
        if (s == MERD_HEAD_BAD)
            refuse(r, &v, true);
        else if (s == MERD_HEAD_GOOD)
            r->in_body = false;
        else
            return;
    }
}

static bool read_client(merd_relay *r)
{
    if (r->refusing || r->client_eof || r->pair_eof)
        return false;
    if (r->up_sent == r->up_fill) {
        r->up_sent = r->up_ok = r->up_fill = 0;
    } else if (r->up_fill == r->up_size && r->up_sent > 0) {
        memmove(r->up, r->up + r->up_sent, r->up_fill - r->up_sent);
        r->up_ok -= r->up_sent;
        r->up_fill -= r->up_sent;
        r->up_sent = 0;
    }
    if (r->up_fill == r->up_size || r->client_dry)
        return false;
    size_t room = r->up_size - r->up_fill;
    ssize_t n = recv(r->client, r->up + r->up_fill, room, 0);
    if (n > 0) {
        r->client_dry = (size_t)n < room;
        r->up_fill += (size_t)n;
        check_up(r);
        return true;
    }
    if (n == 0)
        r->client_eof = true;
    else if (!again())
        r->client_gone = true;
    else
        r->client_dry = true;
    return n == 0;
}

static bool write_pair(merd_relay *r)
{
    if (r->up_sent == r->up_ok || r->pair_shut || r->pair_eof)
        return false;
    ssize_t n = send(r->pair, r->up + r->up_sent, r->up_ok - r->up_sent, MSG_NOSIGNAL);
    if (n > 0) {
        r->up_sent += (size_t)n;
        return true;
    }
    if (n < 0 && !again()) {
        // libmicrohttpd has closed: what it had not read is dropped.
        r->pair_shut = true;
        r->up_sent = r->up_ok;
    }
    return false;
}

/* Reads libmicrohttpd's output; *dry when it had nothing more. While
 * refusing, what was read dry before is read again: the refusal waits for a
 * dry read after the completions were counted. */
static bool read_pair(merd_relay *r, bool *dry)
{
    if (r->pair_eof)
        return false;
    if (r->pair_dry && !r->refusing) {
        *dry = true;
        return false;
    }
    if (r->down_fill == r->down_size && r->down_sent > 0) {
        memmove(r->down, r->down + r->down_sent, r->down_fill - r->down_sent);
        r->down_fill -= r->down_sent;
        r->down_sent = 0;
    }
    if (r->down_fill == r->down_size && r->down_size < DOWN_MAX) {
        char *grown = realloc(r->down, 2 * r->down_size);
        if (grown != NULL) {
            r->down = grown;
            r->down_size *= 2;
        }
    }
    if (r->down_fill == r->down_size)
        return false;
    size_t room = r->down_size - r->down_fill;
    ssize_t n = recv(r->pair, r->down + r->down_fill, room, 0);
    if (n > 0) {
        r->down_fill += (size_t)n;
        // A short read took all there was: dry, as a failed read would say.
        r->pair_dry = *dry = (size_t)n < room;
        return true;
    }
    if (n < 0 && again()) {
        r->pair_dry = *dry = true;
        return false;
    }
    r->pair_eof = true;
    return true;
}

/* An empty answer buffer goes back to DOWN_SIZE (in place). */
static void shrink(merd_relay *r)
{
    if (r->down_size == DOWN_SIZE)
        return;
    char *smaller = realloc(r->down, DOWN_SIZE);
    if (smaller != NULL) {
        r->down = smaller;
        r->down_size = DOWN_SIZE;
    }
}

static bool write_client(merd_relay *r)
{
    if (r->down_sent == r->down_fill)
        return false;
    ssize_t n = send(r->client, r->down + r->down_sent, r->down_fill - r->down_sent, MSG_NOSIGNAL);
    if (n > 0) {
        r->down_sent += (size_t)n;
        if (r->down_sent == r->down_fill) {
            r->down_sent = r->down_fill = 0;
            shrink(r);
        }
        return true;
    }
    if (n < 0 && !again())
        r->client_gone = true;
    return false;
}

size_t merd_relay_refusal(const merd_head_verdict *v, char *out, size_t size)
{
    const char *title = merd_status_title(v->status);
    char *body = merd_problem_body(v->status, v->slug, title, v->detail, NULL);
    if (body == NULL)
        return 0;
    int n = snprintf(out, size,
                     "HTTP/1.1 %u %s\r\nContent-Type: application/problem+json\r\n"
                     "Content-Length: %zu\r\nConnection: close\r\n"
                     "X-Content-Type-Options: nosniff\r\n\r\n%s",
                     v->status, title, strlen(body), body);
    free(body);
    return n > 0 && (size_t)n < size ? (size_t)n : 0;
}

/* After a bad head or chunk: once every request forwarded is answered and its
 * answer is out, the refusal follows. `answered`: libmicrohttpd had completed
 * them all before its output was read dry. */
static void conclude(merd_relay *r, bool answered)
{
    if (r->up_sent != r->up_ok || r->down_fill != 0 || !(answered || r->pair_eof))
        return;
    // A request cut in its body was abandoned by libmicrohttpd unless it had
    // answered it already (refusing it from its head); after a head, nothing
    // is owed once libmicrohttpd has closed the connection itself.
    bool owed = r->in_flight ? atomic_load(&r->slot->replied) < r->forwarded : !r->pair_eof;
    r->refusal_sent = true;
    atomic_store(&r->slot->watch, false);
    if (!r->pair_eof) {
        shutdown(r->pair, SHUT_RDWR);
        r->pair_eof = true;
    }
    if (owed)
        r->down_fill = merd_relay_refusal(&r->verdict, r->down, r->down_size);
}

/* Bytes sent to libmicrohttpd that it has not read yet. */
static int unread(const merd_relay *r)
{
    int n = 0;
    return ioctl(r->pair, SIOCOUTQ, &n) == 0 ? n : 0;
}

/* libmicrohttpd sees the end of the input once the checked bytes are in and
 * it has read them all: with epoll it takes a short read for the end of what
 * there is, and would not look again for an end that came before it. */
static void end_input(merd_relay *r)
{
    r->polling = false;
    if (!(r->client_eof || (r->refusing && r->in_flight)) || r->up_sent != r->up_ok ||
        r->pair_shut || r->pair_eof)
        return;
    if (unread(r) > 0) {
        r->polling = true;
        return;
    }
    shutdown(r->pair, SHUT_WR);
    r->pair_shut = true;
}

merd_relay_state merd_relay_pump(merd_relay *r)
{
    // Loaded before libmicrohttpd's output is read: a completion counted here
    // has all its bytes in the socketpair already.
    unsigned done = atomic_load(&r->slot->done);
    bool dry = false;
    for (bool moved = true; moved && !r->client_gone;) {
        moved = read_pair(r, &dry);
        moved |= write_client(r);
        moved |= read_client(r);
        moved |= write_pair(r);
        end_input(r);
        if (r->refusing && !r->refusal_sent && r->down_fill == 0 && (dry || r->pair_eof)) {
            conclude(r, done == r->forwarded);
            moved |= r->refusal_sent;
        }
    }
    if (r->client_gone)
        return MERD_RELAY_GONE;
    // A completion between the load above and the watch set by refuse()
    // wakes nobody: look again.
    if (r->refusing && !r->refusal_sent && done != r->forwarded &&
        atomic_load(&r->slot->done) == r->forwarded)
        return merd_relay_pump(r);
    if (r->pair_eof || r->refusal_sent)
        return r->down_fill == 0 ? MERD_RELAY_DONE : MERD_RELAY_ENDING;
    return r->refusing ? MERD_RELAY_ENDING : MERD_RELAY_OPEN;
}

void merd_relay_ready(merd_relay *r, bool client)
{
    if (client)
        r->client_dry = false;
    else
        r->pair_dry = false;
}

bool merd_relay_polling(const merd_relay *r)
{
    return r->polling;
}

void merd_relay_finish(merd_relay *r)
{
    r->client_eof = true;
    r->up_fill = r->up_ok;
}

uint32_t merd_relay_client_events(const merd_relay *r)
{
    uint32_t e = 0;
    if (!r->refusing && !r->client_eof && !r->pair_eof && r->up_fill - r->up_sent < r->up_size)
        e |= EPOLLIN;
    if (r->down_sent < r->down_fill)
        e |= EPOLLOUT;
    return e;
}

uint32_t merd_relay_pair_events(const merd_relay *r)
{
    uint32_t e = 0;
    if (r->pair_eof)
        return 0;
    if (r->down_fill - r->down_sent < DOWN_MAX)
        e |= EPOLLIN;
    if (r->up_sent < r->up_ok && !r->pair_shut)
        e |= EPOLLOUT;
    return e;
}
