/* test_io_readers.c -- the point readers accept the formats as documented in io.h, bit-exact,
 * and reject every malformed input with a message that names the file and the line or index.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/io.h"
#include "testutil.h"

/* Parse text; return status, keep the message. */
static io_status parse(io_format f, const char *name, const void *data, size_t len, double **xyz,
                       size_t *n, io_error *e)
{
    memset(e, 0, sizeof *e);
    return io_parse_points(f, name, data, len, xyz, n, e);
}

/* The input must be rejected with IO_ERR_INPUT and a message containing every `want`. */
static void expect_error(io_format f, const void *data, size_t len, const char *want1,
                         const char *want2, int line)
{
    double *xyz = (double *)1;
    size_t n = 7;
    io_error e;
    io_status s = parse(f, "in.dat", data, len, &xyz, &n, &e);
    TEST_CHECK(s == IO_ERR_INPUT, "(case at line %d) status %d, expected IO_ERR_INPUT", line, s);
    TEST_CHECK(xyz == NULL && n == 0, "(case at line %d) outputs not cleared on failure", line);
    TEST_CHECK(strstr(e.message, want1) != NULL, "(case at line %d) message '%s' lacks '%s'", line,
               e.message, want1);
    if (want2)
        TEST_CHECK(strstr(e.message, want2) != NULL, "(case at line %d) message '%s' lacks '%s'",
                   line, e.message, want2);
    free(xyz == (double *)1 ? NULL : xyz);
}
#define REJECT(f, s, w1, w2) expect_error(f, s, sizeof(s) - 1, w1, w2, __LINE__)

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static void test_xyz_reads_comments_blanks_crlf_hex_and_signed_zero(void)
{
    static const char txt[] = "# header comment\n\n  0.1 -0 1e-320\r\n"
                              "\t0x1p-1074   2.5\t7 # trailing comment\n"
                              "   \n-3 4e300 0x1.fffffffffffffp+1023";
    double *p;
    size_t n;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_XYZ, "a.xyz", txt, sizeof txt - 1, &p, &n, &e) == IO_OK, "%s",
                 e.message);
    TEST_REQUIRE(n == 3, "n = %zu, expected 3", n);
    TEST_CHECK(p[3] == 0x1p-1074 && p[5] == 7 && p[6] == -3 && p[8] == 0x1.fffffffffffffp+1023,
               "values read wrong");
    free(p);
}

static void test_xyz_values_are_correctly_rounded_and_bit_exact(void)
{
    static const char txt[] = "0.1 -0 1e-320\n0x1p-1074 2.5 -3\n4e300 0x1.fffffffffffffp+1023 "
                              "0.30000000000000004\n";
    double *p;
    size_t n;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_XYZ, "a.xyz", txt, sizeof txt - 1, &p, &n, &e) == IO_OK, "%s",
                 e.message);
    TEST_REQUIRE(n == 3, "n = %zu", n);
    const double want[9] = {0.1, -0.0, 1e-320, 0x1p-1074, 2.5, -3, 4e300, 0x1.fffffffffffffp+1023,
                            0.30000000000000004};
    for (int i = 0; i < 9; i++)
        TEST_CHECK(same_bits(p[i], want[i]), "coordinate %d is %a, expected %a", i, p[i], want[i]);
    TEST_CHECK(signbit(p[1]), "-0 lost its sign");
    free(p);
}

