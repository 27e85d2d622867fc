/* cmd_triangulate.c -- `gigatet triangulate INPUT [-o OUTPUT] [-t THREADS] [--check]
 * [--stats] [--degeneracies FILE.json [--degeneracies-limit N]] [--map FILE]
 * [--memory-limit SIZE] [-q]`.
 *
 * Order of work, chosen so that a failure costs little and leaves nothing behind: parse and
 * validate every argument (usage errors before any file is touched), make sure the output can
 * be created (io_check_writable) and would not overwrite the input, read the points,
 * triangulate, optionally run the exact checker, and only then write the mesh atomically
 * (and the degeneracy record and the input map: their temporaries are complete before the
 * mesh is written and are renamed into place only after the mesh was).
 * The summary line goes to stdout, --stats adds one JSON object on one line after it; the
 * progress bar goes to stderr only when stderr is a terminal; -q silences all but errors.
 */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700 /* realpath */
#include "base/base.h"
#include "cli.h"
#include "io/io_internal.h"
#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct progress_state { int last; } progress_state;

static void progress_bar(void *user, double fraction)
{
    progress_state *p = user;
    int pct = fraction <= 0 ? 0 : fraction >= 1 ? 100 : (int)(fraction * 100.0);
    if (pct == p->last) return;
    p->last = pct;
    char bar[41];
    int fill = pct * 40 / 100;
    for (int i = 0; i < 40; i++) bar[i] = i < fill ? '#' : '.';
    bar[40] = '\0';
    fprintf(stderr, "\r[%s] %3d%%", bar, pct);
    fflush(stderr);
}

typedef struct tri_args {
    const char *input, *output, *degen, *memory, *map;
    uint64_t threads, degen_limit;
    size_t memory_limit;  /* gtet_options.memory_limit, from --memory-limit */
    unsigned check, stats, quiet;
} tri_args;

enum { GIVEN_LIMIT = 1u };

static const cli_opt tri_opts[] = {
    {.name = "-o", .alias = "--output", .kind = CLI_OPT_STRING, .off = offsetof(tri_args, output),
     .arg = "OUTPUT", .missing = "option {opt} needs a file name",
     .help = "write the mesh in a mesh format (below); without -o nothing is written"},
    {.name = "-t", .alias = "--threads", .kind = CLI_OPT_U64, .off = offsetof(tri_args, threads),
     .max = 1024, .arg = "THREADS", .missing = "option {opt} needs a thread count",
     .invalid = "invalid thread count '{value}' (expected 0..1024, 0 = all cores)",
     .help = "worker threads, 0 = all cores (default 0; at most 1024)"},
    {.name = "--check", .kind = CLI_OPT_FLAG, .off = offsetof(tri_args, check), .bits = 1,
     .help = "verify the result with the exact checker before writing it"},
    {.name = "--stats", .kind = CLI_OPT_FLAG, .off = offsetof(tri_args, stats), .bits = 1,
     .help = "print a JSON object of statistics after the summary line"},
    {.name = "--degeneracies", .kind = CLI_OPT_STRING, .off = offsetof(tri_args, degen),
     .arg = "FILE.json", .missing = "option {opt} needs a file name",
     .help = "write every decision of the symbolic perturbation (five co-spherical\n"
             "points; a point on a hull facet's circle: mesh vertex ids, coordinates,\n"
             "the term that decided, the sign) and the predicate counters as JSON"},
    {.name = "--degeneracies-limit", .kind = CLI_OPT_U64, .off = offsetof(tri_args, degen_limit),
     .max = SIZE_MAX, .mark = GIVEN_LIMIT, .arg = "N", .missing = "option {opt} needs a count",
     .invalid = "invalid degeneracy limit '{value}' (expected a count >= 0)",
     .help = "with --degeneracies: store at most N decisions (default 100000; the\n"
             "counts stay exact)"},
    {.name = "--map", .kind = CLI_OPT_STRING, .off = offsetof(tri_args, map),
     .arg = "FILE", .missing = "option {opt} needs a file name",
     .help = "write where each input point went: after two '#' lines, line k (from 0)\n"
             "is input point k's vertex, its 0-based position in the mesh's vertex list\n"
             "(a duplicate: its first occurrence's vertex)"},
    {.name = "--memory-limit", .kind = CLI_OPT_STRING, .off = offsetof(tri_args, memory),
     .arg = "SIZE", .missing = "option {opt} needs a size (e.g. 16G, 512M, auto, off)",
     .help = "the memory the run may use: before the work it estimates its peak and\n"
             "fails at once (exit 4, nothing written) when it cannot fit; SIZE is bytes\n"
             "or a number with K, M, G, T (powers of 1024), 'auto' (default: what the\n"
             "machine can give: MemAvailable, the cgroup's limit, ulimit -v) or 'off'"},
    CLI_OPT_QUIET(tri_args),
    {0}};

