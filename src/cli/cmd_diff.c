/* cmd_diff.c -- `gigatet diff A B [--points INPUT] [--groups N] [--json] [-q]`.
 *
 * Reads two meshes (any format check reads) and compares them with gtet_diff: as sets of tets
 * over coordinates.  Exit 0 when they are identical, 5 when they differ, 2 when a file is bad,
 * 4 out of memory.  The verdict says how they differ: different tie-breaking of co-spherical
 * groups (both Delaunay; the groups listed), one side not Delaunay (its first violation), or
 * different point sets.
 */
#include "cli.h"
#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct diff_args {
    const char *a, *b, *points;
    uint64_t groups;  /* groups listed; 0 = all */
    unsigned quiet, json;
} diff_args;

static const char *const kind_name[] = {"identical", "ties", "a_not_delaunay", "b_not_delaunay",
                                        "neither_delaunay", "points"};

static const cli_opt diff_opts[] = {
    CLI_OPT_POINTS(diff_args, "check both against the input points too"),
    {.name = "--groups", .kind = CLI_OPT_U64, .off = offsetof(diff_args, groups),
     .max = UINT64_MAX, .arg = "N", .missing = "--groups needs a non-negative integer (0 = all)",
     .help = "list at most N groups (default 10; 0 = all)"},
    CLI_OPT_JSON(diff_args, "print one JSON report on stdout"),
    CLI_OPT_QUIET(diff_args),
    {0}};

static const cli_positional diff_pos[] = {
    {"A", offsetof(diff_args, a)}, {"B", offsetof(diff_args, b)}, {0}};

static int cli_diff(int argc, char **argv);

const cli_command cli_cmd_diff = {
    .name = "diff",
    .summary = "Compare two meshes of one point set as sets of tets over coordinates:\n"
               "exit 0 identical, 5 different, and say how (tie-breaking of co-spherical\n"
               "groups, listed; or which side is not Delaunay; or different points).",
    .opts = diff_opts,
    .pos = diff_pos,
    .missing = "diff: expected two mesh files A B",
    .extra = "diff: expected two mesh files, got a third ('{arg}')",
    .run = cli_diff,
};

static uint64_t listed(const diff_args *d, const gtet_diff_report *r)
{
    return d->groups == 0 || d->groups > r->num_groups ? r->num_groups : d->groups;
}

static void diff_text(const diff_args *d, const gtet_diff_report *r, const io_mesh *ma,
                      const io_mesh *mb)
{
    printf("diff=%s tets_a=%llu tets_b=%llu common=%llu only_a=%llu only_b=%llu groups=%llu\n",
           kind_name[r->kind], (unsigned long long)r->tets_a, (unsigned long long)r->tets_b,
           (unsigned long long)r->common, (unsigned long long)r->only_a,
           (unsigned long long)r->only_b, (unsigned long long)r->num_groups);
    /* check's notes (NOTES.md E159, E159d; here E182): skipped cells of either file, and for
     * the file whose violation the message quotes (A's when neither is Delaunay) how its tet
     * and vertex numbers map to the file's ids */
    char note[2][384] = {"", ""};
    if (r->kind != GTET_DIFF_IDENTICAL) {
        int quoted_b = r->kind == GTET_DIFF_B_NOT_DELAUNAY;
        int quoted_a = r->kind == GTET_DIFF_A_NOT_DELAUNAY || r->kind == GTET_DIFF_NEITHER_DELAUNAY;
        cli_mesh_note(d->a, "A", ma, &r->check_a, quoted_a, note[0], sizeof note[0]);
        cli_mesh_note(d->b, "B", mb, &r->check_b, quoted_b, note[1], sizeof note[1]);
    }
    printf("%s%s%s\n", r->message, note[0], note[1]);
    uint64_t k = listed(d, r);
    for (uint64_t i = 0; i < k; i++) {
        const gtet_diff_group *g = &r->groups[i];
        printf("group %llu: %llu co-spherical points%s, A %llu tets (%llu only in A), B %llu tets "
               "(%llu only in B), point (%.17g, %.17g, %.17g), centre ~ (%.6g, %.6g, %.6g)\n",
               (unsigned long long)i + 1, (unsigned long long)g->size,
               g->on_hull ? " on the hull" : "", (unsigned long long)g->tets_a,
               (unsigned long long)g->only_a, (unsigned long long)g->tets_b,
               (unsigned long long)g->only_b, g->point[0], g->point[1], g->point[2],
               g->center[0], g->center[1], g->center[2]);
    }
    if (k < r->num_groups)
        printf("... and %llu more groups (--groups 0 lists all)\n",
               (unsigned long long)(r->num_groups - k));
}

