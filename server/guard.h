/* meristemd — the connection guard: slow or idle clients cannot hold the
 * daemon's connections.
 *
 * libmicrohttpd's timeout is an idle timeout: a client that sends its request
 * head one byte a second is never idle, and a thousand of them fill every
 * connection slot. The guard keeps the connections that are not in a request
 * (head still arriving, or idle between keep-alive requests) in arrival order
 * and
 *   - closes a head that is not complete `head_seconds` after it began, and an
 *     idle keep-alive connection after `idle_seconds`;
 *   - when more than `soft_limit` connections are open, closes the oldest of
 *     them for each one that arrives, so a new client always gets in while
 *     libmicrohttpd's hard limit (set a little higher) is not reached.
 * Connections inside a request (reading a body, waiting for a worker, sending)
 * are never touched. A cut is shutdown(2) of the socket under the guard's lock;
 * libmicrohttpd then sees the peer gone and closes the connection itself. */
#ifndef MERISTEMD_GUARD_H
#define MERISTEMD_GUARD_H

#include <stddef.h>

#include <microhttpd.h>

typedef struct merd_guard merd_guard;

/* Starts the guard and its sweeping thread. NULL when out of memory. */
merd_guard *merd_guard_start(unsigned soft_limit, double head_seconds, double idle_seconds);

/* Stops the thread and frees the guard; call after the daemon has stopped. NULL is fine. */
void merd_guard_stop(merd_guard *g);

/* MHD_OPTION_NOTIFY_CONNECTION callback; `cls` is the guard. */
void merd_guard_notify(void *cls, struct MHD_Connection *connection, void **socket_context,
                       enum MHD_ConnectionNotificationCode code);

/* The connection's request head is complete: it leaves the guard's list. O(1). */
void merd_guard_request_began(merd_guard *g, struct MHD_Connection *connection);

/* The connection's request is over: it waits for the next head, idle. O(1). */
void merd_guard_request_ended(merd_guard *g, struct MHD_Connection *connection);

/* Connections started and not yet closed. O(1). */
unsigned merd_guard_open(merd_guard *g);

/* Connections cut so far (for the log and tests). */
size_t merd_guard_cuts(merd_guard *g);

#endif
