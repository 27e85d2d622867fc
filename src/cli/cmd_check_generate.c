/* cmd_check_generate.c -- `gigatet check MESH [--points INPUT] [--delaunay] [--any-orientation]
 * [--full] [--json] [-q]` and
 * `gigatet generate KIND N [--seed S] [--mesh FILE] -o FILE [-q]`.
 *
 * check reads the mesh back (io_read_mesh: .ele with its .node, .msh, .vtu; every vertex id is
 * range-checked there) and hands the plain arrays to the exact checker gtet_check_arrays,
 * which rebuilds the adjacency itself.  Exit 5 when an invariant fails, 2 when a file is bad.
 * generate writes the points of io_generate atomically; the kind `surface` samples the
 * triangles of --mesh FILE (io_read_surface, io_sample_surface), which no other kind takes.
 */
#include "cli.h"
#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct check_args {
    const char *mesh, *points;
    unsigned flags, quiet, json;
} check_args;

static const cli_opt check_opts[] = {
    CLI_OPT_POINTS(check_args, "also check that every point of INPUT is a vertex (matched by\n"
                               "coordinates) or a duplicate of one"),
    {.name = "--delaunay", .kind = CLI_OPT_FLAG, .off = offsetof(check_args, flags),
     .bits = GTET_CHECK_DELAUNAY,
     .help = "judge the Delaunay property itself, ties allowed: any tool's Delaunay\n"
             "mesh passes"},
    {.name = "--any-orientation", .kind = CLI_OPT_FLAG, .off = offsetof(check_args, flags),
     .bits = GTET_CHECK_ANY_ORIENTATION,
     .help = "accept and count negatively oriented tets (flat ones fail)"},
    {.name = "--full", .kind = CLI_OPT_FLAG, .off = offsetof(check_args, flags),
     .bits = GTET_CHECK_FULL, .help = "add the O(n*m) empty-sphere test (small meshes only)"},
    CLI_OPT_JSON(check_args, "print one JSON report on stdout (mode, counts, first violation)"),
    CLI_OPT_QUIET(check_args),
    {0}};

static const cli_positional check_pos[] = {{"MESH", offsetof(check_args, mesh)}, {0}};

static int cli_check(int argc, char **argv);

const cli_command cli_cmd_check = {
    .name = "check",
    .summary = "Verify a mesh (a mesh format, below) with the exact checker.  By default\n"
               "the mesh must be THE canonical Delaunay mesh (ties broken by the symbolic\n"
               "perturbation, as gigatet and CGAL do).",
    .opts = check_opts,
    .pos = check_pos,
    .missing = "check: no mesh file",
    .extra = "check: more than one mesh file ('{first}', '{arg}')",
    .run = cli_check,
};