static void test_xyz_rejects_malformed_lines_naming_file_and_line(void)
{
    REJECT(IO_FMT_XYZ, "1 2 3\n1 2\n", "in.dat:2:", "expected 3 numbers");
    REJECT(IO_FMT_XYZ, "1 2 3 4\n", "in.dat:1:", "found 4");
    REJECT(IO_FMT_XYZ, "# c\n\n1 2 3x\n", "in.dat:3:", "not a number");
    REJECT(IO_FMT_XYZ, "1,2,3\n", "in.dat:1:", "found 1");
    REJECT(IO_FMT_XYZ, "1 2 abc\n", "in.dat:1:", "z coordinate");
    REJECT(IO_FMT_XYZ, "1 2 3\nnan 0 0\n", "in.dat:2:", "not finite");
    REJECT(IO_FMT_XYZ, "0 inf 0\n", "in.dat:1:", "not finite");
    REJECT(IO_FMT_XYZ, "0 0 -infinity\n", "in.dat:1:", "not finite");
    REJECT(IO_FMT_XYZ, "0 1e999 0\n", "in.dat:1:", "overflows");
    REJECT(IO_FMT_XYZ, "", "in.dat", "no points");
    REJECT(IO_FMT_XYZ, "# only\n   \n#comments\n", "in.dat", "no points");
    REJECT(IO_FMT_XYZ, "1 2 3\n4 5\0 6\n", "in.dat:2:", NULL);
    REJECT(IO_FMT_XYZ, "1 2 3\n4 5 6\n7\n", "in.dat:3:", "found 1");
}

