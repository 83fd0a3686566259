/* meristemd — the libmicrohttpd front: daemon lifecycle and request plumbing. */
#ifndef MERISTEMD_HTTP_H
#define MERISTEMD_HTTP_H

#include <stdio.h>

#include "server/settings.h"

typedef struct mer_server mer_server;
typedef struct mer_app mer_app;

/* Starts listening as `config` says (copied), answering with `app` (borrowed;
 * may be NULL only in tests of static files). Returns NULL after printing the
 * reason to `err`. The web root must exist. */
mer_server *mer_server_start(const mer_settings *config, mer_app *app, FILE *err);

/* The TCP port actually bound (useful with --port 0). */
unsigned mer_server_port(const mer_server *server);

/* Stops accepting, finishes or drops open connections, frees everything. NULL is fine. */
void mer_server_stop(mer_server *server);

#endif
