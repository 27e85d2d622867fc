/* consumer.c -- a program outside the source tree that uses the installed gigatet: built by
 * tests/install/test_install.sh through pkg-config and through find_package(gigatet).
 * Triangulates 1000 random points, checks the mesh with the exact checker, prints the
 * library's version; exit 0 when all is well. */
#include <gigatet.h>

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define STR_(x) #x
#define STR(x) STR_(x)

int main(void)
{
    enum { N = 1000 };
    static double xyz[3 * N];
    uint64_t s = 0x9e3779b97f4a7c15u;
    for (int i = 0; i < 3 * N; i++) {
        s = s * 6364136223846793005u + 1442695040888963407u;
        xyz[i] = (double)(s >> 11) / 9007199254740992.0;
    }
    const char *v = gtet_version();
    const char *h = STR(GTET_VERSION_MAJOR) "." STR(GTET_VERSION_MINOR) "." STR(GTET_VERSION_PATCH);
    printf("gigatet %s (header %s)\n", v, h);
    if (strcmp(v, h) != 0) {
        fprintf(stderr, "consumer: library version %s, header %s\n", v, h);
        return 1;
    }
    gtet_options opt;
    gtet_error err;
    gtet_mesh *mesh = NULL;
    gtet_options_init(&opt);
    opt.threads = 2;
    opt.error = &err;
    gtet_status st = gtet_triangulate(xyz, N, &opt, &mesh);
    if (st != GTET_OK) {
        fprintf(stderr, "consumer: gtet_triangulate: %s: %s\n", gtet_status_str(st), err.message);
        return 1;
    }
    gtet_check_report rep;
    st = gtet_check(mesh, xyz, N, 0, &rep);
    size_t nv = gtet_mesh_num_vertices(mesh), nt = gtet_mesh_num_tets(mesh);
    gtet_mesh_free(&mesh);
    if (st != GTET_OK || !rep.ok || nv != N || nt == 0) {
        fprintf(stderr, "consumer: check failed (%s): %s\n", gtet_status_str(st), rep.message);
        return 1;
    }
    printf("%zu vertices, %zu tets, check ok\n", nv, nt);
    return 0;
}