static void test_node_reads_zero_and_one_based_with_attributes_and_markers(void)
{
    static const char a[] = "# TetGen\n3 3 2 1\n0 0 0 0 9 9 1\n1 1 0 0 9 9 -1\n"
                            "2 0 1 0.5 9 9 0 # c\n# end\n";
    static const char b[] = "4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
    double *p;
    size_t n;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_NODE, "a.node", a, sizeof a - 1, &p, &n, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(n == 3 && p[3] == 1 && p[8] == 0.5, "0-based .node read wrong (n=%zu)", n);
    free(p);
    TEST_REQUIRE(parse(IO_FMT_NODE, "b.node", b, sizeof b - 1, &p, &n, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(n == 4 && p[11] == 1, "1-based .node with a one-field header read wrong");
    free(p);
}

static void test_node_rejects_bad_headers_ids_and_counts(void)
{
    REJECT(IO_FMT_NODE, "", "in.dat", "no header");
    REJECT(IO_FMT_NODE, "3 2 0 0\n", "in.dat:1:", "dimension");
    REJECT(IO_FMT_NODE, "x 3 0 0\n", "in.dat:1:", "number of points");
    REJECT(IO_FMT_NODE, "0 3 0 0\n", "in.dat:1:", "0 points");
    REJECT(IO_FMT_NODE, "2 3 0 2\n0 0 0 0\n1 1 1 1\n", "in.dat:1:", "boundary markers");
    REJECT(IO_FMT_NODE, "2 3 0 0 7 8\n", "in.dat:1:", "fields");
    REJECT(IO_FMT_NODE, "1152921504606846976 3 0 0\n0 0 0 0\n", "in.dat:1:", "claims 1152921504606846976");
    REJECT(IO_FMT_NODE, "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", "in.dat:5:", "after 4 of the 5");
    REJECT(IO_FMT_NODE, "2 3 0 0\n0 0 0 0\n2 1 0 0\n", "in.dat:3:", "out of sequence");
    REJECT(IO_FMT_NODE, "2 3 0 0\n5 0 0 0\n6 1 0 0\n", "in.dat:2:", "first point id");
    REJECT(IO_FMT_NODE, "2 3 0 1\n0 0 0 0 1\n1 1 0 0\n", "in.dat:3:", "expected 5 columns");
    REJECT(IO_FMT_NODE, "1 3 0 0\n0 0 0 0\n1 1 1 1\n", "in.dat:3:", "data after");
    REJECT(IO_FMT_NODE, "1 3 0 0\n0 0 nan 0\n", "in.dat:2:", "not finite");
    REJECT(IO_FMT_NODE, "1 3 0 0\n-1 0 0 0\n", "in.dat:2:", "point id");
}

static void test_ply_ascii_with_other_properties_and_faces(void)
{
    static const char a[] =
        "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 3\n"
        "property float nx\nproperty double x\nproperty float y\nproperty list uchar int idx\n"
        "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0.1 2 2 7 8 3 255\n0 -0 1 0 0.5 1\n0 1 1 1 5 -7.25 0\n3 0 1 2\n";
    double *p;
    size_t n;
    io_error e;
    TEST_REQUIRE(parse(IO_FMT_PLY, "a.ply", a, sizeof a - 1, &p, &n, &e) == IO_OK, "%s", e.message);
    TEST_REQUIRE(n == 3, "n = %zu", n);
    TEST_CHECK(same_bits(p[0], 0.1) && p[1] == 2 && p[2] == 3, "vertex 0 = %g %g %g", p[0], p[1], p[2]);
    TEST_CHECK(same_bits(p[3], -0.0) && p[5] == 0.5 && p[8] == -7.25, "vertices 1/2 read wrong");
    free(p);
}

/* Little-endian byte writers for the binary cases. */
/* One scalar in the file's byte order (the machine's, little-endian, checked in main; big:
 * reversed). */
static unsigned char *put_order(unsigned char *q, const void *v, size_t size, int big)
{
    const unsigned char *b = v;
    for (size_t i = 0; i < size; i++) q[i] = b[big ? size - 1 - i : i];
    return q + size;
}

static size_t binary_ply_order(unsigned char *buf, uint64_t count, int nan_at, int big)
{
    int l = sprintf((char *)buf,
                    "ply\nformat binary_%s_endian 1.0\nelement material 2\nproperty int id\n"
                    "property list uchar short ks\nelement vertex %llu\nproperty uchar tag\n"
                    "property float x\nproperty double y\nproperty list ushort float w\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n", big ? "big" : "little", (unsigned long long)count);
    unsigned char *q = buf + l;
    for (int m = 0; m < 2; m++) {
        int32_t id = m;
        unsigned char k = (unsigned char)(m + 1);
        q = put_order(q, &id, 4, big);
        q = put_order(q, &k, 1, big);
        for (int j = 0; j < k; j++) {
            int16_t s = (int16_t)-j;
            q = put_order(q, &s, 2, big);
        }
    }
    for (int i = 0; i < 3 && (uint64_t)i < count; i++) {
        unsigned char tag = 9;
        float x = (float)i + 0.1f, z = nan_at == i ? NAN : -1.5f * (float)i;
        double y = 1.0 / 3.0 + i;
        uint16_t nw = (uint16_t)i;
        q = put_order(q, &tag, 1, big);
        q = put_order(q, &x, 4, big);
        q = put_order(q, &y, 8, big);
        q = put_order(q, &nw, 2, big);
        for (int j = 0; j < i; j++) q = put_order(q, &x, 4, big);
        q = put_order(q, &z, 4, big);
    }
    unsigned char three = 3;
    int32_t f[3] = {0, 1, 2};
    q = put_order(q, &three, 1, big);
    for (int j = 0; j < 3; j++) q = put_order(q, &f[j], 4, big);
    return (size_t)(q - buf);
}

static size_t binary_ply(unsigned char *buf, uint64_t count, int nan_at)
{
    return binary_ply_order(buf, count, nan_at, 0);
}

/* The smallest ascii data: one-character values and no newline after the last one (the size
 * check before the allocation counted a separator after it and refused the file). */
static void test_ply_ascii_smallest_data_without_final_newline(void)
{
    static const char txt[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                              "property float y\nproperty float z\nend_header\n"
                              "0 0 0\n1 0 0\n0 1 0\n0 0 1";
    double *p = NULL;
    size_t n = 0;
    io_error e;
    io_status s = parse(IO_FMT_PLY, "min.ply", txt, sizeof txt - 1, &p, &n, &e);
    TEST_CHECK(s == IO_OK && n == 4 && p[3] == 1 && p[11] == 1, "status %d (%s), n %zu", s,
               s == IO_OK ? "" : e.message, n);
    free(p);
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0",
           "in.dat", NULL);
}

/* binary_little_endian, and the same file binary_big_endian (refused before: files from SGI
 * machines and some scanners' tools are big-endian) */
static void test_ply_binary_little_endian_reads_float_and_double_among_lists(void)
{
    for (int big = 0; big <= 1; big++) {
        unsigned char buf[2048];
        size_t len = binary_ply_order(buf, 3, -1, big);
        double *p;
        size_t n;
        io_error e;
        TEST_REQUIRE(parse(IO_FMT_PLY, "b.ply", buf, len, &p, &n, &e) == IO_OK, "big %d: %s",
                     big, e.message);
        TEST_REQUIRE(n == 3, "n = %zu", n);
        for (int i = 0; i < 3; i++) {
            TEST_CHECK(same_bits(p[3 * i], (double)((float)i + 0.1f)), "x of vertex %d = %a", i,
                       p[3 * i]);
            TEST_CHECK(same_bits(p[3 * i + 1], 1.0 / 3.0 + i), "y of vertex %d = %a", i,
                       p[3 * i + 1]);
            TEST_CHECK(p[3 * i + 2] == -1.5 * i, "z of vertex %d = %a", i, p[3 * i + 2]);
        }
        free(p);
        len = binary_ply_order(buf, 3, 1, big);
        expect_error(IO_FMT_PLY, buf, len, "vertex 1", "NaN", __LINE__);
        len = binary_ply_order(buf, 3, -1, big);
        expect_error(IO_FMT_PLY, buf, len - 20, "ends inside vertex 2", NULL, __LINE__);
    }
}

static void test_ply_rejects_bad_headers_counts_and_values(void)
{
    unsigned char buf[2048];
    size_t len = binary_ply(buf, 3, 1);
    expect_error(IO_FMT_PLY, buf, len, "vertex 1", "NaN", __LINE__);
    len = binary_ply(buf, 3, -1);
    expect_error(IO_FMT_PLY, buf, len - 20, "ends inside vertex 2", NULL, __LINE__);
    len = binary_ply(buf, 1152921504606846976ULL, -1);
    expect_error(IO_FMT_PLY, buf, len, "claims 1152921504606846976 vertices", NULL, __LINE__);
    REJECT(IO_FMT_PLY, "", "in.dat", "end_header");
    REJECT(IO_FMT_PLY, "plx\nformat ascii 1.0\nend_header\n", "in.dat:1:", "not a PLY");
    REJECT(IO_FMT_PLY, "ply\nformat binary_middle_endian 1.0\nend_header\n", "in.dat:2:", "unsupported");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
           "end_header\n0 0\n", "in.dat", "lacks property z");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
           "property quad z\nend_header\n0 0 0\n", "in.dat:6:", "unknown property type");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "in.dat", "end_header");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int i\n"
           "end_header\n3 0 1 2\n", "in.dat", "no vertex element");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n0 0 0\n1 1 1            \n", "in.dat:9:", "after 2 of the 3");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n0 0 0\n1 1      \n", "in.dat:9:", "fewer values");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n0 0 0\n1 1 1\n", "in.dat", "claims 3 vertices");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n0 0 0 0\n1 1 1\n", "in.dat:8:", "more values");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n0 inf 0\n", "in.dat:8:", "not finite");
    REJECT(IO_FMT_PLY, "ply\nformat ascii 1.0\nelement vertex 1152921504606846976\nproperty float x\n"
           "property float y\nproperty float z\nend_header\n0 0 0\n", "in.dat", "claims");
}

