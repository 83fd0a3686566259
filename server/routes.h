/* meristemd — the route table: method and path to handler. */
#ifndef MERISTEMD_ROUTES_H
#define MERISTEMD_ROUTES_H

#include <microhttpd.h>

#include "server/request.h"

/* Answers `req` once its body is complete: a /v1 route by the table, anything
 * else from the web root. Every refusal is application/problem+json. */
enum MHD_Result merd_route(merd_request *req, const char *web_root);

#endif
