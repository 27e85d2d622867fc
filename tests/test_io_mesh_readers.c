/* test_io_mesh_readers.c -- the mesh readers (io_read_mesh, io_parse_mesh) read every variant
 * io.h lists to the same arrays, and reject malformed files with IO_ERR_INPUT and a message.
 *
 * One small mesh (6 vertices, 2 tets, sparse unordered node tags in .msh, a point and a
 * triangle element or a triangle cell to be skipped) is written here by hand in each format:
 * TetGen .node/.ele 0- and 1-based with attribute, marker and region columns; Gmsh 4.1 and
 * 2.2, ASCII and binary, with $PhysicalNames, $Entities, a parametric node block and
 * $NodeData; VTU ascii, inline base64 (header and data as one base64 stream or as two),
 * appended raw and base64, UInt32 and UInt64 headers, zlib (stored deflate blocks, several
 * per array, built here so the test needs no zlib of its own), Float32 and Float64 points.
 * Each file is written into a temporary directory and read with io_read_mesh, and its bytes
 * with io_parse_mesh; every prefix of every file must read to the same mesh or fail cleanly.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/io.h"
#include "testutil.h"

/* The reference mesh: coordinates exact in Float32 and in short decimals. */
static const double V[6][3] = {{0, 0, 0},       {1, 0, 0},         {0, 1, 0},
                               {0, 0, 1},       {1.5, 1.25, -0.75}, {0.5, 0.25, -0.125}};
static const uint32_t T[2][4] = {{0, 1, 2, 3}, {5, 2, 1, 4}};
static const uint64_t TAG[6] = {10, 3, 7, 100, 5, 42};   /* .msh node tags */
static char tmpdir[64];

/* ---- a growing byte buffer ---------------------------------------------------------------- */
typedef struct bb { unsigned char *p; size_t n, cap; } bb;

static void put(bb *b, const void *d, size_t n)
{
    if (n > ((size_t)1 << 30) || b->n > ((size_t)1 << 30)) abort();   /* test files are small */
    size_t need = b->n + n + 1;
    if (need > b->cap) {
        size_t cap = 2 * need;
        unsigned char *p = realloc(b->p, cap);
        if (!p) abort();
        b->p = p;
        b->cap = cap;
    }
    if (n) memcpy(b->p + b->n, d, n);
    b->n += n;
    b->p[b->n] = 0;
}

static void pf(bb *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void pf(bb *b, const char *fmt, ...)
{
    char s[512];
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(s, sizeof s, fmt, ap);
    va_end(ap);
    if (k < 0 || (size_t)k >= sizeof s) abort();
    put(b, s, (size_t)k);
}

static void le(bb *b, uint64_t v, size_t w)
{
    unsigned char d[8];
    for (size_t i = 0; i < w; i++) d[i] = (unsigned char)(v >> (8 * i));
    put(b, d, w);
}

static void f64(bb *b, double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    le(b, u, 8);
}

static void b64(bb *out, const unsigned char *d, size_t n)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t w = (uint32_t)d[i] << 16 | (i + 1 < n ? (uint32_t)d[i + 1] << 8 : 0) |
                     (i + 2 < n ? d[i + 2] : 0);
        char q[4] = {a[w >> 18], a[(w >> 12) & 63], i + 1 < n ? a[(w >> 6) & 63] : '=',
                     i + 2 < n ? a[w & 63] : '='};
        put(out, q, 4);
    }
}

/* A zlib stream of one stored (uncompressed) deflate block. */
static void zlib_stored(bb *out, const unsigned char *d, size_t n)
{
    uint32_t s1 = 1, s2 = 0;
    for (size_t i = 0; i < n; i++) {
        s1 = (s1 + d[i]) % 65521;
        s2 = (s2 + s1) % 65521;
    }
    const unsigned char h[3] = {0x78, 0x01, 0x01};
    put(out, h, 3);
    le(out, n, 2);
    le(out, ~n & 0xffff, 2);
    put(out, d, n);
    uint32_t ad = s2 << 16 | s1;
    const unsigned char t[4] = {(unsigned char)(ad >> 24), (unsigned char)(ad >> 16),
                                (unsigned char)(ad >> 8), (unsigned char)ad};
    put(out, t, 4);
}

/* ---- reading and comparing ---------------------------------------------------------------- */

static int same_mesh(const io_mesh *m, size_t skipped)
{
    if (m->nv != 6 || m->nt != 2 || m->skipped_cells != skipped) return 0;
    return memcmp(m->vertices, V, sizeof V) == 0 && memcmp(m->tets, T, sizeof T) == 0;
}

