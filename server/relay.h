/* meristemd — one relayed connection (see front.h).
 *
 * The front keeps each client's socket for the connection's whole life and
 * gives libmicrohttpd one end of a socketpair instead. The relay moves bytes
 * between the two through two fixed buffers:
 *   - up, client → libmicrohttpd: only what has been checked. Each request
 *     head must pass merd_head_check and its body merd_framing_feed before
 *     its bytes go on; a pipelined request is checked while libmicrohttpd
 *     still answers the one before.
 *   - down, libmicrohttpd → client: as it comes, so a large snapshot streams.
 * Either side that cannot take more stops the other from being read.
 *
 * When a head or a chunk is malformed, nothing more is forwarded or read
 * from the client. Every request already forwarded is answered first (the
 * `slot` counts them as libmicrohttpd completes them; a body cut by the bad
 * chunk is ended, so libmicrohttpd gives up that request), then the relay
 * sends the problem+json refusal with "Connection: close" and ends. */
#ifndef MERISTEMD_RELAY_H
#define MERISTEMD_RELAY_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "server/head.h"

/* Requests libmicrohttpd has completed on one connection, counted by its
 * completion callback (any thread); read by the front's thread. */
typedef struct merd_relay_slot {
    atomic_uint done;    /* completed, answered or not */
    atomic_uint replied; /* completed with the whole answer sent */
    atomic_bool watch;   /* the relay waits for `done`: wake the front */
} merd_relay_slot;

typedef struct merd_relay merd_relay;

typedef enum merd_relay_state {
    MERD_RELAY_OPEN,    /* relaying */
    MERD_RELAY_ENDING,  /* refusing, or libmicrohttpd has closed: answers still go out */
    MERD_RELAY_DONE,    /* everything sent: close the client gracefully */
    MERD_RELAY_GONE,    /* the client went away: close it at once */
} merd_relay_state;

/* A relay between the client's socket and `pair`, the front's end of the
 * socketpair whose other end libmicrohttpd has, and whose
 * completions `slot` counts (reset here). Heads cost at most `budget`
 * (head.h). Takes `pair` (closed by merd_relay_free), not `client`. NULL
 * when out of memory. */
merd_relay *merd_relay_new(int client, int pair, merd_relay_slot *slot, size_t budget);

/* Moves what can move both ways without blocking, checks what came from the
 * client, and says where the connection stands. O(bytes moved). */
merd_relay_state merd_relay_pump(merd_relay *r);

/* epoll reported the client's end (`client`) or libmicrohttpd's: the next
 * pump reads it again. A side read dry (a short read) is not read again until
 * then, as epoll reports what arrives later. O(1). */
void merd_relay_ready(merd_relay *r, bool client);

/* The epoll events each socket waits for now (0: none, leave it out of the set). */
uint32_t merd_relay_client_events(const merd_relay *r);
uint32_t merd_relay_pair_events(const merd_relay *r);

/* Whether the relay waits for libmicrohttpd to read what it was sent before
 * it ends libmicrohttpd's input (no event says so): pump it again soon. */
bool merd_relay_polling(const merd_relay *r);

/* The front's end of the socketpair (for its epoll set). */
int merd_relay_pair(const merd_relay *r);

/* Stops reading the client: what was checked still goes on, then libmicrohttpd
 * sees the end of the input (for shutting down). */
void merd_relay_finish(merd_relay *r);

/* Writes the refusal `v` (a MERD_HEAD_BAD verdict) as a whole HTTP response
 * with a problem+json body and "Connection: close" into out[0..size): its
 * length, or 0 when it does not fit or memory runs out. */
size_t merd_relay_refusal(const merd_head_verdict *v, char *out, size_t size);

/* Closes the front's end of the socketpair and frees the relay. NULL is fine. */
void merd_relay_free(merd_relay *r);

#endif
