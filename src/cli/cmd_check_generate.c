/* cmd_check_generate.c -- `gigatet check MESH [--points INPUT] [--delaunay] [--any-orientation]
 * [--full] [--json] [-q]` and
 * `gigatet generate KIND N [--seed S] -o FILE [-q]`.
 *
 * check reads the mesh back (io_read_mesh: .ele with its .node, .msh, .vtu; every vertex id is
 * range-checked there) and hands the plain arrays to the exact checker gtet_check_arrays,
 * which rebuilds the adjacency itself.  Exit 5 when an invariant fails, 2 when a file is bad.
 * generate writes the points of io_generate atomically.
 */
#include "cli.h"
#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct check_args {
    const char *mesh, *points;
    unsigned flags;
    int quiet, json;
} check_args;

static int check_parse(int argc, char **argv, check_args *a)
{
    const char *val;
    int r;
    memset(a, 0, sizeof *a);
    for (int i = 0; i < argc; i++) {
        const char *s = argv[i];
        if ((r = cli_opt_value(argc, argv, &i, "--points", &val))) {
            if (r < 0) return cli_usage("option --points needs a file name");
            a->points = val;
        } else if (!strcmp(s, "--full")) {
            a->flags |= GTET_CHECK_FULL;
        } else if (!strcmp(s, "--delaunay")) {
            a->flags |= GTET_CHECK_DELAUNAY;
        } else if (!strcmp(s, "--any-orientation")) {
            a->flags |= GTET_CHECK_ANY_ORIENTATION;
        } else if (!strcmp(s, "--json")) {
            a->json = 1;
        } else if (!strcmp(s, "-q") || !strcmp(s, "--quiet")) {
            a->quiet = 1;
        } else if (s[0] == '-' && s[1] != '\0') {
            return cli_usage("check: unknown option '%s'", s);
        } else if (!a->mesh) {
            a->mesh = s;
        } else {
            return cli_usage("check: more than one mesh file ('%s', '%s')", a->mesh, s);
        }
    }
    if (!a->mesh) return cli_usage("check: no mesh file");
    io_format mf = io_format_of(a->mesh);
    if (mf != IO_FMT_ELE && mf != IO_FMT_MSH && mf != IO_FMT_VTU)
        return cli_usage("%s: check reads .ele (with its .node), .msh or .vtu meshes", a->mesh);
    return CLI_OK;
}

/* The JSON report of `check --json` (one object on stdout, also for an unreadable file). */
static void check_json(const check_args *a, const char *status, const io_mesh *m,
                       const gtet_check_report *r, int failed, const char *message, double t)
{
    fputs("{\"file\":", stdout);
    cli_json_str(stdout, a->mesh);
    fputs(",\"points_file\":", stdout);
    cli_json_str(stdout, a->points);
    fprintf(stdout, ",\"status\":\"%s\",\"any_orientation\":%s,\"full\":%s,", status,
            (a->flags & GTET_CHECK_ANY_ORIENTATION) ? "true" : "false",
            (a->flags & GTET_CHECK_FULL) ? "true" : "false");
    if (r) {
        fprintf(stdout, "\"vertices\":%zu,\"skipped_cells\":%zu,", m->nv, m->skipped_cells);
        cli_json_check_members(stdout, r, failed);
        fprintf(stdout, ",\"seconds\":%.3f}\n", t);
    } else {
        fprintf(stdout, "\"ok\":false,\"mode\":\"%s\",\"message\":",
                (a->flags & GTET_CHECK_DELAUNAY) ? "delaunay" : "canonical");
        cli_json_str(stdout, message);
        fputs(",\"violation\":null}\n", stdout);
    }
}