static void write_file(const char *name, const bb *b)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(b->p, 1, b->n, f) != b->n || fclose(f) != 0) abort();
}

/* The file reads to the reference mesh from disk and from memory, and every prefix of it
 * either reads to the same mesh or fails with a message.  Prefixes shorter than must_fail
 * must fail. */
static void expect_mesh(io_format fmt, const char *name, const bb *b, const bb *node,
                        size_t skipped, size_t must_fail)
{
    char path[256];
    io_mesh m;
    io_error e;
    if (fmt != IO_FMT_ELE) {
        write_file(name, b);
        snprintf(path, sizeof path, "%s/%s", tmpdir, name);
        e.message[0] = '\0';
        io_status s = io_read_mesh(path, &m, &e);
        TEST_CHECK(s == IO_OK && same_mesh(&m, skipped), "%s: status %d (%s), nv %zu nt %zu "
                   "skipped %zu", name, s, e.message, m.nv, m.nt, m.skipped_cells);
        io_mesh_free(&m);
    }
    const void *nd = node ? node->p : NULL;
    size_t nn = node ? node->n : 0;
    io_status s = io_parse_mesh(fmt, name, b->p, b->n, nd, nn, &m, &e);
    TEST_CHECK(s == IO_OK && same_mesh(&m, skipped), "%s in memory: status %d (%s)", name, s,
               e.message);
    io_mesh_free(&m);
    size_t bad = 0;
    for (size_t k = 0; k < b->n; k++) {
        e.message[0] = '\0';
        s = io_parse_mesh(fmt, name, b->p, k, nd, nn, &m, &e);
        int ok = (s == IO_OK && same_mesh(&m, skipped)) ||
                 (s == IO_ERR_INPUT && e.message[0] && !m.vertices && !m.tets);
        if (k < must_fail && s == IO_OK) ok = 0;
        if (!ok && bad++ < 3)
            TEST_CHECK(0, "%s cut to %zu bytes: status %d (%s)", name, k, s, e.message);
        io_mesh_free(&m);
    }
}

/* The bytes must fail with IO_ERR_INPUT and a message holding `want`. */
static void expect_fail(io_format fmt, const char *what, const bb *b, const bb *node,
                        const char *want)
{
    io_mesh m;
    io_error e;
    e.message[0] = '\0';
    io_status s = io_parse_mesh(fmt, what, b->p, b->n, node ? node->p : NULL,
                                node ? node->n : 0, &m, &e);
    TEST_CHECK(s == IO_ERR_INPUT && strstr(e.message, want) && strstr(e.message, what),
               "%s: status %d, message '%s' (expected '%s')", what, s, e.message, want);
    TEST_CHECK(!m.vertices && !m.tets && m.nv == 0 && m.nt == 0, "%s: mesh not cleared", what);
    io_mesh_free(&m);
}

static size_t offset_of(const bb *b, const char *s)
{
    size_t l = strlen(s);
    for (size_t i = 0; i + l <= b->n; i++)
        if (memcmp(b->p + i, s, l) == 0) return i;
    return 0;
}

/* ---- TetGen ------------------------------------------------------------------------------- */

static void node_file(bb *n, int base)
{
    pf(n, "# written by hand\n6  3  2  1\n");
    for (int i = 0; i < 6; i++)
        pf(n, "%d %.17g %.17g %.17g 0.5 -7 %d\n", i + base, V[i][0], V[i][1], V[i][2], i % 2 ? -1 : 3);
}

