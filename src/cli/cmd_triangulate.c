/* cmd_triangulate.c -- `gigatet triangulate INPUT [-o OUTPUT] [-t THREADS] [--check]
 * [--stats] [--degeneracies FILE.json [--degeneracies-limit N]] [-q]`.
 *
 * Order of work, chosen so that a failure costs little and leaves nothing behind: parse and
 * validate every argument (usage errors before any file is touched), make sure the output can
 * be created (io_check_writable) and would not overwrite the input, read the points,
 * triangulate, optionally run the exact checker, and only then write the mesh atomically
 * (and the degeneracy record: its temporary is complete before the mesh is written and is
 * renamed into place only after the mesh was).
 * The summary line goes to stdout, --stats adds one JSON object on one line after it; the
 * progress bar goes to stderr only when stderr is a terminal; -q silences all but errors.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "io/io_internal.h"

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

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c < 0x20) fprintf(f, "\\u%04x", c);
        else fputc(c, f);
    }
    fputc('"', f);
}

/* The predicate counters as the JSON object --stats and --degeneracies both print. */
static void json_pred_counters(FILE *f, const gtet_pred_counters *p)
{
    fprintf(f, "{\"orient_calls\":%llu,\"orient_exact\":%llu,\"orient_int\":%llu,"
            "\"orient_gmp\":%llu,\"orient_zero\":%llu,\"insphere_calls\":%llu,"
            "\"insphere_exact\":%llu,\"insphere_int\":%llu,\"insphere_gmp\":%llu,"
            "\"insphere_zero\":%llu,\"sos_calls\":%llu,"
            "\"sos_depth\":[%llu,%llu,%llu,%llu]}",
            (unsigned long long)p->orient_calls, (unsigned long long)p->orient_exact,
            (unsigned long long)p->orient_int, (unsigned long long)p->orient_gmp,
            (unsigned long long)p->orient_zero, (unsigned long long)p->insphere_calls,
            (unsigned long long)p->insphere_exact, (unsigned long long)p->insphere_int,
            (unsigned long long)p->insphere_gmp, (unsigned long long)p->insphere_zero,
            (unsigned long long)p->sos_calls, (unsigned long long)p->sos_depth[0],
            (unsigned long long)p->sos_depth[1], (unsigned long long)p->sos_depth[2],
            (unsigned long long)p->sos_depth[3]);
}

static void print_stats(const char *input, const gtet_mesh *mesh, double t_read, double t_kernel,
                        double t_check, double t_write, double t_wall)
{
    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    size_t nt = gtet_mesh_num_tets(mesh);
    printf("{\"input\":");
    json_string(stdout, input);
    printf(",\"points\":%zu,\"vertices\":%zu,\"duplicates\":%zu,\"tets\":%zu,\"hull_facets\":%zu",
           gtet_mesh_num_points(mesh), gtet_mesh_num_vertices(mesh),
           gtet_mesh_num_duplicates(mesh), nt, gtet_mesh_num_hull_facets(mesh));
    printf(",\"threads\":%d,\"tets_per_second\":%.6g", st.threads,
           t_kernel > 0 ? (double)nt / t_kernel : 0.0);
    printf(",\"seconds\":{\"read\":%.6f,\"validate\":%.6f,\"sort\":%.6f,\"insert\":%.6f,"
           "\"finalize\":%.6f,\"kernel\":%.6f,\"kernel_reported\":%.6f,\"check\":%.6f,"
           "\"write\":%.6f,\"wall\":%.6f}",
           t_read, st.seconds_validate, st.seconds_sort, st.seconds_insert, st.seconds_finalize,
           t_kernel, st.seconds_total, t_check, t_write, t_wall);
    printf(",\"bytes_per_tet\":%zu,\"kernel_peak_bytes\":%zu,\"max_rss_bytes\":%ld",
           st.bytes_per_tet, st.peak_bytes, cli_max_rss_bytes());
    printf(",\"tets_created\":%llu,\"walk_steps\":%llu", (unsigned long long)st.tets_created,
           (unsigned long long)st.walk_steps);
    printf(",\"predicates\":");
    json_pred_counters(stdout, &st.pred);
    printf(",\"num_rounds\":%d,\"rounds\":[", st.num_rounds);
    for (int r = 0; r < st.num_rounds && st.rounds; r++) {
        const gtet_round_stats *rs = &st.rounds[r];
        printf("%s{\"points\":%llu,\"tried\":%llu,\"inserted\":%llu,\"deferred\":%llu,"
               "\"threads\":%d,\"passes\":%d,\"alpha\":%.4f,\"alpha_first_pass\":%.4f,"
               "\"ownership\":%d}",
               r ? "," : "", (unsigned long long)rs->points, (unsigned long long)rs->tried,
               (unsigned long long)rs->inserted, (unsigned long long)rs->deferred, rs->threads,
               rs->passes, rs->tried ? (double)rs->inserted / (double)rs->tried : 1.0,
               rs->alpha_first, rs->ownership);
    }
    printf("]}\n");
}

