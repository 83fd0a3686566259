/* Unit tests for the connection guard (server/guard.c): its counting of open
 * connections, the per-daemon soft limit that cuts the oldest connection not in
 * a request, the request-head deadline and the idle deadline. libmicrohttpd is
 * replaced by the one call the guard makes, over socket pairs, so a cut is seen
 * as the peer's end of file. */
#include "config.h"

#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "server/clock.h"
#include "server/guard.h"
#include "server/guard_private.h"

struct MHD_Connection {
    int fd[2];                 /* [0] the daemon's end, [1] the client's */
    void *socket_context;      /* what the guard keeps for it */
    union MHD_ConnectionInfo fd_info, ctx_info;
};

const union MHD_ConnectionInfo *MHD_get_connection_info(struct MHD_Connection *c,
                                                        enum MHD_ConnectionInfoType type, ...)
{
    if (type == MHD_CONNECTION_INFO_CONNECTION_FD) {
        c->fd_info.connect_fd = c->fd[0];
        return &c->fd_info;
    }
    if (type == MHD_CONNECTION_INFO_SOCKET_CONTEXT) {
        c->ctx_info.socket_context = c->socket_context;
        return &c->ctx_info;
    }
    return NULL;
}

#define HEAD 1000.0 /* seconds: far beyond the test, so only the test's sweeps cut */
#define IDLE 3000.0

static void arrive(merd_guard *g, struct MHD_Connection *c)
{
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, c->fd), 0);
    merd_guard_notify(g, c, &c->socket_context, MHD_CONNECTION_NOTIFY_STARTED);
}

static void leave(merd_guard *g, struct MHD_Connection *c)
{
    merd_guard_notify(g, c, &c->socket_context, MHD_CONNECTION_NOTIFY_CLOSED);
    assert_null(c->socket_context);
    close(c->fd[0]);
    close(c->fd[1]);
}

/* Whether the guard shut the daemon's end: the client then reads end of file. */
static bool was_cut(struct MHD_Connection *c)
{
    char byte;
    return recv(c->fd[1], &byte, 1, MSG_DONTWAIT) == 0;
}

static void test_soft_limit_cuts_oldest_waiting(void **state)
{
    (void)state;
    merd_guard *g = merd_guard_start(3, HEAD, IDLE);
    assert_non_null(g);
    struct MHD_Connection c[6] = {0};
    for (int i = 0; i < 3; i++)
        arrive(g, &c[i]);
    assert_int_equal(merd_guard_open(g), 3);
    assert_int_equal(merd_guard_cuts(g), 0);
    // c[1] is inside a request: never a candidate.
    merd_guard_request_began(g, &c[1]);
    arrive(g, &c[3]); /* 4 > 3: the oldest waiting, c[0], makes room */
    assert_int_equal(merd_guard_open(g), 4);
    assert_int_equal(merd_guard_cuts(g), 1);
    assert_true(was_cut(&c[0]));
    assert_false(was_cut(&c[1]));
    arrive(g, &c[4]); /* next oldest waiting: c[2], not c[1] */
    assert_int_equal(merd_guard_cuts(g), 2);
    assert_true(was_cut(&c[2]));
    assert_false(was_cut(&c[1]));
    assert_false(was_cut(&c[3]));
    // libmicrohttpd closes the cut ones: they count no longer.
    leave(g, &c[0]);
    leave(g, &c[2]);
    assert_int_equal(merd_guard_open(g), 3);
    arrive(g, &c[5]); /* 4 > 3 again: c[3] */
    assert_true(was_cut(&c[3]));
    assert_int_equal(merd_guard_cuts(g), 3);
    leave(g, &c[3]);
    leave(g, &c[1]);
    leave(g, &c[4]);
    leave(g, &c[5]);
    assert_int_equal(merd_guard_open(g), 0);
    merd_guard_stop(g);
}

static void test_head_and_idle_deadlines(void **state)
{
    (void)state;
    merd_guard *g = merd_guard_start(100, HEAD, IDLE);
    assert_non_null(g);
    struct MHD_Connection slow = {0}, busy = {0}, idle = {0};
    double t0 = merd_now();
    arrive(g, &slow);
    arrive(g, &busy);
    arrive(g, &idle);
    merd_guard_request_began(g, &busy);
    merd_guard_request_began(g, &idle);
    double t1 = merd_now();
    merd_guard_request_ended(g, &idle); /* waits for its next head: idle deadline */
    assert_int_equal(merd_guard_sweep(g, t0 + HEAD / 2), 0);
    assert_false(was_cut(&slow));
    // The head deadline: only the connection whose head is still arriving.
    assert_int_equal(merd_guard_sweep(g, merd_now() + HEAD + 1.0), 1);
    assert_true(was_cut(&slow));
    assert_false(was_cut(&busy));
    assert_false(was_cut(&idle));
    assert_int_equal(merd_guard_sweep(g, merd_now() + HEAD + 1.0), 0); /* cut once */
    // The idle deadline is longer; a connection inside a request has none.
    assert_int_equal(merd_guard_sweep(g, t1 + IDLE + 1.0), 1);
    assert_true(was_cut(&idle));
    assert_false(was_cut(&busy));
    assert_int_equal(merd_guard_sweep(g, merd_now() + 100 * IDLE), 0);
    assert_int_equal(merd_guard_cuts(g), 2);
    assert_int_equal(merd_guard_open(g), 3);
    leave(g, &slow);
    leave(g, &busy);
    leave(g, &idle);
    assert_int_equal(merd_guard_open(g), 0);
    merd_guard_stop(g);
}

static void test_many_slow_heads(void **state)
{
    (void)state;
    enum { N = 400, LIMIT = 100 };
    merd_guard *g = merd_guard_start(LIMIT, HEAD, IDLE);
    assert_non_null(g);
    static struct MHD_Connection c[N];
    for (int i = 0; i < N; i++) {
        arrive(g, &c[i]);
        if (i >= LIMIT) {
            assert_true(was_cut(&c[i - LIMIT]));
            leave(g, &c[i - LIMIT]); /* libmicrohttpd closes what was cut */
        }
        assert_true(merd_guard_open(g) <= LIMIT + 1);
    }
    assert_int_equal(merd_guard_cuts(g), N - LIMIT);
    assert_int_equal(merd_guard_open(g), LIMIT);
    for (int i = N - LIMIT; i < N; i++) {
        assert_false(was_cut(&c[i]));
        leave(g, &c[i]);
    }
    merd_guard_stop(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_soft_limit_cuts_oldest_waiting),
        cmocka_unit_test(test_head_and_idle_deadlines),
        cmocka_unit_test(test_many_slow_heads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
