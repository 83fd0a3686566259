/* meristemd — why a request was refused, and the one mapping from a library
 * result to an HTTP problem.
 *
 * Every refusal the daemon sends is an RFC 9457 problem: a status, a problem
 * type (urn:meristem:problem:SLUG), the JSON path of the input at fault and a
 * sentence saying what to do. The server never reads the wording of a library
 * message: the mer_result code alone decides status and type.
 */
#ifndef MERISTEMD_REFUSAL_H
#define MERISTEMD_REFUSAL_H

#include <meristem/result.h>

/* Room for a field path such as "edits[12].symmetry.mirror.normal". */
#define MERD_FIELD_MAX 96

/* Why a request was refused: everything a problem+json body needs. */
typedef struct merd_refusal {
    unsigned status;            /* 400, 404, 409, 413, 415, 422, 429, 500, 503 */
    char slug[40];              /* urn:meristem:problem:SLUG */
    char field[MERD_FIELD_MAX]; /* JSON path of the input at fault, or "" */
    char detail[400];
    unsigned line, column;      /* where in a text input (an L-system's source); 0: not a text */
} merd_refusal;

/* Fills `why` (line and column 0) and returns -1, for `return merd_refuse(...)`.
 * `field` may be NULL. */
int merd_refuse(merd_refusal *why, unsigned status, const char *slug, const char *field,
                const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* The library's failure `rc` (not MER_OK) as a refusal, returning -1. The
 * field is `where` joined with err->field ("edits[1]" + "node"); the detail is
 * err->message; err->line and err->column are carried over. Status and type by code:
 *   MER_ERR_NOT_FOUND  404 unknown-node   (a node id never issued)
 *   MER_ERR_GONE       409 dead-node      (a node pruned or shed)
 *   MER_ERR_ROOT       422 root-node      (a prune of a plant's first internode)
 *   MER_ERR_LIMIT      409 limit          (a limit of the tree or scene)
 *   MER_ERR_RANGE      422 out-of-range
 *   MER_ERR_NOMEM      503 out-of-memory  (nothing was changed; try again)
 *   MER_ERR_INTERNAL   500 internal
 *   otherwise          422 invalid-field  (MER_ERR_INVALID, MER_ERR_FORMAT) */
int merd_refuse_lib(merd_refusal *why, mer_result rc, const mer_error *err, const char *where);

/* Joins a field path: "edits[2]" + "count" is "edits[2].count"; either part
 * may be "". Truncates to `n` bytes. */
void merd_path(char *out, size_t n, const char *where, const char *key);

#endif
