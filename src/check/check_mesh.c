/* check_mesh.c -- gtet_check(): the exact checker on a gtet_mesh, read only through the public
 * accessors of gigatet.h (src/mesh/mesh.c).  Kept apart from check.c so that tests of
 * gtet_check_arrays() need no mesh object.  Besides everything gtet_check_arrays() proves, it checks the mesh's own
 * bookkeeping: the input map (each input point maps to the vertex with its coordinates, the
 * vertices numbered in order of first occurrence), the counts of points, duplicates and hull
 * facets the mesh reports, and its neighbor array against the rebuilt adjacency.
 */
#include <stdio.h>
#include <string.h>

#include "gigatet.h"
#include "check_internal.h"

gtet_status gtet_check(const gtet_mesh *mesh, const double *xyz, size_t n, unsigned flags,
                       gtet_check_report *report)
{
    gtet_check_options o;
    gtet_check_options_init(&o);
    o.flags = flags;
    return gtet_check_opt(mesh, xyz, n, &o, report);
}

gtet_status gtet_check_opt(const gtet_mesh *mesh, const double *xyz, size_t n,
                           const gtet_check_options *opts, gtet_check_report *report)
{
    const unsigned flags = opts ? opts->flags : 0u;
    gtet_check_report local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    if (!mesh || (!xyz && n) || (flags & ~CHK_KNOWN_FLAGS)) {
        snprintf(report->message, sizeof report->message,
                 "invalid argument: no mesh, NULL points with n > 0, or unknown flags");
        return GTET_ERR_ARGUMENT;
    }
    size_t nv = gtet_mesh_num_vertices(mesh), nt = gtet_mesh_num_tets(mesh);
    report->tets = nt;
    if (nv >= UINT32_MAX || nt >= UINT32_MAX / 4) {
        snprintf(report->message, sizeof report->message,
                 "%zu vertices / %zu tets: more than 32-bit ids hold", nv, nt);
        return GTET_ERR_TOO_LARGE;
    }
    chk_ctx c;
    memset(&c, 0, sizeof c);
    c.vertices = gtet_mesh_vertices(mesh);
    c.nv = nv;
    c.tets = gtet_mesh_tets(mesh);
    c.nt = nt;
    c.neighbors = gtet_mesh_neighbors(mesh);
    c.flags = flags;
    c.report = report;
    c.cancel = opts ? opts->cancel : NULL;
    c.cancel_user = opts ? opts->cancel_user : NULL;
    if ((!c.vertices && nv) || (!c.tets && nt) || (!c.neighbors && nt))
        return chk_fail(&c, "the mesh lacks its vertex, tet or neighbor array");
    if (xyz) {
        if (n != gtet_mesh_num_points(mesh))
            return chk_fail(&c, "%zu input points given, but the mesh was built from %zu", n,
                            gtet_mesh_num_points(mesh));
        c.xyz = xyz;
        c.n = n;
        c.input_map = gtet_mesh_input_map(mesh);
        if (!c.input_map && n) return chk_fail(&c, "the mesh lacks its input map");
    }
    gtet_status st = chk_run(&c);
    if (st != GTET_OK) return st;
    if (report->hull_facets != gtet_mesh_num_hull_facets(mesh))
        return chk_fail(&c, "the mesh reports %zu hull facets; it has %llu",
                        gtet_mesh_num_hull_facets(mesh), (unsigned long long)report->hull_facets);
    if (xyz && report->duplicates != gtet_mesh_num_duplicates(mesh))
        return chk_fail(&c, "the mesh reports %zu duplicates; the input has %llu",
                        gtet_mesh_num_duplicates(mesh), (unsigned long long)report->duplicates);
    return GTET_OK;
}
