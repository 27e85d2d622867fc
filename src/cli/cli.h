/* cli.h -- shared pieces of the gigatet command-line tool (src/cli/).
 *
 * Exit codes, the contract scripts rely on (issue 3):
 *   0 ok, 1 usage, 2 bad input file or data (also: the output cannot be written),
 *   3 degenerate input (dimension < 3), 4 out of memory, 5 check failed (also: an internal
 *   error of the kernel, i.e. a broken invariant).
 */
#ifndef GTET_CLI_H
#define GTET_CLI_H

#include <stdint.h>

#include "gigatet.h"
#include "io/io.h"

enum {
    CLI_OK = 0,
    CLI_USAGE = 1,
    CLI_BAD_INPUT = 2,
    CLI_DEGENERATE = 3,
    CLI_NOMEM = 4,
    CLI_CHECK_FAILED = 5
};

/* Print "gigatet: <message>" to stderr. */
void cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Print a usage error and the hint to run --help; returns CLI_USAGE. */
int cli_usage(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

int cli_exit_of_io(io_status s);
int cli_exit_of_gtet(gtet_status s);

/* Strict decimal parse of a whole string into [0, max]; 0 on any junk, sign or overflow. */
int cli_parse_u64(const char *s, uint64_t max, uint64_t *v);

/* Option matching: if argv[*i] is `name` (then the value is argv[*i+1]) or `name=value`,
 * set *val, advance *i past the value and return 1; return -1 when the value is missing. */
int cli_opt_value(int argc, char **argv, int *i, const char *name, const char **val);

double cli_now(void);          /* monotonic seconds */
long cli_max_rss_bytes(void);  /* getrusage ru_maxrss in bytes */

int cli_triangulate(int argc, char **argv);
int cli_check(int argc, char **argv);
int cli_diff(int argc, char **argv);
int cli_generate(int argc, char **argv);

#endif
