/* meristemd — the front: our own accept loop before libmicrohttpd.
 *
 * libmicrohttpd 0.9.75 answers a malformed or oversized request head itself,
 * with a fixed HTML page, before any application code runs: no option,
 * callback or access handler can replace those bodies (its
 * transmit_error_response_static(); MHD_OPTION_URI_LOG_CALLBACK runs after the
 * request line but cannot answer, MHD_OPTION_NOTIFY_CONNECTION only reports a
 * connection's start and end). So meristemd listens itself: the front accepts
 * each connection, waits (with MSG_PEEK, reading nothing) until its first
 * request head is complete, checks it as libmicrohttpd would (head.h), and
 *   - answers a head libmicrohttpd would refuse with the same status as an
 *     application/problem+json body, then closes the connection;
 *   - hands every other connection to libmicrohttpd (MHD_add_connection on a
 *     daemon started with MHD_USE_NO_LISTEN_SOCKET) through a relay.
 * Peeking needs no copy of the head while it arrives slowly; a head larger
 * than the socket buffer is no problem, as one larger than the budget (half
 * of --connection-memory) is itself the 414/431 case, so the front never
 * looks at more than budget + 1 bytes of head.
 *
 * From the first good head on, the front keeps the client's socket for the
 * connection's whole life: libmicrohttpd gets one end of a socketpair (with
 * the client's address) and the front relays (relay.h). Every later request
 * head on a kept-alive connection, pipelined or not, and every chunk of a
 * chunked body is checked before it goes on (head.h, framing.h); a bad one is
 * answered with problem+json once the requests before it are answered. So
 * libmicrohttpd never sees a request it would refuse in HTML. Responses are
 * copied back as they come (a large snapshot streams through 64 KiB).
 *
 * While a head arrives the front protects the daemon as the guard (guard.h)
 * does inside libmicrohttpd: a first head not complete --header-timeout
 * seconds after the connection was accepted is cut (later heads are the
 * guard's: it cuts a connection idle for --timeout); at most
 * --max-connections-per-ip connections come from one address, counted once
 * whether their head arrives or libmicrohttpd has them; and when the waiting
 * heads and libmicrohttpd's connections together pass --max-connections, the
 * oldest waiting head makes room for each new arrival. A connection the front
 * ends is closed gracefully: its write side is shut and what the client still
 * sends is read and dropped for a moment, so that the answer is not lost to a
 * reset. A relay that refuses or flushes its last answers has --timeout
 * seconds to do it.
 *
 * One thread, one epoll set. */
#ifndef MERISTEMD_FRONT_H
#define MERISTEMD_FRONT_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/socket.h>

#include <microhttpd.h>

#include "server/guard.h"

typedef struct merd_front merd_front;

typedef struct merd_front_config {
    double head_seconds;   /* --header-timeout */
    double idle_seconds;   /* --timeout */
    unsigned per_ip_limit; /* --max-connections-per-ip */
    unsigned soft_limit;   /* --max-connections */
    size_t budget;         /* half of --connection-memory (head.h) */
} merd_front_config;

/* Listens on `address` (port 0: any free one), stores the front in *out and
 * starts the thread that hands good connections to `daemon` (started with
 * MHD_USE_NO_LISTEN_SOCKET and without a per-address limit: the front counts
 * those; it must outlive the front). `guard` (borrowed) says how many
 * connections the daemon has. False when the address cannot be bound or
 * listened on (in use, not permitted) or memory runs out. */
bool merd_front_start(const struct sockaddr_storage *address, const merd_front_config *config,
                      struct MHD_Daemon *daemon, merd_guard *guard, merd_front **out);

/* libmicrohttpd has completed a request (MHD_OPTION_NOTIFY_COMPLETED) on the
 * connection whose descriptor is `fd`; `replied`: its whole answer was sent.
 * Any thread; O(1). */
void merd_front_answered(merd_front *f, int fd, bool replied);

/* The TCP port bound. */
unsigned merd_front_port(const merd_front *f);

/* Stops accepting: new connections wait unaccepted in the listen queue until
 * merd_front_stop closes it. Heads already accepted are still checked. */
void merd_front_quiesce(merd_front *f);

/* Stops reading clients, lets the answers libmicrohttpd has given go out (at
 * most a few seconds), stops the thread and closes every connection. NULL is
 * fine. */
void merd_front_stop(merd_front *f);

/* Closes the listener and frees the front, after merd_front_stop and once
 * libmicrohttpd has stopped (its completions still call merd_front_answered
 * until then). NULL is fine. */
void merd_front_free(merd_front *f);

#endif
