/* status.c -- status strings and option defaults of the public API. */
#include "../gigatet.h"

#include <string.h>

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
    }
    return "unknown status";
}

void gtet_options_init(gtet_options *opts)
{
    if (!opts) return;
    memset(opts, 0, sizeof *opts);
    opts->threads = 0;
    opts->verbosity = 0;
    opts->check = 0;
    opts->degeneracies = 0;
    opts->degeneracy_limit = 100000;
}