static const cli_positional tri_pos[] = {{"INPUT", offsetof(tri_args, input)}, {0}};

static int cli_triangulate(int argc, char **argv);

const cli_command cli_cmd_triangulate = {
    .name = "triangulate",
    .summary = "Delaunay tetrahedrization of the points of INPUT.  Prints one summary line\n"
               "(points, duplicates, tets, seconds, tets/s) on stdout.",
    .opts = tri_opts,
    .pos = tri_pos,
    .missing = "triangulate: no input file",
    .extra = "triangulate: more than one input file ('{first}', '{arg}')",
    .run = cli_triangulate,
};

typedef struct tri_times { double start, read, kernel, check, write; } tri_times;

/* --map: where each input point went (gtet_mesh_input_map), one line a point, after two
 * comment lines that numpy.loadtxt and most readers skip.  The ids are positions in the
 * vertex list of the mesh -o writes (the written files number their nodes from their own
 * first index: 1 in .node and .msh, 0 in .vtu). */
static void write_input_map(FILE *f, const gtet_mesh *mesh)
{
    const size_t n = gtet_mesh_num_points(mesh), nv = gtet_mesh_num_vertices(mesh);
    const uint32_t *map = gtet_mesh_input_map(mesh);
    fprintf(f, "# gigatet input map: %zu points, %zu vertices, %zu duplicates\n", n, nv,
            gtet_mesh_num_duplicates(mesh));
    fputs("# line k below, counting from 0: input point k's vertex, 0-based in the mesh's list\n",
          f);
    char buf[1 << 16], *p = buf;
    for (size_t i = 0; i < n; i++) {
        if (p > buf + sizeof buf - 24) {
            fwrite(buf, 1, (size_t)(p - buf), f);
            p = buf;
        }
        p = io_fmt_u64(p, map[i]);
        *p++ = '\n';
    }
    fwrite(buf, 1, (size_t)(p - buf), f);
}

/* The predicate counters, then the recorded decisions of the symbolic perturbation
 * (gtet_mesh_degeneracies): mesh vertex ids with their coordinates in %.17g (they read back
 * exactly). */
static void write_degeneracies(FILE *f, const char *input, const gtet_mesh *mesh, size_t limit)
{
    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    size_t stored;
    uint64_t total;
    const gtet_degeneracy *d = gtet_mesh_degeneracies(mesh, &stored, &total);
    const double *v = gtet_mesh_vertices(mesh);
    fputs("{\"input\":", f);
    cli_json_str(f, input);
    fprintf(f, ",\"points\":%zu,\"vertices\":%zu,\"threads\":%d,\"predicates\":",
            gtet_mesh_num_points(mesh), gtet_mesh_num_vertices(mesh), st.threads);
    cli_json_pred_counters(f, &st.pred);
    fprintf(f, ",\"limit\":%zu,\"total\":%llu,\"stored\":%zu,\"omitted\":%llu,"
            "\"truncated\":%s,\"decisions\":[",
            limit, (unsigned long long)total, stored, (unsigned long long)(total - stored),
            total > stored ? "true" : "false");
    for (size_t i = 0; i < stored; i++) {
        const gtet_degeneracy *r = &d[i];
        fprintf(f, "%s\n{\"kind\":\"%s\",\"vertices\":[", i ? "," : "",
                r->kind == GTET_DEGENERACY_COSPHERICAL ? "cospherical" : "coplanar");
        for (int k = 0; k < r->npoints; k++) fprintf(f, "%s%u", k ? "," : "", r->vertex[k]);
        fputs("],\"coords\":[", f);
        for (int k = 0; k < r->npoints; k++) {
            if (k) fputc(',', f);
            cli_json_point(f, v + 3 * (size_t)r->vertex[k]);
        }
        fprintf(f, "],\"term\":%d,\"sign\":%d}", r->term, r->sign);
    }
    fputs(stored ? "\n]}\n" : "]}\n", f);
}

