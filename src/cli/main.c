/* main.c -- the gigatet command-line tool: dispatch, help, version, shared helpers.
 *
 *   gigatet triangulate INPUT [-o OUTPUT] [-t THREADS] [--check] [--stats]
 *                       [--degeneracies FILE.json [--degeneracies-limit N]] [-q]
 *   gigatet check MESH [--points INPUT] [--delaunay] [--any-orientation] [--full] [--json] [-q]
 *   gigatet diff A B [--points INPUT] [--groups N] [--json] [-q]
 *   gigatet generate KIND N [--seed S] -o FILE [-q]
 *   gigatet --help | --version
 *
 * Only this directory prints or exits; the library and src/io report through status codes.
 * The exit codes are listed in cli.h and in --help.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

static const char help_text[] =
    "gigatet %d.%d.%d -- robust, fast 3D Delaunay tetrahedrization\n"
    "\n"
    "Usage:\n"
    "  gigatet triangulate INPUT [-o OUTPUT] [-t THREADS] [--check] [--stats]\n"
    "                      [--degeneracies FILE.json [--degeneracies-limit N]] [-q]\n"
    "  gigatet check MESH [--points INPUT] [--delaunay] [--any-orientation] [--full]\n"
    "                [--json] [-q]\n"
    "  gigatet diff A B [--points INPUT] [--groups N] [--json] [-q]\n"
    "  gigatet generate KIND N [--seed S] -o FILE [-q]\n"
    "  gigatet --help | --version\n"
    "\n"
    "triangulate  Delaunay tetrahedrization of the points of INPUT.  Prints one summary line\n"
    "             (points, duplicates, tets, seconds, tets/s) on stdout.\n"
    "  -o OUTPUT    write the mesh: .ele (TetGen, writes NAME.node and NAME.ele, 1-based),\n"
    "               .msh (Gmsh 4.1 ASCII), .vtu (VTK XML); without -o nothing is written\n"
    "  -t THREADS   worker threads, 0 = all cores (default 0; at most 1024)\n"
    "  --check      verify the result with the exact checker before writing it\n"
    "  --stats      print a JSON object of statistics after the summary line\n"
    "  --degeneracies FILE.json\n"
    "               write every decision of the symbolic perturbation (five co-spherical\n"
    "               points; a point on a hull facet's circle: mesh vertex ids, coordinates,\n"
    "               the term that decided, the sign) and the predicate counters as JSON\n"
    "  --degeneracies-limit N\n"
    "               store at most N decisions (default 100000; the counts stay exact)\n"
    "  -q           print nothing but errors\n"
    "check        Verify a mesh (.ele with its .node, .msh 2.2/4.1, .vtu) with the exact\n"
    "             checker.  By default the mesh must be THE canonical Delaunay mesh (ties\n"
    "             broken by the symbolic perturbation, as gigatet and CGAL do).\n"
    "  --points INPUT  also check that every point of INPUT is a vertex (matched by\n"
    "                  coordinates) or a duplicate of one\n"
    "  --delaunay      judge the Delaunay property itself, ties allowed: any tool's\n"
    "                  Delaunay mesh passes\n"
    "  --any-orientation  accept and count negatively oriented tets (flat ones fail)\n"
    "  --full          add the O(n*m) empty-sphere test (small meshes only)\n"
    "  --json          print one JSON report on stdout (mode, counts, first violation)\n"
    "diff         Compare two meshes of one point set as sets of tets over coordinates:\n"
    "             exit 0 identical, 5 different, and say how (tie-breaking of co-spherical\n"
    "             groups, listed; or which side is not Delaunay; or different points).\n"
    "  --points INPUT  check both against the input points too\n"
    "  --groups N      list at most N groups (default 10; 0 = all)\n"
    "  --json          print one JSON report on stdout\n"
    "generate     Write about N points of KIND to FILE (.xyz, .node, .ply or .bin).\n"
    "  --seed S     seed of the random kinds (default 1)\n"
    "\n"
    "Input formats (by extension): .xyz (x y z per line, # comments), .node (TetGen),\n"
    ".ply (ascii or binary_little_endian), .bin (little-endian uint64 count, then count*3\n"
    "little-endian doubles).  Exact duplicate points are counted and mapped to their first\n"
    "occurrence, never silently dropped.\n"
    "\n"
    "Exit codes: 0 ok, 1 usage, 2 bad input file or data (or unwritable output),\n"
    "3 degenerate input (all points coplanar, collinear or fewer than 4 distinct),\n"
    "4 out of memory, 5 check failed (diff: the meshes differ).  A failed run leaves no\n"
    "partial output file.\n"
    "\n"
    "Generator kinds:\n";

static void print_help(FILE *f)
{
    fprintf(f, help_text, GTET_VERSION_MAJOR, GTET_VERSION_MINOR, GTET_VERSION_PATCH);
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
    case GTET_ERR_INTERNAL: return CLI_CHECK_FAILED;
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

int cli_opt_value(int argc, char **argv, int *i, const char *name, const char **val)
{
    const char *a = argv[*i];
    size_t l = strlen(name);
    if (strncmp(a, name, l) != 0) return 0;
    if (a[l] == '=' && name[1] == '-') {
        *val = a + l + 1;
        return 1;
    }
    if (a[l] != '\0') return 0;
    if (*i + 1 >= argc) return -1;
    *val = argv[++*i];
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

int main(int argc, char **argv)
{
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
    if (!strcmp(cmd, "triangulate")) return cli_triangulate(argc - 2, argv + 2);
    if (!strcmp(cmd, "check")) return cli_check(argc - 2, argv + 2);
    if (!strcmp(cmd, "diff")) return cli_diff(argc - 2, argv + 2);
    if (!strcmp(cmd, "generate")) return cli_generate(argc - 2, argv + 2);
    return cli_usage("unknown command '%s' (triangulate, check, diff, generate)", cmd);
}