int cli_check(int argc, char **argv)
{
    check_args a;
    int rc = check_parse(argc, argv, &a);
    if (rc != CLI_OK) return rc;
    io_error ioe;
    io_status is;
    io_mesh m;
    double *xyz = NULL;
    size_t n = 0;
    if ((is = io_read_mesh(a.mesh, &m, &ioe)) != IO_OK ||
        (a.points && (is = io_read_points(a.points, &xyz, &n, &ioe)) != IO_OK)) {
        cli_error("%s", ioe.message);
        if (a.json) check_json(&a, "unreadable", NULL, NULL, 1, ioe.message, 0);
        io_mesh_free(&m);
        return cli_exit_of_io(is);
    }
    const char *mode = (a.flags & GTET_CHECK_DELAUNAY) ? "delaunay" : "canonical";
    gtet_check_report rep;
    double t0 = cli_now();
    gtet_status gs = gtet_check_arrays(m.vertices, m.nv, m.tets, m.nt, NULL, xyz, n, a.flags, &rep);
    double t = cli_now() - t0;
    int ok = gs == GTET_OK && rep.ok;
    rc = ok ? CLI_OK : gs == GTET_ERR_OUT_OF_MEMORY ? CLI_NOMEM : CLI_CHECK_FAILED;
    if (ok && !a.quiet && !a.json)
        printf("check=ok mode=%s vertices=%zu tets=%zu facets_checked=%llu hull_facets=%llu "
               "duplicates=%llu negative_tets=%llu unused_vertices=%llu cospherical_facets=%llu "
               "coplanar_hull_edges=%llu skipped_cells=%zu euler=%d full=%d seconds=%.3f\n",
               mode, m.nv, m.nt, (unsigned long long)rep.facets_checked,
               (unsigned long long)rep.hull_facets, (unsigned long long)rep.duplicates,
               (unsigned long long)rep.negative_tets, (unsigned long long)rep.unused_vertices,
               (unsigned long long)rep.cospherical_facets,
               (unsigned long long)rep.coplanar_hull_edges, m.skipped_cells, rep.euler,
               (a.flags & GTET_CHECK_FULL) != 0, t);
    if (!ok && (gs == GTET_OK || gs == GTET_ERR_CHECK_FAILED))
        cli_error("%s: check failed (%s): %s", a.mesh, mode,
                  rep.message[0] ? rep.message : "an invariant does not hold");
    else if (!ok)
        cli_error("%s: %s%s%s", a.mesh, gtet_status_str(gs), rep.message[0] ? ": " : "",
                  rep.message);
    if (a.json) check_json(&a, ok ? "ok" : gs == GTET_ERR_CHECK_FAILED ? "check_failed" : "error",
                           &m, &rep, !ok, NULL, t);
    io_mesh_free(&m);
    free(xyz);
    return rc;
}

int cli_generate(int argc, char **argv)
{
    const char *kind = NULL, *count = NULL, *output = NULL, *val;
    uint64_t seed = 1, n = 0;
    int quiet = 0, r;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if ((r = cli_opt_value(argc, argv, &i, "-o", &val)) ||
            (r = cli_opt_value(argc, argv, &i, "--output", &val))) {
            if (r < 0) return cli_usage("option %s needs a file name", a);
            output = val;
        } else if ((r = cli_opt_value(argc, argv, &i, "--seed", &val))) {
            if (r < 0 || !cli_parse_u64(val, UINT64_MAX, &seed))
                return cli_usage("--seed needs a non-negative integer");
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return cli_usage("generate: unknown option '%s'", a);
        } else if (!kind) {
            kind = a;
        } else if (!count) {
            count = a;
        } else {
            return cli_usage("generate: unexpected argument '%s'", a);
        }
    }
    if (!kind || !count) return cli_usage("generate: expected KIND N");
    if (!io_generator_help(kind)) {
        fprintf(stderr, "gigatet: unknown generator kind '%s'; the kinds are:", kind);
        for (const char *const *k = io_generator_kinds(); *k; k++) fprintf(stderr, " %s", *k);
        fputc('\n', stderr);
        return CLI_USAGE;
    }
    if (!cli_parse_u64(count, UINT32_MAX, &n) || n < 1)
        return cli_usage("generate: N must be an integer in 1..%u, not '%s'", UINT32_MAX, count);
    if (!output) return cli_usage("generate: -o FILE is required");
    io_format of = io_format_of(output);
    if (of < IO_FMT_XYZ || of > IO_FMT_BIN)
        return cli_usage("%s: unknown point file extension (use .xyz, .node, .ply or .bin)", output);
    io_error ioe;
    io_status is;
    double *xyz;
    size_t m;
    if ((is = io_generate(kind, (size_t)n, seed, &xyz, &m, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        return cli_exit_of_io(is);
    }
    is = io_write_points(output, xyz, m, &ioe);
    free(xyz);
    if (is != IO_OK) {
        cli_error("%s", ioe.message);
        return cli_exit_of_io(is);
    }
    if (!quiet) printf("generated=%zu kind=%s seed=%llu file=%s\n", m, kind, (unsigned long long)seed, output);
    return CLI_OK;
}
