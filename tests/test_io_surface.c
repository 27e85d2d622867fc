/* test_io_surface.c -- the surface readers (.off, .ply faces: src/io/read_off.c, read_ply.c)
 * and io_sample_surface: polygons fanned into triangles, every malformed file an IO_ERR_INPUT
 * with a message naming the problem, samples on the triangles, by area, uniform inside each
 * triangle, reproducible from the seed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/io.h"
#include "testutil.h"

static io_status parse(io_format fmt, const char *text, io_surface *s, io_error *e)
{
    return io_parse_surface(fmt, "t", text, strlen(text), s, e);
}

static void test_off_quads_are_fanned_and_header_variants_read(void)
{
    static const char cube[] =
        "# a comment line\n"
        "OFF 8 6 12\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7  # last face\n";
    io_surface s;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_OFF, cube, &s, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(s.nv == 8 && s.nt == 12, "nv %zu nt %zu", s.nv, s.nt);
    TEST_CHECK(s.tris[0] == 0 && s.tris[1] == 3 && s.tris[2] == 2 && s.tris[3] == 0 &&
                   s.tris[4] == 2 && s.tris[5] == 1, "the fan of the first quad");
    TEST_CHECK(s.vertices[3 * 6] == 1 && s.vertices[3 * 6 + 1] == 1 && s.vertices[3 * 6 + 2] == 1,
               "vertex 6");
    io_surface_free(&s);
    /* COFF with vertex and face colours, counts on the next line, a pentagon */
    static const char coff[] = "COFF\n5 2 0\n\n0 0 0 1 0 0 1\n2 0 0 1 0 0 1\n2 2 0 0 1 0 1\n"
                               "0 2 0 0 0 1 1\n1 3 0 1 1 1 1\n3 0 1 2 0.9 0 0\n"
                               "5 0 1 2 4 3 0 0 0.9 # blue\n";
    TEST_REQUIRE(parse(IO_FMT_OFF, coff, &s, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(s.nv == 5 && s.nt == 4, "COFF: nv %zu nt %zu", s.nv, s.nt);
    io_surface_free(&s);
    /* NOFF, STCNOFF: extra columns dropped */
    TEST_CHECK(parse(IO_FMT_OFF, "STCNOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
                     &s, &e) == IO_OK && s.nt == 1, "STCNOFF: %s", e.message);
    io_surface_free(&s);
}

static void test_bad_off_files_fail_with_a_message(void)
{
    static const struct { const char *text, *msg; } bad[] = {
        {"", "empty file"},
        {"OFF\n", "ends before the counts"},
        {"PLY\n3 1 0\n", "not an OFF file"},
        {"4OFF\n3 1 0\n", "4OFF"},
        {"nOFF\n3 3 1 0\n", "unsupported OFF variant"},
        {"OFF BINARY\n", "binary OFF"},
        {"OFF\n0 0 0\n", "0 vertices"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "out of range"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "fewer than the 3 corner"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "not a non-negative integer"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n", "fewer than 3 coordinates"},
        {"OFF\n3 1\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n", "not finite"},
        {"OFF\n3 1\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "not a number"},
        {"OFF\n3 2\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "ends after 1 of the 2 faces"},
        {"OFF\n4 1\n0 0 0\n1 0 0\n0 1 0\n", "more than the"},
        {"OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "data after the 1 faces"},
        {"OFF\n3 0\n0 0 0\n1 0 0\n0 1 0\n", "no faces"},
        {"OFF\n4000000000 1\n0 0 0\n", "more than the"},
        {"OFF\n3 1 0 9\n", "more than three counts"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        io_surface s;
        io_error e = {0};
        io_status st = parse(IO_FMT_OFF, bad[i].text, &s, &e);
        TEST_CHECK(st == IO_ERR_INPUT && strstr(e.message, bad[i].msg) && s.vertices == NULL &&
                       s.tris == NULL && s.nt == 0,
                   "case %zu: status %d, message '%s' (expected '%s')", i, (int)st, e.message,
                   bad[i].msg);
    }
    /* an OFF point cloud is a point file, not a surface */
    double *xyz;
    size_t n;
    io_error e;
    static const char cloud[] = "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n";
    TEST_CHECK(io_parse_points(IO_FMT_OFF, "c.off", cloud, strlen(cloud), &xyz, &n, &e) == IO_OK &&
                   n == 3 && xyz[3] == 1.0, "OFF as points: %s", e.message);
    free(xyz);
}

static void test_ply_faces_ascii_and_binary(void)
{
    static const char ascii[] =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement edge 1\nproperty int a\nproperty int b\n"
        "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
        "property list uchar float uv\nend_header\n"
        "0 0 0 9\n1 0 0 9\n0 1 0 9\n0 0 1 9\n0 1\n7 3 0 1 2 2 0.5 0.5\n7 4 0 1 3 2 0 0\n";
    io_surface s;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_PLY, ascii, &s, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(s.nv == 4 && s.nt == 3, "nv %zu nt %zu", s.nv, s.nt);
    TEST_CHECK(s.tris[3] == 0 && s.tris[4] == 1 && s.tris[5] == 3 && s.tris[8] == 2, "fan");
    io_surface_free(&s);
    /* binary: 3 float vertices, one face with an int16 count type and uint32 indices */
    unsigned char bin[512];
    const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list ushort uint vertex_index\nend_header\n";
    size_t k = strlen(hdr);
    memcpy(bin, hdr, k);
    const float v[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    for (int i = 0; i < 9; i++) {
        uint32_t w;
        memcpy(&w, &v[i], 4);
        for (int b = 0; b < 4; b++) bin[k++] = (unsigned char)(w >> (8 * b));
    }
    bin[k++] = 3;
    bin[k++] = 0;
    for (uint32_t i = 0; i < 3; i++)
        for (int b = 0; b < 4; b++) bin[k++] = (unsigned char)((2 - i) >> (8 * b));
    TEST_REQUIRE(io_parse_surface(IO_FMT_PLY, "b", bin, k, &s, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(s.nt == 1 && s.tris[0] == 2 && s.tris[2] == 0 && s.vertices[3] == 2.0, "binary");
    io_surface_free(&s);
    TEST_CHECK(io_parse_surface(IO_FMT_PLY, "b", bin, k - 1, &s, &e) == IO_ERR_INPUT &&
                   strstr(e.message, "ends inside face 0"), "short binary: %s", e.message);
    bin[k - 4] = 9; /* the last index: 9 of 3 vertices */
    TEST_CHECK(io_parse_surface(IO_FMT_PLY, "b", bin, k, &s, &e) == IO_ERR_INPUT &&
                   strstr(e.message, "vertex index 9 out of range"), "%s", e.message);
    /* the same file binary_big_endian: every scalar's bytes reversed */
    const char *bhdr = "ply\nformat binary_big_endian    1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list ushort uint vertex_index\nend_header\n";
    TEST_REQUIRE(strlen(bhdr) == strlen(hdr), "header lengths");
    bin[k - 4] = 0;
    memcpy(bin, bhdr, strlen(bhdr));
    size_t at = strlen(hdr);
    static const int sizes[13] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 2, 4, 4, 4};
    for (int i = 0; i < 13; at += (size_t)sizes[i++])
        for (int b = 0; b < sizes[i] / 2; b++) {
            unsigned char t = bin[at + (size_t)b];
            bin[at + (size_t)b] = bin[at + (size_t)sizes[i] - 1 - (size_t)b];
            bin[at + (size_t)sizes[i] - 1 - (size_t)b] = t;
        }
    TEST_REQUIRE(io_parse_surface(IO_FMT_PLY, "b", bin, k, &s, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(s.nt == 1 && s.tris[0] == 2 && s.tris[2] == 0 && s.vertices[3] == 2.0,
               "big-endian");
    io_surface_free(&s);
}

static void test_bad_ply_surfaces_fail_with_a_message(void)
{
    static const char head[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n"
                               "property double y\nproperty double z\n";
    static const struct { const char *rest, *msg; } bad[] = {
        {"end_header\n0 0 0\n1 0 0\n0 1 0\n", "no face element"},
        {"element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1 2\n", "floating-point type"},
        {"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1 3\n", "out of range"},
        {"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n2 0 1\n", "at least 3"},
        {"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1\n", "fewer values"},
        {"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1 2 5\n", "more values"},
        {"element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1 2\n", "ends after 1 of the 2 faces"},
        {"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
         "0 1 0\n3 0 1.5 2\n", "out of range"},
    };
    char buf[1024];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(buf, sizeof buf, "%s%s", head, bad[i].rest);
        io_surface s;
        io_error e = {0};
        io_status st = parse(IO_FMT_PLY, buf, &s, &e);
        TEST_CHECK(st == IO_ERR_INPUT && strstr(e.message, bad[i].msg) && s.vertices == NULL,
                   "case %zu: status %d, '%s' (expected '%s')", i, (int)st, e.message, bad[i].msg);
    }
}

/* Two triangles in the plane z = 0: T0 = (0,0),(1,0),(0,1) of area 1/2, T1 = (2,0),(5,0),
 * (2,1) of area 3/2, and a degenerate one between them (area 0). */
static const char two_tris[] = "OFF\n8 3\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n5 0 0\n2 1 0\n"
                               "1 1 0\n1 1 0\n3 0 1 2\n3 6 7 6\n3 3 4 5\n";

static void test_samples_follow_the_areas_and_are_uniform_in_each_triangle(void)
{
    io_surface s;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_OFF, two_tris, &s, &e) == IO_OK, "%s", e.message);
    size_t n = 40000, in1 = 0, near0 = 0, in0 = 0;
    double *p, *q;
    TEST_REQUIRE(io_sample_surface(&s, "t", n, 7, &p, &e) == IO_OK, "%s", e.message);
    for (size_t i = 0; i < n; i++) {
        double x = p[3 * i], y = p[3 * i + 1];
        TEST_CHECK(p[3 * i + 2] == 0.0 && y >= 0, "point %zu off the plane", i);
        if (x >= 2.0) {
            in1++;
            TEST_CHECK(x <= 5.0 && y <= 1.0 - (x - 2.0) / 3.0 + 1e-15, "point %zu outside T1", i);
        } else {
            in0++;
            TEST_CHECK(x >= 0 && x + y <= 1.0 + 1e-15, "point %zu outside T0", i);
            near0 += x + y < 0.5; /* the corner triangle of a quarter of T0's area */
        }
    }
    /* binomial: sd = sqrt(0.25 * 0.75 / n) = 0.0022; 0.01 is 4.6 sd */
    TEST_CHECK(fabs((double)in1 / (double)n - 0.75) < 0.01, "T1 got %zu of %zu", in1, n);
    TEST_CHECK(fabs((double)near0 / (double)in0 - 0.25) < 0.015, "corner got %zu of %zu", near0,
               in0);
    TEST_REQUIRE(io_sample_surface(&s, "t", n, 7, &q, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(memcmp(p, q, 3 * n * sizeof(double)) == 0, "not reproducible from the seed");
    free(q);
    TEST_REQUIRE(io_sample_surface(&s, "t", n, 8, &q, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(memcmp(p, q, 3 * n * sizeof(double)) != 0, "the seed is ignored");
    free(q);
    free(p);
    TEST_CHECK(io_sample_surface(&s, "t", 0, 1, &p, &e) == IO_ERR_ARGUMENT && !p, "n = 0");
    io_surface_free(&s);
}

static void test_surfaces_without_area_are_refused(void)
{
    io_surface s;
    io_error e;
    double *p;
    TEST_REQUIRE(parse(IO_FMT_OFF, "OFF\n3 1\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n", &s, &e) == IO_OK,
                 "%s", e.message);
    TEST_CHECK(io_sample_surface(&s, "flat", 10, 1, &p, &e) == IO_ERR_INPUT && !p &&
                   strstr(e.message, "zero area"), "%s", e.message);
    io_surface_free(&s);
    TEST_REQUIRE(parse(IO_FMT_OFF, "OFF\n3 1\n0 0 0\n1e300 0 0\n0 1e300 0\n3 0 1 2\n", &s, &e) ==
                     IO_OK, "%s", e.message);
    TEST_CHECK(io_sample_surface(&s, "huge", 10, 1, &p, &e) == IO_ERR_INPUT && !p &&
                   strstr(e.message, "overflows"), "%s", e.message);
    io_surface_free(&s);
}

int main(void)
{
    TU_RUN(test_off_quads_are_fanned_and_header_variants_read);
    TU_RUN(test_bad_off_files_fail_with_a_message);
    TU_RUN(test_ply_faces_ascii_and_binary);
    TU_RUN(test_bad_ply_surfaces_fail_with_a_message);
    TU_RUN(test_samples_follow_the_areas_and_are_uniform_in_each_triangle);
    TU_RUN(test_surfaces_without_area_are_refused);
    return tu_finish();
}