static void print_rounds(const gtet_stats *st)
{
    printf(",\"num_rounds\":%d,\"rounds\":[", st->num_rounds);
    for (int r = 0; r < st->num_rounds && st->rounds; r++) {
        const gtet_round_stats *rs = &st->rounds[r];
        printf("%s{\"points\":%llu,\"tried\":%llu,\"inserted\":%llu,\"deferred\":%llu,"
               "\"threads\":%d,\"passes\":%d,\"alpha\":%.4f,\"alpha_first_pass\":%.4f,"
               "\"ownership\":%d,\"rebalanced\":%llu}",
               r ? "," : "", (unsigned long long)rs->points, (unsigned long long)rs->tried,
               (unsigned long long)rs->inserted, (unsigned long long)rs->deferred, rs->threads,
               rs->passes, rs->tried ? (double)rs->inserted / (double)rs->tried : 1.0,
               rs->alpha_first, rs->ownership, (unsigned long long)rs->rebalanced);
    }
    printf("]");
}

/* The memory guard's estimate for this run (gtet_estimate_memory, with the checker when
 * --check ran) plus, with --check, the input array this process holds through the run (24
 * bytes a point; without it the array is freed before the peak): comparable with the
 * measured peak RSS. */
static size_t estimated_peak(const tri_args *a, const gtet_mesh *mesh, int threads)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = threads;
    o.check = (int)a->check;
    o.degeneracies = a->degen != NULL;
    o.degeneracy_limit = (size_t)a->degen_limit;
    const size_t n = gtet_mesh_num_points(mesh);
    return gtet_estimate_memory(n, &o) + (a->check ? 3 * sizeof(double) * n : 0);
}

/* The --stats object, one line. */
static void print_stats(const tri_args *a, const gtet_mesh *mesh, const tri_times *t)
{
    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    size_t nt = gtet_mesh_num_tets(mesh);
    printf("{\"input\":");
    cli_json_str(stdout, a->input);
    printf(",\"points\":%zu,\"vertices\":%zu,\"duplicates\":%zu,\"tets\":%zu,\"hull_facets\":%zu",
           gtet_mesh_num_points(mesh), gtet_mesh_num_vertices(mesh),
           gtet_mesh_num_duplicates(mesh), nt, gtet_mesh_num_hull_facets(mesh));
    printf(",\"threads\":%d,\"tets_per_second\":%.6g", st.threads,
           t->kernel > 0 ? (double)nt / t->kernel : 0.0);
    printf(",\"seconds\":{\"read\":%.6f,\"validate\":%.6f,\"sort\":%.6f,\"insert\":%.6f,"
           "\"finalize\":%.6f,\"kernel\":%.6f,\"kernel_reported\":%.6f,\"check\":%.6f,"
           "\"write\":%.6f,\"wall\":%.6f}",
           t->read, st.seconds_validate, st.seconds_sort, st.seconds_insert, st.seconds_finalize,
           t->kernel, st.seconds_total, t->check, t->write, cli_now() - t->start);
    printf(",\"bytes_per_tet\":%zu,\"kernel_peak_bytes\":%zu,\"max_rss_bytes\":%ld,"
           "\"estimated_peak_bytes\":%zu",
           st.bytes_per_tet, st.peak_bytes, cli_max_rss_bytes(),
           estimated_peak(a, mesh, st.threads));
    /* the pages the big arrays asked for (GTET_HUGEPAGES, base_page_mode) and the 4 KiB fault
     * cost that decided it (null when not measured): a run's time depends on them */
    const double us = base_small_fault_us();
    printf(",\"pages\":\"%s\",\"small_fault_us\":",
           base_page_mode() == BASE_PAGES_SMALL ? "4k" : "huge");
    if (us >= 0) printf("%.3f", us);
    else printf("null");
    printf(",\"tets_created\":%llu,\"walk_steps\":%llu", (unsigned long long)st.tets_created,
           (unsigned long long)st.walk_steps);
    printf(",\"predicates\":");
    cli_json_pred_counters(stdout, &st.pred);
    print_rounds(&st);
    printf("}\n");
}

