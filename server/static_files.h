/* meristemd — the brush client's static files, with no way out of the web root. */
#ifndef MERISTEMD_STATIC_FILES_H
#define MERISTEMD_STATIC_FILES_H

#include <stddef.h>
#include <stdio.h>

#include <microhttpd.h>

#include "server/request.h"

/* Answers GET/HEAD `req->url` from the canonical folder `root` (as realpath
 * gives it). A path that names no regular file inside `root`, by "..", an
 * encoded "%2e%2e" (libmicrohttpd decodes it before we see it), a symlink that
 * leads outside, or anything else, gets a 404 problem; a folder gets its
 * index.html, or a 301 to the same path with a trailing slash. */
enum MHD_Result merd_static_serve(merd_request *req, const char *root);

/* Settles --web-root before the server starts: when it was not given and the
 * installed folder is missing, a meristemd run from its build tree serves the
 * build's webroot/; failing that `web_root` becomes "" (the API only). Says
 * which on `log`. 0, or -1 when a --web-root given does not exist. */
int merd_static_find_root(char *web_root, size_t size, FILE *log);

/* The Content-Type for a file name, by its extension; never NULL. */
const char *merd_static_mime_type(const char *path);

#endif