/* The --degeneracies file: the run's counters and the recorded decisions of the symbolic
 * perturbation (gtet_mesh_degeneracies), vertex ids of the mesh with their coordinates in
 * %.17g (they read back exactly). */
static void write_degeneracies(FILE *f, const char *input, const gtet_mesh *mesh, size_t limit)
{
    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    size_t stored;
    uint64_t total;
    const gtet_degeneracy *d = gtet_mesh_degeneracies(mesh, &stored, &total);
    const double *v = gtet_mesh_vertices(mesh);
    fputs("{\"input\":", f);
    json_string(f, input);
    fprintf(f, ",\"points\":%zu,\"vertices\":%zu,\"threads\":%d,\"predicates\":",
            gtet_mesh_num_points(mesh), gtet_mesh_num_vertices(mesh), st.threads);
    json_pred_counters(f, &st.pred);
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
            const double *p = v + 3 * (size_t)r->vertex[k];
            fprintf(f, "%s[%.17g,%.17g,%.17g]", k ? "," : "", p[0], p[1], p[2]);
        }
        fprintf(f, "],\"term\":%d,\"sign\":%d}", r->term, r->sign);
    }
    fputs(stored ? "\n]}\n" : "]}\n", f);
}

/* 1 when writing `out` (or the .node beside a .ele) would replace the input file. */
static int overwrites_input(const char *input, const char *out)
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

