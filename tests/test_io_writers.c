/* test_io_writers.c -- every writer reads back bit-exact through the readers, and a failed
 * write leaves nothing behind (no output, no temporary, no half of a .node/.ele pair).
 */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/io.h"
#include "testutil.h"

static char dir[64];

static const char *in_dir(char *buf, const char *name)
{
    snprintf(buf, 256, "%s/%s", dir, name);
    return buf;
}

/* Number of directory entries other than . and .. under path. */
static int entries(const char *path)
{
    DIR *d = opendir(path);
    int k = 0;
    if (!d) return -1;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) k++;
    closedir(d);
    return k;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Awkward doubles: signed zero, denormals, extremes, values whose shortest decimal has 17
 * digits, and random bit patterns (finite ones). */
static size_t awkward_points(double *p, size_t cap)
{
    static const double fixed[] = {0.0, -0.0, 0x1p-1074, -0x1p-1022, DBL_MAX, -DBL_MAX, 0.1,
                                   1.0 / 3.0, 0.30000000000000004, 1e-300, 123456789.0, -1.5};
    size_t k = 0;
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) p[k++] = fixed[i];
    tu_rng r = {42};
    while (k < cap) {
        uint64_t u = tu_next(&r);
        double d;
        memcpy(&d, &u, 8);
        if (isfinite(d)) p[k++] = d;
    }
    return k / 3;
}

static void test_point_writers_read_back_bit_exact_in_every_format(void)
{
    double pts[3 * 200];
    size_t n = awkward_points(pts, 3 * 200);
    const char *names[] = {"p.xyz", "p.node", "p.ply", "p.bin"};
    char path[256];
    for (int f = 0; f < 4; f++) {
        io_error e;
        double *q;
        size_t m;
        in_dir(path, names[f]);
        TEST_REQUIRE(io_write_points(path, pts, n, &e) == IO_OK, "write %s: %s", names[f], e.message);
        TEST_REQUIRE(io_read_points(path, &q, &m, &e) == IO_OK, "read %s: %s", names[f], e.message);
        TEST_CHECK(m == n && memcmp(q, pts, 3 * n * sizeof(double)) == 0,
                   "%s does not read back bit-exact", names[f]);
        free(q);
        remove(path);
    }
    TEST_CHECK(entries(dir) == 0, "files left behind in %s", dir);
}

static void test_mesh_writers_read_back_bit_exact_as_ele_msh_and_vtu(void)
{
    double v[3 * 60];
    size_t nv = awkward_points(v, 3 * 60);
    uint32_t tets[4 * 30];
    tu_rng r = {7};
    for (size_t i = 0; i < 4 * 30; i++) tets[i] = (uint32_t)tu_below(&r, nv);
    const char *names[] = {"m.ele", "m.msh", "m.vtu"};
    char path[256], node[256];
    for (int f = 0; f < 3; f++) {
        io_error e;
        io_mesh m;
        in_dir(path, names[f]);
        TEST_REQUIRE(io_write_mesh(path, v, nv, tets, 30, &e) == IO_OK, "write %s: %s", names[f], e.message);
        TEST_REQUIRE(io_read_mesh(path, &m, &e) == IO_OK, "read %s: %s", names[f], e.message);
        TEST_CHECK(m.nv == nv && memcmp(m.vertices, v, sizeof v) == 0, "%s vertices differ", names[f]);
        TEST_CHECK(m.nt == 30 && memcmp(m.tets, tets, sizeof tets) == 0, "%s tets differ", names[f]);
        io_mesh_free(&m);
        remove(path);
    }
    TEST_CHECK(exists(in_dir(node, "m.node")), ".ele did not write its .node");
    remove(node);
    TEST_CHECK(entries(dir) == 0, "files left behind in %s", dir);
}

static void test_ele_files_are_one_based_tetgen_with_17_digit_coordinates(void)
{
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.1};
    const uint32_t t[4] = {0, 1, 2, 3};
    char path[256], node[256], text[512];
    io_error e;
    TEST_REQUIRE(io_write_mesh(in_dir(path, "one.ele"), v, 4, t, 1, &e) == IO_OK, "%s", e.message);
    FILE *f = fopen(path, "r");
    size_t k = fread(text, 1, sizeof text - 1, f);
    text[k] = '\0';
    fclose(f);
    TEST_CHECK(strncmp(text, "1 4 0\n1 1 2 3 4\n", 16) == 0, ".ele text is '%s'", text);
    f = fopen(in_dir(node, "one.node"), "r");
    k = fread(text, 1, sizeof text - 1, f);
    text[k] = '\0';
    fclose(f);
    TEST_CHECK(strstr(text, "4 3 0 0\n1 0 0 0\n") == text && strstr(text, "4 0 0 0.10000000000000001\n"),
               ".node text is '%s'", text);
    remove(path);
    remove(node);
}

static void test_vtu_declares_counts_and_tetra_cell_type(void)
{
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t t[4] = {0, 1, 2, 3};
    char path[256], text[4096];
    io_error e;
    TEST_REQUIRE(io_write_mesh(in_dir(path, "one.vtu"), v, 4, t, 1, &e) == IO_OK, "%s", e.message);
    FILE *f = fopen(path, "r");
    size_t k = fread(text, 1, sizeof text - 1, f);
    text[k] = '\0';
    fclose(f);
    TEST_CHECK(strstr(text, "NumberOfPoints=\"4\" NumberOfCells=\"1\""), "counts missing");
    TEST_CHECK(strstr(text, "Name=\"types\" format=\"ascii\">\n10\n</DataArray>"), "type 10 missing");
    TEST_CHECK(strstr(text, "Name=\"offsets\" format=\"ascii\">\n4\n</DataArray>"), "offsets wrong");
    remove(path);
}