/* A usage error unless path names a mesh format io_read_mesh reads. */
int cli_need_mesh_format(const char *cmd, const char *path)
{
    char list[128];
    if (io_format_can(io_format_of(path), IO_READ_MESH)) return CLI_OK;
    return cli_usage("%s: %s reads %s meshes", path, cmd,
                     io_format_list(IO_READ_MESH, 1, list, sizeof list));
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

/* After a failed check of a file with cells that are not linear tetrahedra (quadratic
 * tets, hexahedra, ...: read_msh.c and read_vtu.c skip them), say so: "the mesh has no
 * tets" or a hole in the hull is otherwise a riddle (NOTES.md E159); and how the message's
 * tet and vertex numbers map to the file's (below).  diff's verdicts get the same notes
 * (NOTES.md E182). */
const char *cli_mesh_note(const char *path, const char *owner, const io_mesh *m,
                          const gtet_check_report *r, int ids, char *buf, size_t size)
{
    buf[0] = '\0';
    if (m->skipped_cells)
        snprintf(buf, size, " (%zu cell%s of %s %s not linear tetrahedra and %s skipped: "
                 "points, lines, triangles, quadratic tets, hexahedra, ...)", m->skipped_cells,
                 m->skipped_cells == 1 ? "" : "s", owner, m->skipped_cells == 1 ? "is" : "are",
                 m->skipped_cells == 1 ? "was" : "were");
    /* The numbers in the message are 0-based positions in the file (the checker sees arrays):
     * a 1-based .ele (TetGen's and gigatet's own) or a .msh's node tags read otherwise, so
     * say how to find them (NOTES.md E159d: 'tet 0 (26 35 24 13)' for the file's tet 1 with
     * nodes 27 36 25 14). */
    io_format f = io_format_of(path);
    ids = ids && (r->violation.tet[0] != GTET_CHECK_NONE || r->violation.nvertices > 0);
    if (ids && (f == IO_FMT_ELE || f == IO_FMT_MSH || m->skipped_cells)) {
        size_t at = strlen(buf);
        snprintf(buf + at, size - at, " [tets and vertices are numbered from 0 in the order of "
                 "%s%s, not by its own ids%s]", owner, f == IO_FMT_ELE ? "'s .ele and .node" : "",
                 f == IO_FMT_ELE   ? ": add 1 for a 1-based file"
                 : f == IO_FMT_MSH ? " (node tags, element tags)"
                                   : " (only its linear tetrahedra count)");
    }
    return buf;
}

static int cli_check(int argc, char **argv)
{
    char note[384];
    check_args a = {0};
    int rc = cli_parse(&cli_cmd_check, argc, argv, &a, NULL);
    if (rc == CLI_OK) rc = cli_need_mesh_format("check", a.mesh);
    if (rc != CLI_OK) return rc;
    io_error ioe;
    io_status is;
    io_mesh m;
    double *xyz = NULL;
    size_t n = 0;
    if ((is = io_read_mesh(a.mesh, &m, &ioe)) != IO_OK ||
        (a.points && (is = io_read_points(a.points, &xyz, &n, &ioe)) != IO_OK)) {
        rc = cli_io_failed(is, &ioe);
        if (a.json) check_json(&a, "unreadable", NULL, NULL, 1, ioe.message, 0);
        io_mesh_free(&m);
        return rc;
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
        cli_error("%s: check failed (%s): %s%s", a.mesh, mode,
                  rep.message[0] ? rep.message : "an invariant does not hold",
                  cli_mesh_note(a.mesh, "the file", &m, &rep, 1, note, sizeof note));
    else if (!ok)
        cli_error("%s: %s%s%s", a.mesh, gtet_status_str(gs), rep.message[0] ? ": " : "",
                  rep.message);
    if (a.json) check_json(&a, ok ? "ok" : gs == GTET_ERR_CHECK_FAILED ? "check_failed" : "error",
                           &m, &rep, !ok, NULL, t);
    io_mesh_free(&m);
    free(xyz);
    return rc;
}

typedef struct gen_args {
    const char *kind, *count, *output, *mesh;
    uint64_t seed;
    unsigned quiet;
} gen_args;

static const cli_opt gen_opts[] = {
    {.name = "-o", .alias = "--output", .kind = CLI_OPT_STRING, .off = offsetof(gen_args, output),
     .required = 1, .arg = "FILE", .missing = "option {opt} needs a file name",
     .help = "the point file to write, in a point format (below)"},
    {.name = "--seed", .kind = CLI_OPT_U64, .off = offsetof(gen_args, seed), .max = UINT64_MAX,
     .arg = "S", .missing = "--seed needs a non-negative integer",
     .help = "seed of the random kinds (default 1)"},
    {.name = "--mesh", .kind = CLI_OPT_STRING, .off = offsetof(gen_args, mesh), .arg = "FILE",
     .missing = "option --mesh needs a file name",
     .help = "the triangle mesh the kind 'surface' samples (.off or .ply with faces)"},
    CLI_OPT_QUIET(gen_args),
    {0}};

static const cli_positional gen_pos[] = {
    {"KIND", offsetof(gen_args, kind)}, {"N", offsetof(gen_args, count)}, {0}};

static int cli_generate(int argc, char **argv);

const cli_command cli_cmd_generate = {
    .name = "generate",
    .summary = "Write about N points of KIND (the generator kinds, below) to FILE.",
    .opts = gen_opts,
    .pos = gen_pos,
    .missing = "generate: expected KIND N",
    .extra = "generate: unexpected argument '{arg}'",
    .run = cli_generate,
};

/* n points on the triangles of a->mesh. */
static io_status gen_surface(const gen_args *a, size_t n, double **xyz, io_error *e)
{
    io_surface s;
    io_status is = io_read_surface(a->mesh, &s, e);
    if (is == IO_OK) is = io_sample_surface(&s, a->mesh, n, a->seed, xyz, e);
    io_surface_free(&s);
    return is;
}

static int cli_generate(int argc, char **argv)
{
    gen_args a = {.seed = 1};
    uint64_t n = 0;
    char list[128];
    int rc = cli_parse(&cli_cmd_generate, argc, argv, &a, NULL);
    if (rc != CLI_OK) return rc;
    if (!io_generator_help(a.kind)) {
        fprintf(stderr, "gigatet: unknown generator kind '%s'; the kinds are:", a.kind);
        for (const char *const *k = io_generator_kinds(); *k; k++) fprintf(stderr, " %s", *k);
        fputc('\n', stderr);
        return CLI_USAGE;
    }
    if (!cli_parse_u64(a.count, UINT32_MAX, &n) || n < 1)
        return cli_usage("generate: N must be an integer in 1..%u, not '%s'", UINT32_MAX, a.count);
    if (!a.output) return cli_usage("generate: -o FILE is required");
    if (!io_format_can(io_format_of(a.output), IO_WRITE_POINTS))
        return cli_usage("%s: unknown point file extension (use %s)", a.output,
                         io_format_list(IO_WRITE_POINTS, 0, list, sizeof list));
    int surface = !strcmp(a.kind, "surface");
    if (surface && !a.mesh) return cli_usage("generate: the kind 'surface' needs --mesh FILE");
    if (!surface && a.mesh) return cli_usage("generate: --mesh is only for the kind 'surface'");
    if (surface && !io_format_can(io_format_of(a.mesh), IO_READ_SURFACE))
        return cli_usage("%s: generate surface reads %s meshes", a.mesh,
                         io_format_list(IO_READ_SURFACE, 0, list, sizeof list));
    if (surface && cli_overwrites_input(a.mesh, a.output))   /* NOTES.md E151 */
        return cli_usage("%s: writing the points would overwrite the input mesh %s", a.output,
                         a.mesh);
    io_error ioe;
    io_status is;
    double *xyz;
    size_t m = (size_t)n;
    if ((is = surface ? gen_surface(&a, m, &xyz, &ioe)
                      : io_generate(a.kind, (size_t)n, a.seed, &xyz, &m, &ioe)) != IO_OK)
        return cli_io_failed(is, &ioe);
    is = io_write_points(a.output, xyz, m, &ioe);
    free(xyz);
    if (is != IO_OK) return cli_io_failed(is, &ioe);
    if (!a.quiet)
        printf("generated=%zu kind=%s seed=%llu file=%s\n", m, a.kind, (unsigned long long)a.seed,
               a.output);
    return CLI_OK;
}
