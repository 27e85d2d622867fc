/* cmd_check_generate.c -- `gigatet check MESH [--points INPUT] [--full] [-q]` and
 * `gigatet generate KIND N [--seed S] -o FILE [-q]`.
 *
 * check reads the mesh back (io_read_mesh: .ele with its .node, .msh, .vtu; every vertex id is
 * range-checked there) and hands the plain arrays to the exact checker gtet_check_arrays,
 * which rebuilds the adjacency itself.  Exit 5 when an invariant fails, 2 when a file is bad.
 * generate writes the points of io_generate atomically.
 */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cli_check(int argc, char **argv)
{
    const char *mesh_path = NULL, *points = NULL, *val;
    int full = 0, quiet = 0, r;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if ((r = cli_opt_value(argc, argv, &i, "--points", &val))) {
            if (r < 0) return cli_usage("option --points needs a file name");
            points = val;
        } else if (!strcmp(a, "--full")) {
            full = 1;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return cli_usage("check: unknown option '%s'", a);
        } else if (!mesh_path) {
            mesh_path = a;
        } else {
            return cli_usage("check: more than one mesh file ('%s', '%s')", mesh_path, a);
        }
    }
    if (!mesh_path) return cli_usage("check: no mesh file");
    io_format mf = io_format_of(mesh_path);
    if (mf != IO_FMT_ELE && mf != IO_FMT_MSH && mf != IO_FMT_VTU)
        return cli_usage("%s: check reads .ele (with its .node), .msh or .vtu meshes", mesh_path);

    io_error ioe;
    io_status is;
    io_mesh m;
    double *xyz = NULL;
    size_t n = 0;
    if ((is = io_read_mesh(mesh_path, &m, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        return cli_exit_of_io(is);
    }
    if (points && (is = io_read_points(points, &xyz, &n, &ioe)) != IO_OK) {
        cli_error("%s", ioe.message);
        io_mesh_free(&m);
        return cli_exit_of_io(is);
    }
    gtet_check_report rep;
    memset(&rep, 0, sizeof rep);
    double t0 = cli_now();
    gtet_status gs = gtet_check_arrays(m.vertices, m.nv, m.tets, m.nt, NULL, xyz, n,
                                       full ? GTET_CHECK_FULL : 0u, &rep);
    double t = cli_now() - t0;
    int rc = CLI_OK;
    if (gs == GTET_OK && rep.ok) {
        if (!quiet)
            printf("check=ok vertices=%zu tets=%zu facets_checked=%llu hull_facets=%llu "
                   "duplicates=%llu euler=%d full=%d seconds=%.3f\n", m.nv, m.nt,
                   (unsigned long long)rep.facets_checked, (unsigned long long)rep.hull_facets,
                   (unsigned long long)rep.duplicates, rep.euler, full, t);
    } else if (gs == GTET_OK || gs == GTET_ERR_CHECK_FAILED) {
        cli_error("%s: check failed: %s", mesh_path, rep.message[0] ? rep.message : "an invariant does not hold");
        rc = CLI_CHECK_FAILED;
    } else {
        cli_error("%s: %s%s%s", mesh_path, gtet_status_str(gs), rep.message[0] ? ": " : "",
                  rep.message);
        rc = gs == GTET_ERR_OUT_OF_MEMORY ? CLI_NOMEM : CLI_CHECK_FAILED;
    }
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