static size_t bin_file(unsigned char *buf, uint64_t count, size_t points, const double *v)
{
    memcpy(buf, &count, 8);
    memcpy(buf + 8, v, 24 * points);
    return 8 + 24 * points;
}

static void test_bin_round_trips_and_rejects_bad_sizes_and_values(void)
{
    const double v[6] = {0.1, -0.0, 0x1p-1074, 1e308, -2, 3};
    unsigned char buf[256];
    double *p;
    size_t n;
    io_error e;
    size_t len = bin_file(buf, 2, 2, v);
    TEST_REQUIRE(parse(IO_FMT_BIN, "a.bin", buf, len, &p, &n, &e) == IO_OK, "%s", e.message);
    TEST_CHECK(n == 2 && memcmp(p, v, sizeof v) == 0, "bin points differ");
    free(p);
    expect_error(IO_FMT_BIN, buf, 0, "in.dat", "empty", __LINE__);
    expect_error(IO_FMT_BIN, buf, 5, "in.dat", "too short", __LINE__);
    expect_error(IO_FMT_BIN, buf, bin_file(buf, 3, 2, v), "claims 3 points", NULL, __LINE__);
    expect_error(IO_FMT_BIN, buf, bin_file(buf, 1152921504606846976ULL, 2, v),
                 "claims 1152921504606846976 points", NULL, __LINE__);
    expect_error(IO_FMT_BIN, buf, bin_file(buf, 1, 2, v), "24 bytes after the 1 points", NULL, __LINE__);
    expect_error(IO_FMT_BIN, buf, bin_file(buf, 0, 0, v), "0 points", NULL, __LINE__);
    const double w[6] = {0, 0, 0, 1, NAN, 2};
    expect_error(IO_FMT_BIN, buf, bin_file(buf, 2, 2, w), "point 1 (byte offset 40)", "y is NaN", __LINE__);
}

