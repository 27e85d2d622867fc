/* test_check_mesh.c -- gtet_check() on a gtet_mesh: it reads the mesh through its accessors and
 * also checks the mesh's own bookkeeping (input map, first-occurrence numbering, the reported
 * counts of points, duplicates and hull facets, the neighbor array).
 *
 * The mesh object is filled by hand here (struct gtet_mesh of src/mesh/mesh.h) from the
 * brute-force perturbed Delaunay mesh of test_check_meshes.h, so the test needs no kernel.
 */
#include <stdio.h>
#include <string.h>

#include "mesh/mesh.h"
#include "test_check_meshes.h"
#include "testutil.h"

/* Input: (0, 0.5, 0), 14 random points, then duplicates of point 4, of point 0 written with
 * -0.0, and of point 8. */
#define NIN 18

static void make_input(double xyz[3 * NIN])
{
    double *r = tm_random_points(31, 14);
    const double zero[3] = {0.0, 0.5, 0.0}, negzero[3] = {-0.0, 0.5, -0.0};
    memcpy(xyz, zero, sizeof zero);
    memcpy(xyz + 3, r, 14 * 3 * sizeof *r);
    memcpy(xyz + 3 * 15, xyz + 3 * 4, 3 * sizeof *xyz);
    memcpy(xyz + 3 * 16, negzero, sizeof negzero);
    memcpy(xyz + 3 * 17, xyz + 3 * 8, 3 * sizeof *xyz);
    free(r);
}

/* A gtet_mesh over the 15 distinct points, numbered in order of first occurrence. */
static gtet_mesh *make_mesh(const double xyz[3 * NIN])
{
    tmesh m = tm_brute_delaunay(xyz, 15);
    gtet_mesh *g = calloc(1, sizeof *g);
    g->n_points = NIN;
    g->n_vertices = 15;
    g->n_tets = m.nt;
    g->vertices = m.v;
    g->tets = m.t;
    g->neighbors = m.nb;
    g->input_map = malloc(NIN * sizeof *g->input_map);
    for (uint32_t i = 0; i < 15; i++) g->input_map[i] = i;
    g->input_map[15] = 4;
    g->input_map[16] = 0;
    g->input_map[17] = 8;
    for (size_t i = 0; i < 4 * m.nt; i++) g->n_hull_facets += m.nb[i] == GTET_NO_TET;
    return g;
}

static gtet_status check(const gtet_mesh *g, const double *xyz, size_t n, char msg[512])
{
    gtet_check_report r;
    gtet_status st = gtet_check(g, xyz, n, 0, &r);
    snprintf(msg, 512, "%s", r.message);
    return st;
}

static void test_valid_mesh_with_signed_zero_duplicates_passes(void)
{
    double xyz[3 * NIN];
    make_input(xyz);
    gtet_mesh *g = make_mesh(xyz);
    gtet_check_report r;
    TEST_CHECK(gtet_check(g, xyz, NIN, GTET_CHECK_FULL, &r) == GTET_OK, "%s", r.message);
    TEST_CHECK(r.ok && r.duplicates == 3 && r.tets == g->n_tets && r.euler == 1 &&
               r.hull_facets == g->n_hull_facets, "report: %s", r.message);
    TEST_CHECK(gtet_check(g, NULL, 0, 0, NULL) == GTET_OK, "without input");
    gtet_mesh_free(&g);
}

static void test_wrong_input_map_entry_is_named(void)
{
    double xyz[3 * NIN];
    char msg[512];
    make_input(xyz);
    gtet_mesh *g = make_mesh(xyz);
    g->input_map[16] = 1;
    TEST_CHECK(check(g, xyz, NIN, msg) == GTET_ERR_CHECK_FAILED, "wrong map passes");
    TEST_CHECK(strstr(msg, "input_map[16] = 1, but input point 16 is vertex 0") != NULL, "%s", msg);
    gtet_mesh_free(&g);
}

