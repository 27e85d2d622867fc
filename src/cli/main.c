/* main.c -- the gigatet command-line tool: dispatch, help, version, shared helpers.
 *
 * The commands are triangulate, check, diff and generate (cmd_*.c), each with its option
 * table; `gigatet --help` prints their synopses.  Only this directory prints or exits; the library and src/io report through status codes.
 * The exit codes are listed in cli.h and in --help.  The help is drawn from the commands'
 * option tables (opts.c) and the table of file formats (io_formats in src/io).
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static const cli_command *const commands[] = {&cli_cmd_triangulate, &cli_cmd_check,
                                              &cli_cmd_diff, &cli_cmd_generate};
enum { NCOMMANDS = sizeof commands / sizeof commands[0] };

static void print_help(FILE *f)
{
    fprintf(f, "gigatet %d.%d.%d -- robust, fast 3D Delaunay tetrahedrization\n\nUsage:\n",
            GTET_VERSION_MAJOR, GTET_VERSION_MINOR, GTET_VERSION_PATCH);
    for (int c = 0; c < NCOMMANDS; c++) cli_print_synopsis(f, commands[c]);
    fputs("  gigatet --help | --version\n\n", f);
    for (int c = 0; c < NCOMMANDS; c++) cli_print_command_help(f, commands[c]);
    fputs("\nFile formats, by extension (points: triangulate's INPUT, --points, generate's -o;\n"
          "meshes: triangulate's -o, check, diff; surfaces: generate surface's --mesh):\n", f);
    for (int k = 0; k < IO_FMT_COUNT; k++)
        fprintf(f, "  %-6s %s\n", io_formats[k].ext, io_formats[k].description);
    fputs("Exact duplicate points are counted and mapped to their first occurrence, never\n"
          "silently dropped.\n"
          "\n"
          "Exit codes: 0 ok, 1 usage, 2 bad input file or data (or unwritable output),\n"
          "3 degenerate input (all points coplanar, collinear or fewer than 4 distinct),\n"
          "4 out of memory (or threads that could not be created), 5 check failed (diff: the\n"
          "meshes differ).  A failed run leaves no partial output file.\n"
          "\n"
          "Generator kinds:\n", f);
    for (const char *const *k = io_generator_kinds(); *k; k++)
        fprintf(f, "  %-20s %s\n", *k, io_generator_help(*k));
}

void cli_error(const char *fmt, ...)
{
    va_list ap;
    fputs("gigatet: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

int cli_usage(const char *fmt, ...)
{
    va_list ap;
    fputs("gigatet: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputs("\nTry 'gigatet --help'.\n", stderr);
    return CLI_USAGE;
}

int cli_exit_of_io(io_status s)
{
    switch (s) {
    case IO_OK: return CLI_OK;
    case IO_ERR_ARGUMENT: return CLI_USAGE;
    case IO_ERR_NOMEM: return CLI_NOMEM;
    case IO_ERR_INPUT:
    case IO_ERR_WRITE: return CLI_BAD_INPUT;
    }
    return CLI_BAD_INPUT;
}

int cli_io_failed(io_status s, const io_error *e)
{
    cli_error("%s", e->message);
    return cli_exit_of_io(s);
}

int cli_exit_of_gtet(gtet_status s)
{
    switch (s) {
    case GTET_OK: return CLI_OK;
    case GTET_ERR_ARGUMENT: return CLI_USAGE;
    case GTET_ERR_NONFINITE:
    case GTET_ERR_TOO_LARGE: return CLI_BAD_INPUT;
    case GTET_ERR_DEGENERATE_INPUT: return CLI_DEGENERATE;
    case GTET_ERR_OUT_OF_MEMORY: return CLI_NOMEM;
    case GTET_ERR_CHECK_FAILED:
    case GTET_ERR_INTERNAL:
    case GTET_ERR_CANCELLED: return CLI_CHECK_FAILED;  /* the CLI sets no cancel hook */
    }
    return CLI_CHECK_FAILED;
}

int cli_parse_u64(const char *s, uint64_t max, uint64_t *v)
{
    uint64_t x = 0;
    if (!s || !*s) return 0;
    for (const char *p = s; *p; p++) {
        if (*p < '0' || *p > '9') return 0;
        unsigned d = (unsigned)(*p - '0');
        if (d > max || x > (max - d) / 10) return 0;
        x = x * 10 + d;
    }
    *v = x;
    return 1;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

long cli_max_rss_bytes(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return -1;
    return ru.ru_maxrss * 1024L; /* Linux reports kilobytes */
}

/* 1 while a command runs: an exit() then is not the command's own return but a library's.
 * libgomp calls exit(1) after "libgomp: Thread creation failed: ..." when it cannot start a
 * parallel region's threads (the process limit, ulimit -u, reached between the library's probe
 * and the region, or a region the probe does not cover: NOTES.md E183); the handler removes
 * the temporaries, says what to do and exits 4 (the resources' code) instead. */
static volatile int command_running;

static void exit_during_command(void)
{
    if (!command_running) return;
    io_out_unlink_all();
    fputs("gigatet: the OpenMP runtime ended the run (its message is above): if it could not "
          "create threads, ask for fewer (-t N) or raise the process limit (ulimit -u)\n",
          stderr);
    _exit(CLI_NOMEM);
}

int main(int argc, char **argv)
{
    io_out_catch_signals();  /* NOTES.md E156 */
    atexit(exit_during_command);
    if (argc < 2) {
        print_help(stderr);
        return CLI_USAGE;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        print_help(stdout);
        return CLI_OK;
    }
    if (!strcmp(cmd, "--version")) {
        printf("gigatet %d.%d.%d\n", GTET_VERSION_MAJOR, GTET_VERSION_MINOR, GTET_VERSION_PATCH);
        return CLI_OK;
    }
    for (int i = 2; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            print_help(stdout);
            return CLI_OK;
        }
    for (int c = 0; c < NCOMMANDS; c++)
        if (!strcmp(cmd, commands[c]->name)) {
            command_running = 1;
            int rc = commands[c]->run(argc - 2, argv + 2);
            command_running = 0;
            return rc;
        }
    char names[128] = "";
    for (int c = 0; c < NCOMMANDS; c++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", c ? ", " : "",
                 commands[c]->name);
    return cli_usage("unknown command '%s' (%s)", cmd, names);
}