static void test_ele_variants(void)
{
    for (int base = 0; base <= 1; base++) {
        bb n = {0}, e = {0};
        node_file(&n, base);
        pf(&e, "2 4 1\n");
        for (int t = 0; t < 2; t++)
            pf(&e, "%d %u %u %u %u -1.5\n", t + base, T[t][0] + base, T[t][1] + base,
               T[t][2] + base, T[t][3] + base);
        char name[32];
        snprintf(name, sizeof name, "b%d.ele", base);
        expect_mesh(IO_FMT_ELE, name, &e, &n, 0, 0);
        /* on disk, beside its .node */
        snprintf(name, sizeof name, "b%d.node", base);
        write_file(name, &n);
        snprintf(name, sizeof name, "b%d.ele", base);
        write_file(name, &e);
        char path[256];
        snprintf(path, sizeof path, "%s/%s", tmpdir, name);
        io_mesh m;
        io_error er;
        TEST_CHECK(io_read_mesh(path, &m, &er) == IO_OK && same_mesh(&m, 0), "%s: %s", path,
                   er.message);
        io_mesh_free(&m);
        /* MESH.ELE beside MESH.NODE, as tools on case-insensitive file systems write them */
        snprintf(name, sizeof name, "U%d.NODE", base);
        write_file(name, &n);
        snprintf(name, sizeof name, "U%d.ELE", base);
        write_file(name, &e);
        snprintf(path, sizeof path, "%s/%s", tmpdir, name);
        TEST_CHECK(io_read_mesh(path, &m, &er) == IO_OK && same_mesh(&m, 0), "%s: %s", path,
                   er.message);
        io_mesh_free(&m);
        bb bad = {0};
        pf(&bad, "1 4 1\n%d 1 2 3 %d 0\n", base, 7 + base);
        expect_fail(IO_FMT_ELE, "bad.ele", &bad, &n, "vertex id");
        /* NOTES.md E152: a UTF-8 byte order mark before the .ele's and the .node's header */
        bb nb = {0}, eb = {0};
        put(&nb, "\xEF\xBB\xBF", 3), put(&nb, n.p, n.n);
        put(&eb, "\xEF\xBB\xBF", 3), put(&eb, e.p, e.n);
        snprintf(name, sizeof name, "bom%d.ele", base);
        expect_mesh(IO_FMT_ELE, name, &eb, &nb, 0, 0);
        free(nb.p);
        free(eb.p);
        free(n.p);
        free(e.p);
        free(bad.p);
    }
}

/* 10-node tets as TetGen's -o2 writes them: the mid-edge nodes after every corner in the
 * .node.  They are dropped (the corners keep their numbers); a node after them that no tet
 * names (extra 1) is kept, and with it the mid-edge nodes before it; one between the corners
 * and the mid-edge nodes (extra 2) is kept alone. */
static void test_ele_quadratic(void)
{
    for (int base = 0; base <= 1; base++) {
        for (int extra = 0; extra <= 2; extra++) {
            bb n = {0}, e = {0};
            int nv = 6 + 12 + (extra > 0), mid0 = 6 + (extra == 2);
            pf(&n, "%d 3 0 0\n", nv);
            for (int i = 0; i < nv; i++) {
                const double *p = V[i < 6 ? i : i % 6];
                pf(&n, "%d %.17g %.17g %.17g\n", i + base, p[0] + (i >= 6), p[1], p[2]);
            }
            pf(&e, "2 10 1\n");
            for (int t = 0; t < 2; t++) {
                pf(&e, "%d %u %u %u %u", t + base, T[t][0] + base, T[t][1] + base,
                   T[t][2] + base, T[t][3] + base);
                for (int k = 0; k < 6; k++) pf(&e, " %d", mid0 + 6 * t + k + base);
                pf(&e, " -1.5\n");
            }
            char name[32];
            snprintf(name, sizeof name, "q%d%d.ele", base, extra);
            if (!extra) {
                expect_mesh(IO_FMT_ELE, name, &e, &n, 0, 0);
            } else {
                io_mesh m;
                io_error er;
                io_status s = io_parse_mesh(IO_FMT_ELE, name, e.p, e.n, n.p, n.n, &m, &er);
                TEST_CHECK(s == IO_OK && m.nv == (extra == 1 ? 19u : 7u) && m.nt == 2 &&
                           memcmp(m.tets, T, sizeof T) == 0, "%s: status %d (%s), nv %zu",
                           name, s, er.message, m.nv);
                io_mesh_free(&m);
            }
            free(n.p);
            free(e.p);
        }
    }
}

/* ---- Gmsh --------------------------------------------------------------------------------- */

static void msh41_ascii(bb *b)
{
    pf(b, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"a $Nodes name\"\n"
          "$EndPhysicalNames\n$Entities\n1 0 0 1\n1 0 0 0 0\n1 0 0 0 1 1 1 1 1 0\n"
          "$EndEntities\n$Nodes\n2 6 3 100\n3 1 0 4\n");
    for (int i = 0; i < 4; i++) pf(b, "%llu\n", (unsigned long long)TAG[i]);
    for (int i = 0; i < 4; i++) pf(b, "%.17g %.17g %.17g\n", V[i][0], V[i][1], V[i][2]);
    pf(b, "2 1 1 2\n%llu\n%llu\n", (unsigned long long)TAG[4], (unsigned long long)TAG[5]);
    for (int i = 4; i < 6; i++) pf(b, "%.17g %.17g %.17g 0.25 0.75\n", V[i][0], V[i][1], V[i][2]);
    pf(b, "$EndNodes\n$Elements\n3 4 1 4\n0 1 15 1\n1 10\n2 1 2 1\n2 10 3 7\n3 1 4 2\n");
    for (int t = 0; t < 2; t++)
        pf(b, "%d %llu %llu %llu %llu\n", t + 3, (unsigned long long)TAG[T[t][0]],
           (unsigned long long)TAG[T[t][1]], (unsigned long long)TAG[T[t][2]],
           (unsigned long long)TAG[T[t][3]]);
    pf(b, "$EndElements\n$NodeData\n1\n\"t\"\n1\n0.0\n3\n0\n1\n1\n10 1.5\n$EndNodeData\n");
}