/* 1 when writing `out` (or the .node beside a .ele) would replace the input file. */
int cli_overwrites_input(const char *input, const char *out)
{
    struct stat si, so;
    if (stat(input, &si) != 0) return 0;
    char *node = io_ele_node_path(out);
    int same = 0;
    if (stat(out, &so) == 0 && so.st_dev == si.st_dev && so.st_ino == si.st_ino) same = 1;
    if (node && stat(node, &so) == 0 && so.st_dev == si.st_dev && so.st_ino == si.st_ino) same = 1;
    free(node);
    return same;
}

/* The directory entry `path` names: its directory resolved (realpath) and its last component,
 * so that two spellings of one entry ("m.vtu", "./m.vtu", "sub/../m.vtu") give one string;
 * NULL when the directory cannot be resolved.  Not the file a symbolic link points to: the
 * atomic rename of io_out replaces the link itself. */
static char *resolved_entry(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
    char *rd = dir ? realpath(dir, NULL) : NULL;
    free(dir);
    if (!rd) return NULL;
    const char *base = slash ? slash + 1 : path;
    size_t n = strlen(rd) + strlen(base) + 2;
    char *r = malloc(n);
    if (r) snprintf(r, n, "%s/%s", rd, base);
    free(rd);
    return r;
}

/* 1 when the two output paths name the same directory entry (NOTES.md E150). */
static int same_entry(const char *a, const char *b)
{
    if (!strcmp(a, b)) return 1;
    char *ra = resolved_entry(a), *rb = resolved_entry(b);
    int same = ra && rb && !strcmp(ra, rb);
    free(ra);
    free(rb);
    return same;
}

/* --memory-limit's value: "auto" (0), "off" (SIZE_MAX), or a positive number of bytes with
 * an optional binary suffix K, M, G, T (and an optional "B" or "iB" after it).  0 on junk. */
static int parse_memory_limit(const char *s, size_t *out)
{
    if (!strcmp(s, "auto")) return *out = 0, 1;
    if (!strcmp(s, "off")) return *out = SIZE_MAX, 1;
    static const char units[] = "KMGT";
    size_t len = 0;
    while (s[len] >= '0' && s[len] <= '9') len++;
    char digits[24];
    uint64_t v, mult = 1;
    if (len == 0 || len >= sizeof digits) return 0;
    memcpy(digits, s, len);
    digits[len] = '\0';
    if (!cli_parse_u64(digits, UINT64_MAX, &v)) return 0;
    const char *u = s + len;
    const char *at = *u ? strchr(units, *u & ~0x20) : NULL;
    if (*u && !at) return 0;
    if (at) {
        for (const char *k = units; k <= at; k++) mult *= 1024;
        u++;
        if (*u == 'i' && u[1] == 'B') u += 2;
        else if (*u == 'B') u++;
    }
    if (*u || v == 0 || v > SIZE_MAX / mult || v * mult == SIZE_MAX) return 0;
    *out = (size_t)(v * mult);
    return 1;
}

/* Is path one of the files -o output writes (output itself, or the .node beside an .ele)? */
static int is_mesh_file(const char *path, const char *output)
{
    char *node = io_ele_node_path(output);
    const int same = same_entry(path, output) || (node && same_entry(path, node));
    free(node);
    return same;
}

