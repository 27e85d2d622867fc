/* options.c -- the defaults of gtet_options (gigatet.h). */
#include "gigatet.h"

#include <string.h>

void gtet_options_init(gtet_options *opts)
{
    if (!opts) return;
    memset(opts, 0, sizeof *opts);
    opts->threads = 0;
    opts->verbosity = 0;
    opts->check = 0;
    opts->degeneracies = 0;
    opts->degeneracy_limit = 100000;
    opts->memory_limit = 0;  /* the guard against the machine's limits (memory.c) */
}