static void msh41_binary(bb *b, size_t ds)
{
    pf(b, "$MeshFormat\n4.1 1 %zu\n", ds);
    le(b, 1, 4);
    pf(b, "\n$EndMeshFormat\n$Entities\n");
    le(b, 1, ds), le(b, 0, ds), le(b, 0, ds), le(b, 1, ds);
    le(b, 1, 4), f64(b, 0), f64(b, 0), f64(b, 0), le(b, 0, ds);           /* a point */
    le(b, 1, 4);
    for (int i = 0; i < 6; i++) f64(b, i / 3);
    le(b, 1, ds), le(b, 1, 4), le(b, 0, ds);                             /* the volume */
    pf(b, "\n$EndEntities\n$Nodes\n");
    le(b, 2, ds), le(b, 6, ds), le(b, 3, ds), le(b, 100, ds);
    le(b, 3, 4), le(b, 1, 4), le(b, 0, 4), le(b, 4, ds);
    for (int i = 0; i < 4; i++) le(b, TAG[i], ds);
    for (int i = 0; i < 4; i++) f64(b, V[i][0]), f64(b, V[i][1]), f64(b, V[i][2]);
    le(b, 2, 4), le(b, 1, 4), le(b, 1, 4), le(b, 2, ds);
    le(b, TAG[4], ds), le(b, TAG[5], ds);
    for (int i = 4; i < 6; i++)
        f64(b, V[i][0]), f64(b, V[i][1]), f64(b, V[i][2]), f64(b, 0.25), f64(b, 0.75);
    pf(b, "\n$EndNodes\n$Elements\n");
    le(b, 3, ds), le(b, 4, ds), le(b, 1, ds), le(b, 4, ds);
    le(b, 0, 4), le(b, 1, 4), le(b, 15, 4), le(b, 1, ds), le(b, 1, ds), le(b, 10, ds);
    le(b, 2, 4), le(b, 1, 4), le(b, 2, 4), le(b, 1, ds), le(b, 2, ds);
    le(b, 10, ds), le(b, 3, ds), le(b, 7, ds);
    le(b, 3, 4), le(b, 1, 4), le(b, 4, 4), le(b, 2, ds);
    for (int t = 0; t < 2; t++) {
        le(b, (uint64_t)t + 3, ds);
        for (int c = 0; c < 4; c++) le(b, TAG[T[t][c]], ds);
    }
    pf(b, "\n$EndElements\n");
}

static void msh22(bb *b, int binary, uint32_t tet_type)
{
    pf(b, "$MeshFormat\n2.2 %d 8\n", binary);
    if (binary) le(b, 1, 4), pf(b, "\n");
    pf(b, "$EndMeshFormat\n$Nodes\n6\n");
    for (int i = 0; i < 6; i++) {
        if (binary) le(b, TAG[i], 4), f64(b, V[i][0]), f64(b, V[i][1]), f64(b, V[i][2]);
        else pf(b, "%llu %.17g %.17g %.17g\n", (unsigned long long)TAG[i], V[i][0], V[i][1], V[i][2]);
    }
    pf(b, "%s$EndNodes\n$Elements\n4\n", binary ? "\n" : "");
    if (!binary) {
        pf(b, "1 15 2 0 1 10\n2 2 2 0 1 10 3 7\n");
        for (int t = 0; t < 2; t++)
            pf(b, "%d 4 %s %llu %llu %llu %llu\n", t + 3, t ? "3 1 1 -2" : "2 1 1",
               (unsigned long long)TAG[T[t][0]], (unsigned long long)TAG[T[t][1]],
               (unsigned long long)TAG[T[t][2]], (unsigned long long)TAG[T[t][3]]);
    } else {
        le(b, 15, 4), le(b, 1, 4), le(b, 2, 4), le(b, 1, 4), le(b, 0, 4), le(b, 1, 4), le(b, 10, 4);
        le(b, 2, 4), le(b, 1, 4), le(b, 2, 4), le(b, 2, 4), le(b, 0, 4), le(b, 1, 4);
        le(b, 10, 4), le(b, 3, 4), le(b, 7, 4);
        le(b, tet_type, 4), le(b, 2, 4), le(b, 2, 4);
        for (int t = 0; t < 2; t++) {
            le(b, (uint64_t)t + 3, 4), le(b, 1, 4), le(b, 1, 4);
            for (int c = 0; c < 4; c++) le(b, TAG[T[t][c]], 4);
        }
        pf(b, "\n");
    }
    pf(b, "$EndElements\n");
}

