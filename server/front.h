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
 *     daemon started with MHD_USE_NO_LISTEN_SOCKET), which then reads the
 *     very bytes the front looked at.
 * Peeking needs no copy of the head and leaves libmicrohttpd's handling of
 * the request untouched; a head larger than the socket buffer is no problem,
 * as one larger than the budget (half of --connection-memory) is itself the
 * 414/431 case, so the front never looks at more than budget + 1 bytes of
 * head.
 *
 * Only a connection's first request is checked: on a keep-alive connection
 * the later heads go to libmicrohttpd directly and a malformed one still gets
 * its HTML page. Checking those too would mean relaying every byte.
 *
 * While a head arrives the front protects the daemon as the guard (guard.h)
 * does inside libmicrohttpd: a head not complete --header-timeout seconds
 * after the connection was accepted is cut; at most --max-connections-per-ip
 * heads wait from one address (libmicrohttpd counts the connections it has
 * on top); and when the waiting heads and libmicrohttpd's connections
 * together pass --max-connections, the oldest waiting head makes room for each
 * new arrival. A refused connection is closed gracefully: its write side is
 * shut and what the client still sends is read and dropped for a moment, so
 * that the answer is not lost to a reset.
 *
 * One thread, one epoll set. */
#ifndef MERISTEMD_FRONT_H
#define MERISTEMD_FRONT_H

#include <stddef.h>
#include <sys/socket.h>

#include <microhttpd.h>

#include "server/guard.h"

typedef struct merd_front merd_front;

typedef struct merd_front_config {
    double head_seconds;   /* --header-timeout */
    unsigned per_ip_limit; /* --max-connections-per-ip */
    unsigned soft_limit;   /* --max-connections */
    size_t budget;         /* half of --connection-memory (head.h) */
} merd_front_config;

/* Listens on `address` (port 0: any free one) and starts the thread that hands
 * good connections to `daemon` (started with MHD_USE_NO_LISTEN_SOCKET; it must
 * outlive the front). `guard` (borrowed) says how many connections the daemon
 * has. NULL when the address cannot be bound or listened on (in use, not
 * permitted) or memory runs out. */
merd_front *merd_front_start(const struct sockaddr_storage *address, const merd_front_config *config,
                             struct MHD_Daemon *daemon, merd_guard *guard);

/* The TCP port bound. */
unsigned merd_front_port(const merd_front *f);

/* Stops accepting: new connections wait unaccepted in the listen queue until
 * merd_front_stop closes it. Heads already accepted are still checked. */
void merd_front_quiesce(merd_front *f);

/* Stops the thread, closes the listener and every connection not handed on,
 * and frees the front. NULL is fine. */
void merd_front_stop(merd_front *f);

#endif