/* Usage errors of the output paths and options, before any file is touched. */
static int tri_validate(tri_args *a, unsigned given)
{
    char list[128];
    if (a->memory && !parse_memory_limit(a->memory, &a->memory_limit))
        return cli_usage("invalid memory limit '%s' (expected a size such as 16G or 512M, "
                         "'auto' or 'off')", a->memory);
    if (a->output && !io_format_can(io_format_of(a->output), IO_WRITE_MESH))
        return cli_usage("%s: unknown output extension (use %s)", a->output,
                         io_format_list(IO_WRITE_MESH, 0, list, sizeof list));
    if (a->output && cli_overwrites_input(a->input, a->output))
        return cli_usage("%s: writing the mesh would overwrite the input file %s", a->output,
                         a->input);
    if ((given & GIVEN_LIMIT) && !a->degen)
        return cli_usage("--degeneracies-limit needs --degeneracies FILE");
    if (a->degen && cli_overwrites_input(a->input, a->degen))
        return cli_usage("%s: writing the degeneracies would overwrite the input file %s",
                         a->degen, a->input);
    if (a->degen && a->output && is_mesh_file(a->degen, a->output))
        return cli_usage("%s: both the mesh and the degeneracies would go there", a->degen);
    if (a->map && cli_overwrites_input(a->input, a->map))
        return cli_usage("%s: writing the input map would overwrite the input file %s", a->map,
                         a->input);
    if (a->map && a->degen && same_entry(a->map, a->degen))
        return cli_usage("%s: both the input map and the degeneracies would go there", a->map);
    if (a->map && a->output && is_mesh_file(a->map, a->output))
        return cli_usage("%s: both the mesh and the input map would go there", a->map);
    return CLI_OK;
}

/* Every output can be created: fail before the work, not after it. */
static int tri_writable(const tri_args *a)
{
    const char *paths[4] = {a->output, NULL, a->degen, a->map};
    char *node = a->output ? io_ele_node_path(a->output) : NULL;
    paths[1] = node;
    io_error ioe;
    io_status is = IO_OK;
    for (int i = 0; i < 4 && is == IO_OK; i++)
        if (paths[i]) is = io_check_writable(paths[i], &ioe);
    free(node);
    return is == IO_OK ? CLI_OK : cli_io_failed(is, &ioe);
}

/* gtet_options.input_done: the points read are freed once the library has its own copy (24
 * bytes a point at the insertion's peak); *user is the CLI's pointer to them. */
static void free_input(void *user)
{
    double **xyz = user;
    free(*xyz);
    *xyz = NULL;
}

/* gtet_triangulate with the options of a (and the progress bar on a terminal).  Without
 * --check, which compares the mesh with the points read, *xyz is freed (set to NULL) during
 * the run. */
static int tri_kernel(const tri_args *a, double **xyz, size_t n, gtet_mesh **mesh)
{
    gtet_options opts;
    gtet_error gerr;
    progress_state ps = {-1};
    memset(&gerr, 0, sizeof gerr);
    gtet_options_init(&opts);
    opts.threads = (int)a->threads;
    opts.error = &gerr;
    opts.degeneracies = a->degen != NULL;
    opts.degeneracy_limit = (size_t)a->degen_limit;
    opts.memory_limit = a->memory_limit;
    if (!a->check) {
        opts.input_done = free_input;
        opts.input_done_user = xyz;
    }
    int bar = !a->quiet && isatty(STDERR_FILENO);
    if (bar) {
        opts.progress = progress_bar;
        opts.progress_user = &ps;
    }
    /* --check runs after the kernel (tri_outputs), and its peak can be the run's: the guard
     * is asked with it before the work */
    gtet_options with_check = opts;
    with_check.check = (int)a->check;
    gtet_status gs = gtet_memory_guard(n, &with_check);
    if (gs == GTET_OK) gs = gtet_triangulate(*xyz, n, &opts, mesh);
    if (bar && ps.last >= 0) fputs("\r\033[K", stderr);
    if (gs == GTET_OK) {
        /* the library runs on the threads the system lets it start and OpenMP gives
         * (NOTES.md E183, E184): say so when that is fewer than -t asked for */
        gtet_stats st;
        gtet_mesh_stats(*mesh, &st);
        const int asked = a->threads > BASE_MAX_THREADS ? BASE_MAX_THREADS : (int)a->threads;
        if (!a->quiet && asked > 1 && st.threads < asked)
            cli_error("warning: ran on %d of the %d threads asked for (no more could be "
                      "started or OpenMP would give no more: ulimit -u, memory for their "
                      "stacks, OMP_THREAD_LIMIT, a call inside a parallel region); the mesh is "
                      "the same", st.threads, asked);
        return CLI_OK;
    }
    const char *msg = gerr.message[0] ? gerr.message : gtet_status_str(gs);
    if (gs == GTET_ERR_NONFINITE && gerr.index != SIZE_MAX)
        cli_error("%s: point %zu: %s", a->input, gerr.index, msg);
    else
        cli_error("%s: %s", a->input, msg);
    return cli_exit_of_gtet(gs);
}

