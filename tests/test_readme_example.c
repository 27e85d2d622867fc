/* test_readme_example.c -- the C example of README.md, line for line, compiles and works. */
#include <stdio.h>

#include "gigatet.h"
#include "testutil.h"

static int readme_example(const double *xyz, size_t n)
{
    gtet_options opt; gtet_error err; gtet_mesh *mesh;
    gtet_options_init(&opt); opt.threads = 0; opt.error = &err;      /* 0 = all cores */
    if (gtet_triangulate(xyz, n, &opt, &mesh) != GTET_OK) { fprintf(stderr, "%s\n", err.message); return 1; }
    const uint32_t *tet = gtet_mesh_tets(mesh);        /* 4 vertex ids per tet, orient3d > 0 */
    const uint32_t *nbr = gtet_mesh_neighbors(mesh);   /* across the facet opposite vertex i, or GTET_NO_TET */
    const double *v = gtet_mesh_vertices(mesh);        /* distinct points, first occurrence order */
    const uint32_t *map = gtet_mesh_input_map(mesh);   /* input point i -> vertex id (duplicates too) */
    gtet_check_report rep; gtet_check(mesh, xyz, n, 0, &rep);   /* exact, independent checker */
    int ok = rep.ok && tet && nbr && v && map && map[n - 1] == map[0];
    gtet_mesh_free(&mesh);
    return ok ? 0 : 2;
}

static void test_readme_example_triangulates_and_checks(void)
{
    double xyz[3 * 1001];
    tu_rng r = {11};
    for (int i = 0; i < 3 * 1000; i++) xyz[i] = tu_uniform(&r);
    xyz[3000] = xyz[0]; xyz[3001] = xyz[1]; xyz[3002] = xyz[2];   /* a duplicate of point 0 */
    TEST_CHECK(readme_example(xyz, 1001) == 0, "the README example fails");
}

int main(void)
{
    TU_RUN(test_readme_example_triangulates_and_checks);
    return tu_finish();
}