static void test_msh_variants(void)
{
    bb a = {0}, b8 = {0}, b4 = {0}, c = {0}, d = {0};
    msh41_ascii(&a);
    expect_mesh(IO_FMT_MSH, "a41.msh", &a, NULL, 2, offset_of(&a, "$EndElements") + 12);
    msh41_binary(&b8, 8);
    expect_mesh(IO_FMT_MSH, "b41.msh", &b8, NULL, 2, offset_of(&b8, "$EndElements") + 12);
    msh41_binary(&b4, 4);
    expect_mesh(IO_FMT_MSH, "b41_4.msh", &b4, NULL, 2, offset_of(&b4, "$EndElements") + 12);
    msh22(&c, 0, 4);
    expect_mesh(IO_FMT_MSH, "a22.msh", &c, NULL, 2, offset_of(&c, "$EndElements") + 12);
    msh22(&d, 1, 4);
    expect_mesh(IO_FMT_MSH, "b22.msh", &d, NULL, 2, offset_of(&d, "$EndElements") + 12);
    /* NOTES.md E152: a UTF-8 byte order mark before $MeshFormat */
    bb bom = {0};
    put(&bom, "\xEF\xBB\xBF", 3), put(&bom, a.p, a.n);
    expect_mesh(IO_FMT_MSH, "bom41.msh", &bom, NULL, 2, offset_of(&bom, "$EndElements") + 12);
    free(bom.p);
    free(a.p), free(b8.p), free(b4.p), free(c.p), free(d.p);
}

/* Replace the first occurrence of `from` (same length as `to`) in a copy of b. */
static bb patched(const bb *b, const void *from, const void *to, size_t n)
{
    bb c = {0};
    put(&c, b->p, b->n);
    for (size_t i = 0; i + n <= c.n; i++)
        if (memcmp(c.p + i, from, n) == 0) {
            memcpy(c.p + i, to, n);
            break;
        }
    return c;
}