int cli_triangulate(int argc, char **argv)
{
    const char *input = NULL, *output = NULL, *degen = NULL, *val;
    uint64_t threads = 0, degen_limit = 100000;
    int check = 0, stats = 0, quiet = 0, have_limit = 0, r;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if ((r = cli_opt_value(argc, argv, &i, "-o", &val)) ||
            (r = cli_opt_value(argc, argv, &i, "--output", &val))) {
            if (r < 0) return cli_usage("option %s needs a file name", a);
            output = val;
        } else if ((r = cli_opt_value(argc, argv, &i, "-t", &val)) ||
                   (r = cli_opt_value(argc, argv, &i, "--threads", &val))) {
            if (r < 0) return cli_usage("option %s needs a thread count", a);
            if (!cli_parse_u64(val, 1024, &threads))
                return cli_usage("invalid thread count '%s' (expected 0..1024, 0 = all cores)", val);
        } else if ((r = cli_opt_value(argc, argv, &i, "--degeneracies", &val))) {
            if (r < 0) return cli_usage("option %s needs a file name", a);
            degen = val;
        } else if ((r = cli_opt_value(argc, argv, &i, "--degeneracies-limit", &val))) {
            if (r < 0) return cli_usage("option %s needs a count", a);
            if (!cli_parse_u64(val, (uint64_t)SIZE_MAX, &degen_limit))
                return cli_usage("invalid degeneracy limit '%s' (expected a count >= 0)", val);
            have_limit = 1;
        } else if (!strcmp(a, "--check")) {
            check = 1;
        } else if (!strcmp(a, "--stats")) {
            stats = 1;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return cli_usage("triangulate: unknown option '%s'", a);
        } else if (!input) {
            input = a;
        } else {
            return cli_usage("triangulate: more than one input file ('%s', '%s')", input, a);
        }
    }
    if (!input) return cli_usage("triangulate: no input file");
    io_format of = io_format_of(output);
    if (output && of != IO_FMT_ELE && of != IO_FMT_MSH && of != IO_FMT_VTU)
        return cli_usage("%s: unknown output extension (use .ele, .msh or .vtu)", output);
    if (output && overwrites_input(input, output))
        return cli_usage("%s: writing the mesh would overwrite the input file %s", output, input);
    if (have_limit && !degen) return cli_usage("--degeneracies-limit needs --degeneracies FILE");
    if (degen && overwrites_input(input, degen))
        return cli_usage("%s: writing the degeneracies would overwrite the input file %s", degen,
                         input);
    if (degen && output) {
        char *node = io_ele_node_path(output);
        int same = !strcmp(degen, output) || (node && !strcmp(degen, node));
        free(node);
        if (same) return cli_usage("%s: both the mesh and the degeneracies would go there", degen);
    }

    io_error ioe;
    io_status is;
    if (output) {
        /* fail before the work, not after it */
        if ((is = io_check_writable(output, &ioe)) != IO_OK) {
            cli_error("%s", ioe.message);
            return cli_exit_of_io(is);
        }
        char *node = io_ele_node_path(output);
        if (node && (is = io_check_writable(node, &ioe)) != IO_OK) {
            cli_error("%s", ioe.message);
            free(node);
            return cli_exit_of_io(is);
        }
        free(node);
    }
    if (degen && (is = io_check_writable(degen, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        return cli_exit_of_io(is);
    }

    double t0 = cli_now();
    double *xyz;
    size_t n;
    if ((is = io_read_points(input, &xyz, &n, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        return cli_exit_of_io(is);
    }
    double t1 = cli_now();

    gtet_options opts;
    gtet_error gerr;
    progress_state ps = {-1};
    memset(&gerr, 0, sizeof gerr);
    gtet_options_init(&opts);
    opts.threads = (int)threads;
    opts.error = &gerr;
    opts.degeneracies = degen != NULL;
    opts.degeneracy_limit = (size_t)degen_limit;
    int bar = !quiet && isatty(STDERR_FILENO);
    if (bar) {
        opts.progress = progress_bar;
        opts.progress_user = &ps;
    }
    gtet_mesh *mesh = NULL;
    gtet_status gs = gtet_triangulate(xyz, n, &opts, &mesh);
    double t2 = cli_now();
    if (bar && ps.last >= 0) fputs("\r\033[K", stderr);
    if (gs != GTET_OK) {
        const char *msg = gerr.message[0] ? gerr.message : gtet_status_str(gs);
        if (gs == GTET_ERR_NONFINITE && gerr.index != SIZE_MAX)
            cli_error("%s: point %zu: %s", input, gerr.index, msg);
        else
            cli_error("%s: %s", input, msg);
        free(xyz);
        return cli_exit_of_gtet(gs);
    }
    int rc = CLI_OK;
    double t_check = 0, t_write = 0;
    io_out dout = {NULL, NULL, NULL};
    if (check) {
        gtet_check_report rep;
        memset(&rep, 0, sizeof rep);
        double c0 = cli_now();
        gs = gtet_check(mesh, xyz, n, 0, &rep);
        t_check = cli_now() - c0;
        if (gs != GTET_OK) {
            cli_error("%s: check failed: %s", input, rep.message[0] ? rep.message : gtet_status_str(gs));
            rc = gs == GTET_ERR_CHECK_FAILED ? CLI_CHECK_FAILED : cli_exit_of_gtet(gs);
            goto out;
        }
    }
    if (degen) {  /* complete in its temporary before the mesh is written */
        if ((is = io_out_open(&dout, degen, &ioe)) == IO_OK) {
            write_degeneracies(dout.f, input, mesh, (size_t)degen_limit);
            is = io_out_close(&dout, &ioe);
        }
        if (is != IO_OK) {
            cli_error("%s", ioe.message);
            rc = cli_exit_of_io(is);
            goto out;
        }
    }
    if (output) {
        double w0 = cli_now();
        is = io_write_mesh(output, gtet_mesh_vertices(mesh), gtet_mesh_num_vertices(mesh),
                           gtet_mesh_tets(mesh), gtet_mesh_num_tets(mesh), &ioe);
        t_write = cli_now() - w0;
        if (is != IO_OK) {
            cli_error("%s", ioe.message);
            rc = cli_exit_of_io(is);
            goto out;
        }
    }
    if (degen && (is = io_out_commit(&dout, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        rc = cli_exit_of_io(is);
        goto out;
    }
    if (!quiet) {
        double k = t2 - t1;
        size_t nt = gtet_mesh_num_tets(mesh);
        printf("points=%zu duplicates=%zu tets=%zu seconds=%.3f tets/s=%.0f%s\n", n,
               gtet_mesh_num_duplicates(mesh), nt, k, k > 0 ? (double)nt / k : 0.0,
               check ? " check=ok" : "");
        if (stats) print_stats(input, mesh, t1 - t0, k, t_check, t_write, cli_now() - t0);
        fflush(stdout);
    }
out:
    if (dout.tmp) io_out_abort(&dout);
    gtet_mesh_free(&mesh);
    free(xyz);
    return rc;
}