/* The .bin file reader (which reads straight into the point array) says what the in-memory
 * parser says. */
static void test_bin_file_reader_checks_the_size_before_allocating(void)
{
    char dir[] = "/tmp/gtet-iob-XXXXXX";
    TEST_REQUIRE(mkdtemp(dir) != NULL, "mkdtemp failed");
    char path[256];
    snprintf(path, sizeof path, "%s/p.bin", dir);
    const double v[6] = {0.1, -0.0, 0x1p-1074, 1e308, -2, 3}, w[6] = {0, 0, 0, 1, 2, INFINITY};
    struct { uint64_t count; const double *v; size_t pts, cut; int ok; const char *want; } cases[] = {
        {2, v, 2, 0, 1, ""},
        {1152921504606846976ULL, v, 2, 0, 0, "claims 1152921504606846976 points"},
        {3, v, 2, 0, 0, "claims 3 points"},
        {1, v, 2, 0, 0, "24 bytes after the 1 points"},
        {2, w, 2, 0, 0, "point 1 (byte offset 48): z is infinite"},
        {0, v, 0, 0, 0, "0 points"},
        {2, v, 2, 51, 0, "too short"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        unsigned char buf[64];
        size_t len = bin_file(buf, cases[c].count, cases[c].pts, cases[c].v);
        if (cases[c].cut) len -= cases[c].cut;
        FILE *f = fopen(path, "wb");
        fwrite(buf, 1, len, f);
        fclose(f);
        double *p = NULL;
        size_t n = 0;
        io_error e;
        memset(&e, 0, sizeof e);
        io_status s = io_read_points(path, &p, &n, &e);
        if (cases[c].ok)
            TEST_CHECK(s == IO_OK && n == 2 && memcmp(p, v, sizeof v) == 0, "case %zu: %s", c, e.message);
        else
            TEST_CHECK(s == IO_ERR_INPUT && p == NULL && strstr(e.message, cases[c].want) &&
                       strstr(e.message, path), "case %zu: '%s' lacks '%s'", c, e.message, cases[c].want);
        free(p);
    }
    remove(path);
    rmdir(dir);
}

static void test_read_points_rejects_missing_file_directory_and_unknown_extension(void)
{
    char dir[] = "/tmp/gtet-io-XXXXXX";
    TEST_REQUIRE(mkdtemp(dir) != NULL, "mkdtemp failed");
    char path[256];
    double *p;
    size_t n;
    io_error e;
    snprintf(path, sizeof path, "%s/missing.xyz", dir);
    TEST_CHECK(io_read_points(path, &p, &n, &e) == IO_ERR_INPUT && strstr(e.message, path),
               "missing file: %s", e.message);
    snprintf(path, sizeof path, "%s/sub.xyz", dir);
    mkdir(path, 0700);
    TEST_CHECK(io_read_points(path, &p, &n, &e) == IO_ERR_INPUT && strstr(e.message, "directory"),
               "directory: %s", e.message);
    rmdir(path);
    snprintf(path, sizeof path, "%s/points.txt", dir);
    FILE *f = fopen(path, "w");
    fputs("1 2 3\n", f);
    fclose(f);
    TEST_CHECK(io_read_points(path, &p, &n, &e) == IO_ERR_INPUT && strstr(e.message, "extension"),
               "unknown extension: %s", e.message);
    remove(path);
    snprintf(path, sizeof path, "%s/p.XYZ", dir);
    f = fopen(path, "w");
    fputs("1 2 3\n4 5 6\n", f);
    fclose(f);
    TEST_CHECK(io_read_points(path, &p, &n, &e) == IO_OK && n == 2, "upper-case .XYZ: %s", e.message);
    free(p);
    remove(path);
    rmdir(dir);
}

/* NOTES.md E152: a UTF-8 byte order mark (EF BB BF) at the start of a text file, as Windows
 * editors write it, is skipped; before, the first number read as '???0.5' and failed. */
static void test_text_formats_skip_a_utf8_byte_order_mark(void)
{
    static const struct { io_format f; const char *txt; } cases[] = {
        {IO_FMT_XYZ, "\xEF\xBB\xBF" "0.5 0 0\n1 0 0\n0 1 0\n0 0 1\n"},
        {IO_FMT_NODE, "\xEF\xBB\xBF" "4 3 0 0\n1 0.5 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"},
        {IO_FMT_OFF, "\xEF\xBB\xBF" "OFF\n4 0 0\n0.5 0 0\n1 0 0\n0 1 0\n0 0 1\n"},
        {IO_FMT_PLY, "\xEF\xBB\xBF" "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n0.5 0 0\n1 0 0\n0 1 0\n0 0 1\n"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double *p = NULL;
        size_t n = 0;
        io_error e;
        io_status s = parse(cases[k].f, "bom.txt", cases[k].txt, strlen(cases[k].txt), &p, &n, &e);
        TEST_CHECK(s == IO_OK, "case %zu: %s", k, e.message);
        TEST_CHECK(s != IO_OK || (n == 4 && p[0] == 0.5 && p[11] == 1), "case %zu: read wrong", k);
        free(p);
    }
    /* only at the very start: a BOM inside the data is still junk */
    REJECT(IO_FMT_XYZ, "0 0 0\n\xEF\xBB\xBF" "1 0 0\n", "in.dat:2: x coordinate is not a number",
           NULL);
}

/* UTF-16 and UTF-32 text (Windows PowerShell's `>` writes UTF-16LE with its byte order mark)
 * is refused naming the encoding; before, the first token was quoted as '??0?'. */
static void test_text_formats_name_a_utf16_or_utf32_file(void)
{
    REJECT(IO_FMT_XYZ, "\xFF\xFE" "0\0 \0" "0\0 \0" "0\0\n\0", "in.dat: the file is UTF-16LE text",
           "iconv -f UTF-16 -t UTF-8");
    REJECT(IO_FMT_NODE, "\xFE\xFF" "\0" "4", "in.dat: the file is UTF-16BE text", NULL);
    REJECT(IO_FMT_OFF, "\xFF\xFE\0\0" "O\0\0\0", "in.dat: the file is UTF-32LE text",
           "iconv -f UTF-32 -t UTF-8");
    REJECT(IO_FMT_PLY, "\0\0\xFE\xFF" "\0\0\0p", "in.dat: the file is UTF-32BE text", NULL);
    /* the mesh readers too (.ele and its .node, .msh, .vtu) */
    static const char node[] = "4 3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
    static const char u16[] = "\xFF\xFE" "1\0 \0" "4\0";
    static const struct { io_format f; const char *name, *d, *n; size_t dl, nl; } m[] = {
        {IO_FMT_ELE, "u.ele", u16, node, sizeof u16 - 1, sizeof node - 1},
        {IO_FMT_ELE, "u.ele", "1 4\n1 1 2 3 4\n", u16, 14, sizeof u16 - 1},
        {IO_FMT_MSH, "u.msh", u16, NULL, sizeof u16 - 1, 0},
        {IO_FMT_VTU, "u.vtu", u16, NULL, sizeof u16 - 1, 0},
    };
    for (size_t k = 0; k < sizeof m / sizeof m[0]; k++) {
        io_mesh mesh;
        io_error e;
        io_status s = io_parse_mesh(m[k].f, m[k].name, m[k].d, m[k].dl, m[k].n, m[k].nl, &mesh,
                                    &e);
        TEST_CHECK(s == IO_ERR_INPUT && strstr(e.message, "the file is UTF-16LE text") &&
                   strstr(e.message, k == 1 ? "u.node" : m[k].name), "case %zu: status %d, '%s'",
                   k, s, e.message);
        io_mesh_free(&mesh);
    }
}

/* NOTES.md E153: a PLY element without properties (legal; its items have no bytes, and in
 * ascii no values) before the vertex element: binary skipped it item by item (2^64 items: a
 * loop only the optimiser removed), ascii took vertex lines for its items. */
static void test_ply_elements_without_properties(void)
{
    static const char asc[] = "ply\nformat ascii 1.0\nelement empty 2\nelement vertex 4\n"
                              "property double x\nproperty double y\nproperty double z\n"
                              "end_header\n\n\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    double *p = NULL;
    size_t n = 0;
    io_error e;
    io_status s = parse(IO_FMT_PLY, "a.ply", asc, sizeof asc - 1, &p, &n, &e);
    TEST_CHECK(s == IO_OK && n == 4 && p[3] == 1 && p[7] == 1 && p[11] == 1, "ascii: %s",
               s == IO_OK ? "read wrong" : e.message);
    free(p);
    static const char hdr[] = "ply\nformat binary_little_endian 1.0\n"
                              "element empty 18446744073709551615\nelement vertex 4\n"
                              "property double x\nproperty double y\nproperty double z\nend_header\n";
    unsigned char bin[sizeof hdr - 1 + 12 * 8];
    memcpy(bin, hdr, sizeof hdr - 1);
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(bin + sizeof hdr - 1, v, sizeof v);
    s = parse(IO_FMT_PLY, "b.ply", bin, sizeof bin, &p, &n, &e);
    TEST_CHECK(s == IO_OK && n == 4 && p[3] == 1 && p[11] == 1, "binary: %s",
               s == IO_OK ? "read wrong" : e.message);
    free(p);
}

int main(void)
{
    const uint16_t one = 1;
    if (*(const unsigned char *)&one != 1) {
        printf("SKIP: the binary test inputs are built for a little-endian host\n");
        return 77;
    }
    TU_RUN(test_xyz_reads_comments_blanks_crlf_hex_and_signed_zero);
    TU_RUN(test_xyz_values_are_correctly_rounded_and_bit_exact);
    TU_RUN(test_xyz_rejects_malformed_lines_naming_file_and_line);
    TU_RUN(test_node_reads_zero_and_one_based_with_attributes_and_markers);
    TU_RUN(test_node_rejects_bad_headers_ids_and_counts);
    TU_RUN(test_ply_ascii_with_other_properties_and_faces);
    TU_RUN(test_ply_ascii_smallest_data_without_final_newline);
    TU_RUN(test_ply_binary_little_endian_reads_float_and_double_among_lists);
    TU_RUN(test_ply_rejects_bad_headers_counts_and_values);
    TU_RUN(test_bin_round_trips_and_rejects_bad_sizes_and_values);
    TU_RUN(test_bin_file_reader_checks_the_size_before_allocating);
    TU_RUN(test_read_points_rejects_missing_file_directory_and_unknown_extension);
    TU_RUN(test_text_formats_skip_a_utf8_byte_order_mark);
    TU_RUN(test_text_formats_name_a_utf16_or_utf32_file);
    TU_RUN(test_ply_elements_without_properties);
    return tu_finish();
}