static void diff_json(const diff_args *d, const gtet_diff_report *r)
{
    fputs("{\"a\":", stdout);
    cli_json_str(stdout, d->a);
    fputs(",\"b\":", stdout);
    cli_json_str(stdout, d->b);
    printf(",\"verdict\":\"%s\",\"identical\":%s,\"tets_a\":%llu,\"tets_b\":%llu,\"common\":%llu,"
           "\"only_a\":%llu,\"only_b\":%llu,\"points_only_a\":%llu,\"points_only_b\":%llu,"
           "\"message\":",
           kind_name[r->kind], r->kind == GTET_DIFF_IDENTICAL ? "true" : "false",
           (unsigned long long)r->tets_a, (unsigned long long)r->tets_b,
           (unsigned long long)r->common, (unsigned long long)r->only_a,
           (unsigned long long)r->only_b, (unsigned long long)r->points_only_a,
           (unsigned long long)r->points_only_b);
    cli_json_str(stdout, r->message);
    printf(",\"groups_total\":%llu,\"groups\":[", (unsigned long long)r->num_groups);
    uint64_t k = listed(d, r);
    for (uint64_t i = 0; i < k; i++) {
        const gtet_diff_group *g = &r->groups[i];
        printf("%s{\"size\":%llu,\"tets_a\":%llu,\"only_a\":%llu,\"tets_b\":%llu,\"only_b\":%llu,"
               "\"on_hull\":%s,\"point\":", i ? "," : "", (unsigned long long)g->size,
               (unsigned long long)g->tets_a, (unsigned long long)g->only_a,
               (unsigned long long)g->tets_b, (unsigned long long)g->only_b,
               g->on_hull ? "true" : "false");
        cli_json_point(stdout, g->point);
        fputs(",\"center\":", stdout);
        cli_json_point(stdout, g->center);
        fputc('}', stdout);
    }
    fputc(']', stdout);
    int ran = r->kind != GTET_DIFF_IDENTICAL && r->kind != GTET_DIFF_POINTS;
    const gtet_check_report *c[2] = {&r->check_a, &r->check_b};
    for (int i = 0; i < 2; i++) {
        printf(",\"check_%c\":", "ab"[i]);
        if (!ran) {
            fputs("null", stdout);
            continue;
        }
        fputc('{', stdout);
        cli_json_check_members(stdout, c[i], !c[i]->ok);
        fputc('}', stdout);
    }
    fputs("}\n", stdout);
}

static int cli_diff(int argc, char **argv)
{
    diff_args d = {.groups = 10};
    int rc = cli_parse(&cli_cmd_diff, argc, argv, &d, NULL);
    if (rc == CLI_OK) rc = cli_need_mesh_format("diff", d.a);
    if (rc == CLI_OK) rc = cli_need_mesh_format("diff", d.b);
    if (rc != CLI_OK) return rc;
    io_error ioe;
    io_status is;
    io_mesh ma, mb;
    memset(&mb, 0, sizeof mb);
    double *xyz = NULL;
    size_t n = 0;
    if ((is = io_read_mesh(d.a, &ma, &ioe)) != IO_OK) return cli_io_failed(is, &ioe);
    if ((is = io_read_mesh(d.b, &mb, &ioe)) != IO_OK ||
        (d.points && (is = io_read_points(d.points, &xyz, &n, &ioe)) != IO_OK)) {
        io_mesh_free(&ma);
        io_mesh_free(&mb);
        return cli_io_failed(is, &ioe);
    }
    gtet_diff_report r;
    gtet_status gs = gtet_diff(ma.vertices, ma.nv, ma.tets, ma.nt, mb.vertices, mb.nv, mb.tets,
                               mb.nt, xyz, n, &r);
    if (gs != GTET_OK) {
        cli_error("diff %s %s: %s", d.a, d.b, r.message);
        rc = cli_exit_of_gtet(gs);
    } else {
        if (d.json) diff_json(&d, &r);
        else if (!d.quiet) diff_text(&d, &r, &ma, &mb);
        rc = r.kind == GTET_DIFF_IDENTICAL ? CLI_OK : CLI_CHECK_FAILED;
    }
    gtet_diff_report_free(&r);
    io_mesh_free(&ma);
    io_mesh_free(&mb);
    free(xyz);
    return rc;
}
