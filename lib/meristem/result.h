/* meristem — result codes and the error record every fallible call fills.
 *
 * Functions that can fail return a mer_result and, when the caller passes a
 * non-NULL mer_error, describe the failure there in words a person can act on.
 * The server copies `field` and `message` into an application/problem+json body,
 * so messages name the offending field and the allowed range where there is one.
 */
#ifndef MERISTEM_RESULT_H
#define MERISTEM_RESULT_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mer_result {
    MER_OK = 0,
    MER_ERR_INVALID,  /* an argument is malformed or of the wrong kind */
    MER_ERR_RANGE,    /* a value lies outside its documented range */
    MER_ERR_NOMEM,    /* an allocation failed; nothing was changed */
    MER_ERR_FORMAT,   /* input data (a glTF file, a journal record) is corrupt */
    MER_ERR_LIMIT,    /* a configured limit would be exceeded */
    MER_ERR_INTERNAL, /* a bug: an invariant did not hold */
    MER_ERR_NOT_FOUND, /* a named thing (a node id) was never issued */
    MER_ERR_GONE,     /* a named thing existed but was removed (a pruned or shed node) */
    MER_ERR_ROOT      /* the edit would remove a plant's first internode, emptying it */
} mer_result;

#define MER_ERROR_FIELD_MAX 64
#define MER_ERROR_MESSAGE_MAX 256

typedef struct mer_error {
    mer_result code;
    char field[MER_ERROR_FIELD_MAX];     /* dotted path of the bad input, or "" */
    char message[MER_ERROR_MESSAGE_MAX]; /* one sentence, no trailing newline */
    /* Where in a text input (a growth model's definition, mer_scene_set_definition)
     * the failure is: 1-based line and column; 0 when it is not about a text. */
    unsigned line, column;
} mer_error;

/* A stable lower-case name for `code` ("ok", "invalid", ...). Never NULL. */
const char *mer_result_name(mer_result code);

/* Fills `err` (which may be NULL: then nothing happens) and returns `code`, so a
 * caller can write `return mer_error_set(err, MER_ERR_RANGE, "count", "...")`.
 * `field` may be NULL. Messages longer than the buffer are truncated. The line
 * and column are reset to 0; a caller reporting a position sets them after. */
mer_result mer_error_set(mer_error *err, mer_result code, const char *field,
                         const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* Resets `err` to MER_OK with empty strings. `err` may be NULL. */
void mer_error_clear(mer_error *err);

#ifdef __cplusplus
}
#endif

#endif
