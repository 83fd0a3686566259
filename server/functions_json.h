/* meristemd — an inverse session's functions in JSON (issue 16: {"name",
 * "kind", "samples", "points": [[x, y, m], ...]}) written as the .fset text the
 * library reads (G04 §4; L-studio's function gallery). */
#ifndef MERD_FUNCTIONS_JSON_H
#define MERD_FUNCTIONS_JSON_H

#include <stddef.h>

#include <jansson.h>

#include "server/refusal.h"

/* The array `v` (at field path `f`) as .fset text, malloc'd and 0-terminated
 * into *out, its length in *len. The shapes are checked here (a refusal names
 * the element's field); what a function's points mean (x from 0 to 1, a known
 * name) the library checks when it reads the text. -1 with `why` filled. */
int merd_functions_fset(const json_t *v, const char *f, char **out, size_t *len,
                        merd_refusal *why);

#endif