/* --check, then the outputs: the degeneracy record complete in its temporary, the mesh
 * written atomically, and only then the record renamed into place.  xyz: the points read
 * (NULL without --check: freed during the run). */
static int tri_outputs(const tri_args *a, const double *xyz, size_t n, const gtet_mesh *mesh,
                       tri_times *t)
{
    io_error ioe;
    io_status is = IO_OK;
    io_out dout = {NULL, NULL, NULL}, mout = {NULL, NULL, NULL};
    if (a->check) {
        gtet_check_report rep;
        memset(&rep, 0, sizeof rep);
        double c0 = cli_now();
        gtet_status gs = gtet_check(mesh, xyz, n, 0, &rep);
        t->check = cli_now() - c0;
        if (gs != GTET_OK) {
            cli_error("%s: check failed: %s", a->input, rep.message[0] ? rep.message : gtet_status_str(gs));
            return gs == GTET_ERR_CHECK_FAILED ? CLI_CHECK_FAILED : cli_exit_of_gtet(gs);
        }
    }
    if (a->degen && (is = io_out_open(&dout, a->degen, &ioe)) == IO_OK) {
        write_degeneracies(dout.f, a->input, mesh, (size_t)a->degen_limit);
        is = io_out_close(&dout, &ioe);
    }
    if (is == IO_OK && a->map && (is = io_out_open(&mout, a->map, &ioe)) == IO_OK) {
        write_input_map(mout.f, mesh);
        is = io_out_close(&mout, &ioe);
    }
    if (is == IO_OK && a->output) {
        double w0 = cli_now();
        is = io_write_mesh(a->output, gtet_mesh_vertices(mesh), gtet_mesh_num_vertices(mesh),
                           gtet_mesh_tets(mesh), gtet_mesh_num_tets(mesh), &ioe);
        t->write = cli_now() - w0;
    }
    if (is == IO_OK && a->degen) is = io_out_commit(&dout, &ioe);
    if (is == IO_OK && a->map) is = io_out_commit(&mout, &ioe);
    if (dout.tmp) io_out_abort(&dout);
    if (mout.tmp) io_out_abort(&mout);
    return is == IO_OK ? CLI_OK : cli_io_failed(is, &ioe);
}

static int cli_triangulate(int argc, char **argv)
{
    tri_args a = {.degen_limit = 100000};
    unsigned given;
    int rc;
    if ((rc = cli_parse(&cli_cmd_triangulate, argc, argv, &a, &given)) != CLI_OK ||
        (rc = tri_validate(&a, given)) != CLI_OK || (rc = tri_writable(&a)) != CLI_OK)
        return rc;
    tri_times t = {.start = cli_now()};
    double *xyz;
    size_t n;
    io_error ioe;
    io_status is = io_read_points(a.input, &xyz, &n, &ioe);
    if (is != IO_OK) return cli_io_failed(is, &ioe);
    double t1 = cli_now();
    t.read = t1 - t.start;
    gtet_mesh *mesh = NULL;
    rc = tri_kernel(&a, &xyz, n, &mesh);  /* frees xyz unless --check needs it */
    t.kernel = cli_now() - t1;
    if (rc == CLI_OK) rc = tri_outputs(&a, xyz, n, mesh, &t);
    if (rc == CLI_OK && !a.quiet) {
        size_t nt = gtet_mesh_num_tets(mesh);
        printf("points=%zu duplicates=%zu tets=%zu seconds=%.3f tets/s=%.0f%s\n", n,
               gtet_mesh_num_duplicates(mesh), nt, t.kernel,
               t.kernel > 0 ? (double)nt / t.kernel : 0.0, a.check ? " check=ok" : "");
        if (a.stats) print_stats(&a, mesh, &t);
        fflush(stdout);
    }
    gtet_mesh_free(&mesh);
    free(xyz);
    return rc;
}
