/* meristemd — the libmicrohttpd front: daemon lifecycle and request plumbing. */
#ifndef MERISTEMD_HTTP_H
#define MERISTEMD_HTTP_H

#include <stdbool.h>
#include <stdio.h>

#include "server/settings.h"

typedef struct merd_server merd_server;
typedef struct merd_app merd_app;

/* Starts listening as `config` says (copied), answering with `app` (borrowed;
 * may be NULL only in tests of static files). Returns NULL after printing the
 * reason to `err`. The web root must exist. */
merd_server *merd_server_start(const merd_settings *config, merd_app *app, FILE *err);

/* The TCP port actually bound (useful with --port 0). */
unsigned merd_server_port(const merd_server *server);

/* Stops accepting new connections; open ones are still served. */
void merd_server_quiesce(merd_server *server);

/* Waits until no request is in progress (every suspended one answered and
 * sent), at most `seconds`. Whether it got there. */
bool merd_server_settle(merd_server *server, double seconds);

/* Stops the daemon, closing every connection, and frees everything. Every
 * suspended request must have been answered (merd_request_finish) first:
 * libmicrohttpd aborts the process otherwise. NULL is fine. */
void merd_server_stop(merd_server *server);

#endif