static void test_vertices_out_of_first_occurrence_order_are_named(void)
{
    double xyz[3 * NIN];
    char msg[512];
    make_input(xyz);
    gtet_mesh *g = make_mesh(xyz);
    /* swap the numbers of vertices 5 and 6 everywhere: still a valid mesh, wrong numbering */
    for (int j = 0; j < 3; j++) {
        double x = g->vertices[15 + j];
        g->vertices[15 + j] = g->vertices[18 + j];
        g->vertices[18 + j] = x;
    }
    for (size_t i = 0; i < 4 * g->n_tets; i++)
        if (g->tets[i] == 5 || g->tets[i] == 6) g->tets[i] ^= 3;  /* 5 <-> 6 */
    for (size_t t = 0; t < g->n_tets; t++) tm_orient(g->vertices, g->tets + 4 * t);
    tmesh tmp = {g->vertices, 15, g->tets, g->n_tets, g->neighbors};
    tm_neighbors(&tmp);
    g->neighbors = tmp.nb;
    g->input_map[5] = 6;
    g->input_map[6] = 5;
    TEST_CHECK(gtet_check_arrays(g->vertices, 15, g->tets, g->n_tets, g->neighbors, xyz, NIN, 0,
                                 NULL) == GTET_OK, "the renumbered arrays are not valid");
    TEST_CHECK(check(g, xyz, NIN, msg) == GTET_ERR_CHECK_FAILED, "renumbering passes");
    TEST_CHECK(strstr(msg, "not numbered in order of first occurrence") != NULL, "%s", msg);
    gtet_mesh_free(&g);
}

static void test_wrong_counts_are_named(void)
{
    double xyz[3 * NIN];
    char msg[512];
    make_input(xyz);
    gtet_mesh *g = make_mesh(xyz);
    g->n_hull_facets++;
    TEST_CHECK(check(g, xyz, NIN, msg) == GTET_ERR_CHECK_FAILED && strstr(msg, "hull facets"),
               "hull count: %s", msg);
    g->n_hull_facets--;
    TEST_CHECK(check(g, xyz, NIN - 1, msg) == GTET_ERR_CHECK_FAILED &&
               strstr(msg, "17 input points given, but the mesh was built from 18"), "n: %s", msg);
    /* the last duplicate replaced by a new point that the mesh lacks */
    xyz[3 * 17] = 2.0;
    TEST_CHECK(check(g, xyz, NIN, msg) == GTET_ERR_CHECK_FAILED &&
               strstr(msg, "input point 17 (2,"), "new point: %s", msg);
    gtet_mesh_free(&g);
}

static void test_broken_neighbor_array_is_named(void)
{
    double xyz[3 * NIN];
    char msg[512];
    make_input(xyz);
    gtet_mesh *g = make_mesh(xyz);
    size_t tf = 0;
    while (g->neighbors[tf] == GTET_NO_TET) tf++;
    g->neighbors[tf] = GTET_NO_TET;
    TEST_CHECK(check(g, xyz, NIN, msg) == GTET_ERR_CHECK_FAILED, "broken neighbor passes");
    char want[64];
    snprintf(want, sizeof want, "neighbor[4*%zu+%zu] is the hull", tf / 4, tf % 4);
    TEST_CHECK(strstr(msg, want) != NULL, "%s", msg);
    TEST_CHECK(gtet_check(NULL, xyz, NIN, 0, NULL) == GTET_ERR_ARGUMENT, "NULL mesh accepted");
    gtet_mesh_free(&g);
}

int main(void)
{
    TU_RUN(test_valid_mesh_with_signed_zero_duplicates_passes);
    TU_RUN(test_wrong_input_map_entry_is_named);
    TU_RUN(test_vertices_out_of_first_occurrence_order_are_named);
    TU_RUN(test_wrong_counts_are_named);
    TU_RUN(test_broken_neighbor_array_is_named);
    return tu_finish();
}