static void test_msh_malformed(void)
{
    bb b = {0}, x;
    msh41_binary(&b, 8);
    /* the $Nodes header's node count (6, after the block count 2) claims 2^60 */
    const unsigned char six[16] = {2, 0, 0, 0, 0, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0};
    unsigned char huge[16] = {2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x10};
    x = patched(&b, six, huge, 16);
    expect_fail(IO_FMT_MSH, "nodes.msh", &x, NULL, "claims 1152921504606846976 nodes");
    free(x.p);
    /* the tet block (dim 3, entity 1, type 4, count 2) claims 2^40 elements */
    const unsigned char blk[12] = {3, 0, 0, 0, 1, 0, 0, 0, 4, 0, 0, 0};
    size_t at = offset_of(&b, "$Elements");
    for (size_t i = at; i + 12 <= b.n; i++)
        if (memcmp(b.p + i, blk, 12) == 0) {
            x = (bb){0};
            put(&x, b.p, b.n);
            x.p[i + 12 + 5] = 1;
            expect_fail(IO_FMT_MSH, "count.msh", &x, NULL, "longer than the rest of the file");
            x.p[i + 12 + 5] = 0;
            x.p[i + 8] = 200;            /* an element type without a node count */
            expect_fail(IO_FMT_MSH, "type.msh", &x, NULL, "element type 200");
            free(x.p);
            break;
        }
    const unsigned char one[4] = {1, 0, 0, 0}, big[4] = {0, 0, 0, 1};
    x = patched(&b, one, big, 4);
    expect_fail(IO_FMT_MSH, "endian.msh", &x, NULL, "big-endian");
    free(x.p);
    free(b.p);
    b = (bb){0};
    msh22(&b, 1, 200);
    expect_fail(IO_FMT_MSH, "type22.msh", &b, NULL, "element type 200");
    free(b.p);
    b = (bb){0};
    msh22(&b, 0, 4);
    x = patched(&b, "3 1 1 -2 42", "3 1 1 -2 99", 11);
    expect_fail(IO_FMT_MSH, "tag.msh", &x, NULL, "node tag 99");
    free(x.p);
    x = patched(&b, "\n100 ", "\n10  ", 5);
    expect_fail(IO_FMT_MSH, "dup.msh", &x, NULL, "node tag 10 appears twice");
    free(x.p);
    x = patched(&b, "2.2 0 8", "4.0 0 8", 7);
    expect_fail(IO_FMT_MSH, "v40.msh", &x, NULL, "MSH version '4.0' is not read");
    free(x.p);
    x = patched(&b, "\n6\n", "\n9\n", 3);
    expect_fail(IO_FMT_MSH, "count22.msh", &x, NULL, "$EndNodes");
    free(x.p);
    free(b.p);
    b = (bb){0};
    pf(&b, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1152921504606846976 1 2\n");
    expect_fail(IO_FMT_MSH, "claim.msh", &b, NULL, "claims");
    free(b.p);
    b = (bb){0};
    pf(&b, "$Nodes\n");
    expect_fail(IO_FMT_MSH, "nofmt.msh", &b, NULL, "$MeshFormat");
    free(b.p);
}

/* ---- VTU ---------------------------------------------------------------------------------- */

enum { ASCII, INLINE, INLINE_SPLIT, APP_RAW, APP_B64 };

typedef struct vtu_opts {
    int mode, hdr64, zlib, f32;
} vtu_opts;

/* The payload of one binary array: header and data (uncompressed), or the block header and
 * the stored-deflate blocks of 10 bytes each (compressed). */
static void payload(const vtu_opts *o, const bb *data, bb *head, bb *body)
{
    size_t w = o->hdr64 ? 8 : 4;
    if (!o->zlib) {
        le(head, data->n, w);
        put(body, data->p, data->n);
        return;
    }
    size_t bs = 10, nb = (data->n + bs - 1) / bs;
    bb blocks[64];
    le(head, nb, w), le(head, bs, w), le(head, data->n % bs, w);
    for (size_t i = 0; i < nb; i++) {
        blocks[i] = (bb){0};
        size_t k = i + 1 < nb || data->n % bs == 0 ? bs : data->n % bs;
        zlib_stored(&blocks[i], data->p + i * bs, k);
        le(head, blocks[i].n, w);
        put(body, blocks[i].p, blocks[i].n);
        free(blocks[i].p);
    }
}

/* The array's values as raw little-endian data, or as ASCII text. */
static void array_data(int which, const vtu_opts *o, bb *d, int ascii)
{
    static const uint64_t conn[11] = {0, 1, 2, 3, 0, 1, 2, 5, 2, 1, 4};
    static const uint64_t offs[3] = {4, 7, 11}, types[3] = {10, 5, 10};
    for (int i = 0; which == 0 && i < 18; i++) {
        double x = V[i / 3][i % 3];
        float f = (float)x;
        uint32_t u32;
        memcpy(&u32, &f, 4);
        if (ascii) pf(d, "%.17g ", x);
        else if (o->f32) le(d, u32, 4);
        else f64(d, x);
    }
    for (int i = 0; which == 1 && i < 11; i++) ascii ? pf(d, "%llu\n", (unsigned long long)conn[i]) : le(d, conn[i], 8);
    for (int i = 0; which == 2 && i < 3; i++) ascii ? pf(d, " %llu", (unsigned long long)offs[i]) : le(d, offs[i], 4);
    for (int i = 0; which == 3 && i < 3; i++) ascii ? pf(d, "%llu ", (unsigned long long)types[i]) : le(d, types[i], 1);
}

static void vtu_file(bb *b, const vtu_opts *o)
{
    static const char *const fmts[5] = {"ascii", "binary", "binary", "appended", "appended"};
    bb app = {0};
    pf(b, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
          "byte_order=\"LittleEndian\" header_type=\"%s\"%s>\n<UnstructuredGrid>\n"
          "<Piece NumberOfCells=\"3\"  NumberOfPoints=\"6\">\n<PointData>\n</PointData>\n",
       o->hdr64 ? "UInt64" : "UInt32", o->zlib ? " compressor=\"vtkZLibDataCompressor\"" : "");
    for (int a = 0; a < 4; a++) {
        const char *type = a == 0 ? (o->f32 ? "Float32" : "Float64") : a == 1 ? "Int64" : a == 2 ? "Int32" : "UInt8";
        if (a == 0) pf(b, "<Points>\n");
        if (a == 1) pf(b, "<Cells>\n");
        pf(b, "<DataArray ");
        /* attribute orders and quotes as different writers use them */
        if (a == 0) pf(b, "type=\"%s\" Name=\"Points\" NumberOfComponents=\"3\"", type);
        if (a == 1) pf(b, "Name=\"connectivity\" type=\"%s\"", type);
        if (a == 2) pf(b, "type='%s' Name='offsets'", type);
        if (a == 3) pf(b, "format=\"%s\" Name=\"types\" type=\"%s\"", fmts[o->mode], type);
        else pf(b, " format=\"%s\"", fmts[o->mode]);
        bb d = {0}, head = {0}, body = {0};
        array_data(a, o, &d, o->mode == ASCII);
        if (o->mode >= APP_RAW) {
            pf(b, " offset=\"%zu\"/>\n", app.n);
            payload(o, &d, &head, &body);
            if (o->mode == APP_RAW) put(&app, head.p, head.n), put(&app, body.p, body.n);
            else b64(&app, head.p, head.n), b64(&app, body.p, body.n);
        } else if (o->mode == ASCII) {
            pf(b, ">\n");
            put(b, d.p, d.n);
            pf(b, "\n</DataArray>\n");
        } else {
            pf(b, ">\n");
            payload(o, &d, &head, &body);
            if (o->mode == INLINE_SPLIT) {
                b64(b, head.p, head.n), b64(b, body.p, body.n);
            } else {
                put(&head, body.p, body.n);
                b64(b, head.p, head.n);
            }
            pf(b, "\n<InformationKey name=\"L2_NORM_RANGE\" location=\"vtkDataArray\" "
                  "length=\"2\"><Value index=\"0\">0</Value></InformationKey>\n</DataArray>\n");
        }
        free(d.p), free(head.p), free(body.p);
        if (a == 0) pf(b, "</Points>\n");
        if (a == 3) pf(b, "</Cells>\n");
    }
    pf(b, "</Piece>\n</UnstructuredGrid>\n");
    if (o->mode >= APP_RAW) {
        pf(b, "<AppendedData encoding=\"%s\">\n   _", o->mode == APP_RAW ? "raw" : "base64");
        put(b, app.p, app.n);
        pf(b, "\n</AppendedData>\n");
    }
    pf(b, "</VTKFile>\n");
    free(app.p);
}

static void test_vtu_variants(void)
{
    static const char *const mode_name[5] = {"ascii", "inline", "split", "raw", "b64"};
    for (int mode = ASCII; mode <= APP_B64; mode++)
        for (int hdr64 = 0; hdr64 <= 1; hdr64++)
            for (int zlib = 0; zlib <= 1; zlib++)
                for (int f32 = 0; f32 <= 1; f32++) {
                    if (mode == ASCII && (hdr64 || zlib || f32)) continue;
                    vtu_opts o = {mode, hdr64, zlib, f32};
                    bb b = {0};
                    char name[64];
                    vtu_file(&b, &o);
                    snprintf(name, sizeof name, "%s_h%d_z%d_f%d.vtu", mode_name[mode],
                             hdr64 ? 64 : 32, zlib, f32 ? 32 : 64);
                    expect_mesh(IO_FMT_VTU, name, &b, NULL, 1, offset_of(&b, "</Cells>"));
                    free(b.p);
                }
}

/* Integer coordinates (meshio writes an integer points array as Int64; VTK reads it): ascii
 * and inline binary, negative values included; one past 2^53 is refused (not a double). */
static void vtu_int_points(bb *b, int binary, int64_t big)
{
    static const int64_t P[4][3] = {{-3, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, -1}};
    pf(b, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
          "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n"
          "<Piece NumberOfCells=\"1\" NumberOfPoints=\"4\">\n<Points>\n<DataArray "
          "type=\"Int64\" Name=\"points\" NumberOfComponents=\"3\" format=\"%s\">\n",
       binary ? "binary" : "ascii");
    if (binary) {
        bb d = {0};
        le(&d, 96, 4);
        for (int i = 0; i < 12; i++) le(&d, (uint64_t)(i == 4 ? big : P[i / 3][i % 3]), 8);
        b64(b, d.p, d.n);
        free(d.p);
    } else {
        for (int i = 0; i < 12; i++) pf(b, "%lld ", (long long)(i == 4 ? big : P[i / 3][i % 3]));
    }
    pf(b, "\n</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
          "format=\"ascii\">0 1 2 3</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" "
          "format=\"ascii\">4</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" "
          "format=\"ascii\">10</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

static void test_vtu_integer_points(void)
{
    for (int binary = 0; binary <= 1; binary++) {
        bb b = {0};
        vtu_int_points(&b, binary, 0);
        io_mesh m;
        io_error e;
        io_status s = io_parse_mesh(IO_FMT_VTU, "int.vtu", b.p, b.n, NULL, 0, &m, &e);
        TEST_CHECK(s == IO_OK && m.nv == 4 && m.nt == 1 && m.vertices[0] == -3 &&
                   m.vertices[7] == 2 && m.vertices[11] == -1, "binary %d: status %d (%s)",
                   binary, s, s == IO_OK ? "" : e.message);
        io_mesh_free(&m);
        free(b.p);
    }
    bb b = {0};
    vtu_int_points(&b, 1, ((int64_t)1 << 53) + 1);
    expect_fail(IO_FMT_VTU, "big.vtu", &b, NULL, "is not a double exactly");
    free(b.p);
}

static void test_vtu_malformed(void)
{
    bb b = {0}, x;
    vtu_opts o = {INLINE, 0, 0, 0};
    vtu_file(&b, &o);
    x = (bb){0};
    put(&x, b.p, b.n);
    x.p[offset_of(&x, "format=\"binary\">\n") + 17] = '*';
    expect_fail(IO_FMT_VTU, "b64.vtu", &x, NULL, "not base64");
    free(x.p);
    x = patched(&b, "LittleEndian", "BigEndian   ", 12);
    expect_fail(IO_FMT_VTU, "be.vtu", &x, NULL, "byte_order \"BigEndian");
    free(x.p);
    free(b.p);
    /* a raw appended header claiming 2^62 bytes */
    b = (bb){0};
    o = (vtu_opts){APP_RAW, 1, 0, 0};
    vtu_file(&b, &o);
    size_t at = offset_of(&b, "   _") + 4;
    x = (bb){0};
    put(&x, b.p, b.n);
    x.p[at + 7] = 0x40;
    expect_fail(IO_FMT_VTU, "huge.vtu", &x, NULL, "its header claims 46116860184273");
    free(x.p);
    free(b.p);
    /* zlib: a block size claiming far more than its compressed bytes, a corrupt stream */
    b = (bb){0};
    o = (vtu_opts){APP_RAW, 0, 1, 0};
    vtu_file(&b, &o);
    at = offset_of(&b, "   _") + 4;
    x = (bb){0};
    put(&x, b.p, b.n);
    x.p[at + 4 + 3] = 0x7f;
    x.p[at + 8 + 3] = 0x7f;
    expect_fail(IO_FMT_VTU, "zhuge.vtu", &x, NULL, "zlib block 0 claims");
    memcpy(x.p, b.p, b.n);
    x.p[at + 4 * (3 + 15) + 3] ^= 0xff;  /* the first block's stored LEN (15 blocks) */
    expect_fail(IO_FMT_VTU, "zbad.vtu", &x, NULL, "zlib block 0 is corrupt");
    free(x.p);
    x = patched(&b, "vtkZLibDataCompressor", "vtkLZ4DataCompressor ", 21);
    expect_fail(IO_FMT_VTU, "lz4.vtu", &x, NULL, "vtkLZ4DataCompressor");
    free(x.p);
    x = patched(&b, "encoding=\"raw\"", "encoding=\"zip\"", 14);
    expect_fail(IO_FMT_VTU, "enc.vtu", &x, NULL, "encoding");
    free(x.p);
    free(b.p);
    /* ASCII: offsets out of order, a 3-point tetra, a vertex id out of range, negative id */
    b = (bb){0};
    o = (vtu_opts){ASCII, 0, 0, 0};
    vtu_file(&b, &o);
    x = patched(&b, " 4 7 11", " 4 3 11", 7);
    expect_fail(IO_FMT_VTU, "offs.vtu", &x, NULL, "cell 1: offsets 4..3");
    free(x.p);
    x = patched(&b, " 4 7 11", " 3 7 11", 7);
    expect_fail(IO_FMT_VTU, "tri.vtu", &x, NULL, "cell 0 is a VTK_TETRA of 3 points");
    free(x.p);
    x = patched(&b, "\n5\n2\n", "\n6\n2\n", 5);
    expect_fail(IO_FMT_VTU, "range.vtu", &x, NULL, "refers to point 6");
    free(x.p);
    x = patched(&b, "\n4\n", "\n-4\n", 3);
    expect_fail(IO_FMT_VTU, "neg.vtu", &x, NULL, "non-negative");
    free(x.p);
    x = patched(&b, "NumberOfPoints=\"6\"", "NumberOfPoints=\"7\"", 18);
    expect_fail(IO_FMT_VTU, "np.vtu", &x, NULL, "NumberOfPoints=\"7\"");
    free(x.p);
    free(b.p);
    b = (bb){0};
    pf(&b, "<VTKFile type=\"PolyData\">");
    expect_fail(IO_FMT_VTU, "poly.vtu", &b, NULL, "UnstructuredGrid");
    free(b.p);
}

int main(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/gtet-meshio-XXXXXX");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    TU_RUN(test_ele_variants);
    TU_RUN(test_ele_quadratic);
    TU_RUN(test_msh_variants);
    TU_RUN(test_msh_malformed);
    TU_RUN(test_vtu_variants);
    TU_RUN(test_vtu_integer_points);
    TU_RUN(test_vtu_malformed);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return tu_finish();
}
