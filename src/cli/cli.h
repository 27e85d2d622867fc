/* cli.h -- shared pieces of the gigatet command-line tool (src/cli/).
 *
 * Exit codes, the contract scripts rely on:
 *   0 ok, 1 usage, 2 bad input file or data (also: the output cannot be written),
 *   3 degenerate input (dimension < 3), 4 out of memory (also: the OpenMP runtime ended the
 *   run, as when it cannot create threads: main.c), 5 check failed (also: an internal error of
 *   the kernel, i.e. a broken invariant).
 */
#ifndef GTET_CLI_H
#define GTET_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

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
/* Print the I/O error's message; return the exit code of s. */
int cli_io_failed(io_status s, const io_error *e);

/* Strict decimal parse of a whole string into [0, max]; 0 on any junk, sign or overflow. */
int cli_parse_u64(const char *s, uint64_t max, uint64_t *v);

/* ---- the option tables (opts.c) ----------------------------------------------------------
 * Each command describes its options and positionals in one table: the parser, the usage
 * line and the --help paragraph all come from it.  Values land in the command's own argument
 * struct, at the offsets the table gives. */
typedef enum cli_opt_kind {
    CLI_OPT_FLAG,    /* no value: `bits` are OR'ed into an unsigned */
    CLI_OPT_STRING,  /* a const char * (the argument itself, not a copy) */
    CLI_OPT_U64      /* a uint64_t in [0, max], strict decimal */
} cli_opt_kind;

typedef struct cli_opt {
    const char *name;      /* as shown in help: "-o", "--check" */
    const char *alias;     /* a second name ("--output"), or NULL */
    cli_opt_kind kind;
    size_t off;            /* offsetof the target in the command's argument struct */
    unsigned bits;         /* CLI_OPT_FLAG: the bits it sets */
    uint64_t max;          /* CLI_OPT_U64: the largest value */
    unsigned mark;         /* OR'ed into cli_parse's *given when the option appears */
    int required;          /* shown without brackets in the synopsis (the command checks it) */
    const char *arg;       /* the value's name in help: "FILE" */
    const char *missing;   /* message when the value is missing; "{opt}": the name as typed */
    const char *invalid;   /* CLI_OPT_U64: message for a bad value ("{value}"); NULL: missing */
    const char *help;      /* help text; '\n' starts an indented line */
} cli_opt;

typedef struct cli_positional {
    const char *name;      /* as shown in help: "INPUT" */
    size_t off;            /* offsetof its const char * in the argument struct */
} cli_positional;

typedef struct cli_command {
    const char *name;            /* "triangulate" */
    const char *summary;         /* help paragraph; '\n' starts an indented line */
    const cli_opt *opts;         /* up to the entry whose name is NULL */
    const cli_positional *pos;   /* up to the entry whose name is NULL; all required */
    const char *missing;         /* message when a positional is missing */
    const char *extra;           /* message for one too many ("{arg}"; "{first}": the first) */
    int (*run)(int argc, char **argv);
} cli_command;

/* Parse argv (the command's arguments, after its name) into args.  *given (when not NULL)
 * receives the OR of the `mark`s of the options that appeared.  CLI_OK, or CLI_USAGE after
 * printing the message. */
int cli_parse(const cli_command *cmd, int argc, char **argv, void *args, unsigned *given);
/* "  gigatet NAME POSITIONALS [OPTIONS]" wrapped under the command's name. */
void cli_print_synopsis(FILE *f, const cli_command *cmd);
/* The command's summary and one entry per option. */
void cli_print_command_help(FILE *f, const cli_command *cmd);

/* Options several commands share, for the argument struct `type` (its field names fixed). */
#define CLI_OPT_QUIET(type)                                                                \
    {.name = "-q", .alias = "--quiet", .kind = CLI_OPT_FLAG, .off = offsetof(type, quiet),  \
     .bits = 1, .help = "print nothing but errors"}
#define CLI_OPT_JSON(type, text)                                                           \
    {.name = "--json", .kind = CLI_OPT_FLAG, .off = offsetof(type, json), .bits = 1,        \
     .help = text}
#define CLI_OPT_POINTS(type, text)                                                         \
    {.name = "--points", .kind = CLI_OPT_STRING, .off = offsetof(type, points),             \
     .arg = "INPUT", .missing = "option --points needs a file name", .help = text}

/* 1 when writing `out` (or the .node beside it when it is a .ele) would replace the existing
 * file `input` (same device and inode). */
int cli_overwrites_input(const char *input, const char *out);

/* A usage error ("PATH: CMD reads ... meshes") unless path names a readable mesh format. */
int cli_need_mesh_format(const char *cmd, const char *path);

/* The notes a failed check of mesh file `path` (read into m) gets after its message: the
 * file's cells that were skipped, and, when `ids` and the violation names tets or vertices,
 * how the checker's 0-based numbers map to the file's ids.  `owner` names the file in them
 * ("the file" for check, "A" or "B" for diff).  Returns buf ("" when there is nothing to say). */
const char *cli_mesh_note(const char *path, const char *owner, const io_mesh *m,
                          const gtet_check_report *r, int ids, char *buf, size_t size);

extern const cli_command cli_cmd_triangulate, cli_cmd_check, cli_cmd_diff, cli_cmd_generate;

double cli_now(void);          /* monotonic seconds */
long cli_max_rss_bytes(void);  /* getrusage ru_maxrss in bytes */


#endif