static void test_failed_writes_leave_no_file_and_no_temporary(void)
{
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t t[4] = {0, 1, 2, 3};
    char path[256], sub[256];
    io_error e;
    /* a missing directory */
    TEST_CHECK(io_write_mesh(in_dir(path, "nodir/m.msh"), v, 4, t, 1, &e) == IO_ERR_WRITE &&
               strstr(e.message, "nodir/m.msh"), "missing directory: %s", e.message);
    TEST_CHECK(io_write_points(in_dir(path, "nodir/p.xyz"), v, 4, &e) == IO_ERR_WRITE, "%s", e.message);
    TEST_CHECK(io_check_writable(in_dir(path, "nodir/p.xyz"), &e) == IO_ERR_WRITE, "check_writable");
    TEST_CHECK(io_check_writable(in_dir(path, "ok.xyz"), &e) == IO_OK && !exists(path),
               "io_check_writable left a file or failed: %s", e.message);
    /* the .ele rename fails (the name is a directory): the .node must not stay behind */
    mkdir(in_dir(sub, "m.ele"), 0700);
    TEST_CHECK(io_write_mesh(sub, v, 4, t, 1, &e) == IO_ERR_WRITE, "rename onto a directory succeeded");
    TEST_CHECK(!exists(in_dir(path, "m.node")), "half of a .node/.ele pair left behind");
    rmdir(sub);
    /* an unknown extension is an argument error, and creates nothing */
    TEST_CHECK(io_write_mesh(in_dir(path, "m.stl"), v, 4, t, 1, &e) == IO_ERR_ARGUMENT, "%s", e.message);
    TEST_CHECK(io_write_points(in_dir(path, "p.txt"), v, 4, &e) == IO_ERR_ARGUMENT, "%s", e.message);
    TEST_CHECK(entries(dir) == 0, "a failed write left %d entries in %s", entries(dir), dir);
    /* an existing file is replaced whole */
    FILE *f = fopen(in_dir(path, "keep.xyz"), "w");
    fputs("1 2 3\n", f);
    fclose(f);
    TEST_CHECK(io_write_points(path, v, 4, &e) == IO_OK, "overwrite: %s", e.message);
    double *q;
    size_t m;
    TEST_CHECK(io_read_points(path, &q, &m, &e) == IO_OK && m == 4, "overwritten file wrong");
    free(q);
    remove(path);
}

static void test_mesh_reader_rejects_out_of_range_ids_and_short_files(void)
{
    char path[256], node[256];
    io_error e;
    io_mesh m;
    FILE *f = fopen(in_dir(node, "bad.node"), "w");
    fputs("4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", f);
    fclose(f);
    f = fopen(in_dir(path, "bad.ele"), "w");
    fputs("1 4 0\n1 1 2 3 5\n", f);
    fclose(f);
    TEST_CHECK(io_read_mesh(path, &m, &e) == IO_ERR_INPUT && strstr(e.message, "bad.ele:2:") &&
               strstr(e.message, "vertex id 5"), "out-of-range id: %s", e.message);
    f = fopen(path, "w");
    fputs("3 4 0\n1 1 2 3 4\n", f);
    fclose(f);
    TEST_CHECK(io_read_mesh(path, &m, &e) == IO_ERR_INPUT && strstr(e.message, "claims 3 tets"),
               "short .ele: %s", e.message);
    f = fopen(path, "w");
    fputs("1 4 0\n1 0 1 2 3\n", f);
    fclose(f);
    TEST_CHECK(io_read_mesh(path, &m, &e) == IO_ERR_INPUT && strstr(e.message, "vertex id 0"),
               "0 in a 1-based mesh: %s", e.message);
    remove(node);
    TEST_CHECK(io_read_mesh(path, &m, &e) == IO_ERR_INPUT && strstr(e.message, "bad.node"),
               "missing .node: %s", e.message);
    remove(path);
    TEST_CHECK(io_read_mesh(in_dir(path, "x.vtk"), &m, &e) == IO_ERR_INPUT, "unknown mesh extension");
    f = fopen(in_dir(path, "bad.vtu"), "w");
    fputs("<VTKFile><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n"
          "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0\n1 0 0\n"
          "0 1 0\n0 0 1\n</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" "
          "Name=\"connectivity\" format=\"ascii\">\n0 1 2 4\n</DataArray>\n<DataArray "
          "type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n4\n</DataArray>\n<DataArray "
          "type=\"UInt8\" Name=\"types\" format=\"ascii\">\n10\n</DataArray>\n</Cells>\n"
          "</Piece></UnstructuredGrid></VTKFile>\n", f);
    fclose(f);
    TEST_CHECK(io_read_mesh(path, &m, &e) == IO_ERR_INPUT && strstr(e.message, "bad.vtu:11:") &&
               strstr(e.message, "refers to point 4"), "bad .vtu: %s", e.message);
    remove(path);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/gtet-iow-XXXXXX");
    if (!mkdtemp(dir)) {
        printf("cannot create a temporary directory\n");
        return 1;
    }
    TU_RUN(test_point_writers_read_back_bit_exact_in_every_format);
    TU_RUN(test_mesh_writers_read_back_bit_exact_as_ele_msh_and_vtu);
    TU_RUN(test_ele_files_are_one_based_tetgen_with_17_digit_coordinates);
    TU_RUN(test_vtu_declares_counts_and_tetra_cell_type);
    TU_RUN(test_failed_writes_leave_no_file_and_no_temporary);
    TU_RUN(test_mesh_reader_rejects_out_of_range_ids_and_short_files);
    rmdir(dir);
    return tu_finish();
}
