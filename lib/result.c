/* meristem — result codes and error records. */
#include "config.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <meristem/result.h>

const char *mer_result_name(mer_result code)
{
    switch (code) {
    case MER_OK: return "ok";
    case MER_ERR_INVALID: return "invalid";
    case MER_ERR_RANGE: return "range";
    case MER_ERR_NOMEM: return "nomem";
    case MER_ERR_FORMAT: return "format";
    case MER_ERR_LIMIT: return "limit";
    case MER_ERR_INTERNAL: return "internal";
    case MER_ERR_NOT_FOUND: return "not-found";
    case MER_ERR_GONE: return "gone";
    case MER_ERR_ROOT: return "root";
    }
    return "unknown";
}

mer_result mer_error_set(mer_error *err, mer_result code, const char *field,
                         const char *fmt, ...)
{
    if (err == NULL)
        return code;
    err->code = code;
    err->line = err->column = 0;
    snprintf(err->field, sizeof err->field, "%s", field != NULL ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return code;
}

void mer_error_clear(mer_error *err)
{
    if (err == NULL)
        return;
    memset(err, 0, sizeof *err);
    err->code = MER_OK;
}
