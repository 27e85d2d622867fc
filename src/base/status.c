/* status.c -- status strings and error records of the public API (gigatet.h, base.h). */
#include "base.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>

#define GTET_STR_(x) #x
#define GTET_STR(x) GTET_STR_(x)

const char *gtet_version(void)
{
    return GTET_STR(GTET_VERSION_MAJOR) "." GTET_STR(GTET_VERSION_MINOR) "." GTET_STR(
        GTET_VERSION_PATCH);
}

const char *gtet_status_str(gtet_status status)
{
    switch (status) {
    case GTET_OK: return "success";
    case GTET_ERR_ARGUMENT: return "invalid argument";
    case GTET_ERR_NONFINITE: return "input contains a NaN or infinite coordinate";
    case GTET_ERR_DEGENERATE_INPUT:
        return "degenerate input: fewer than 4 distinct points, or all collinear or coplanar";
    case GTET_ERR_OUT_OF_MEMORY: return "out of memory";
    case GTET_ERR_TOO_LARGE: return "input too large for 32-bit vertex or tet indices";
    case GTET_ERR_CHECK_FAILED: return "the exact checker found a violated invariant";
    case GTET_ERR_INTERNAL: return "internal error (a broken invariant; please report it)";
    case GTET_ERR_CANCELLED: return "cancelled by the caller (gtet_options.cancel)";
    }
    return "unknown status";
}

void base_error(gtet_error *err, gtet_status status, size_t index, int dimension,
                const char *fmt, ...)
{
    if (!err) return;
    err->status = status;
    err->index = index;
    err->dimension = dimension;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
}

gtet_status base_fail(gtet_error *err, gtet_status s, const char *what)
{
    if (err && err->status != s)
        base_error(err, s, SIZE_MAX, -1, "%s: %s", what, gtet_status_str(s));
    return s;
}
