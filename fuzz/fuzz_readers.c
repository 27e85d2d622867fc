/* fuzz_readers.c -- libFuzzer target: the point-file and surface parsers of src/io on
 * arbitrary bytes.
 *
 * data[0] % 8 picks what is parsed: 0-3 the point formats .xyz, .node, .ply, .bin and 4 .off
 * (io_parse_points, the parser io_read_points runs on a file); 5 .off and 6 .ply as surfaces
 * (io_parse_surface, as io_read_surface), 7 an .off surface then 16 points sampled on it
 * (io_sample_surface).  The rest is the file's content.  Properties (src/io/io.h): never a
 * crash, a leak or undefined behaviour (ASan + UBSan + LeakSanitizer watch); the result is
 * either IO_OK with n >= 1 finite points (a surface: triangles with in-range ids; samples:
 * finite), or an error status with a non-empty message and nothing returned.  Allocations
 * are bounded by the input size (a header claiming 2^60 points is checked against the bytes
 * present first), which libFuzzer's -rss_limit_mb / -malloc_limit_mb enforce.
 */
#include "fuzz_common.h"

#include "io/io.h"

static void check_failure(io_status st, const io_error *err)
{
    FZ_ASSERT(st == IO_ERR_INPUT || st == IO_ERR_NOMEM || st == IO_ERR_ARGUMENT,
              "unexpected status %d", (int)st);
    FZ_ASSERT(err->message[0] != '\0' && memchr(err->message, '\0', sizeof err->message),
              "status %d without a message", (int)st);
}

static void surface(io_format fmt, int sample, const uint8_t *data, size_t size)
{
    io_surface s;
    io_error err;
    err.message[0] = '\0';
    io_status st = io_parse_surface(fmt, "fuzz", data, size, &s, &err);
    if (st != IO_OK) {
        FZ_ASSERT(s.vertices == NULL && s.tris == NULL && s.nt == 0, "status %d with data", (int)st);
        check_failure(st, &err);
        return;
    }
    FZ_ASSERT(s.nv >= 1 && s.nt >= 1, "IO_OK with nv=%zu nt=%zu", s.nv, s.nt);
    for (size_t i = 0; i < 3 * s.nt; i++) FZ_ASSERT(s.tris[i] < s.nv, "id %u out of range", s.tris[i]);
    for (size_t i = 0; i < 3 * s.nv; i++) FZ_ASSERT(isfinite(s.vertices[i]), "non-finite vertex");
    if (sample) {
        double *xyz = NULL;
        err.message[0] = '\0';
        st = io_sample_surface(&s, "fuzz", 16, 1, &xyz, &err);
        if (st == IO_OK)
            for (size_t i = 0; i < 48; i++) FZ_ASSERT(isfinite(xyz[i]), "non-finite sample");
        else
            check_failure(st, &err);
        free(xyz);
    }
    io_surface_free(&s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    int sel = data[0] % 8;
    if (sel >= 5) {
        surface(sel == 6 ? IO_FMT_PLY : IO_FMT_OFF, sel == 7, data + 1, size - 1);
        return 0;
    }
    double *xyz = NULL;
    size_t n = 12345;
    io_error err;
    err.message[0] = '\0';
    io_format fmt = sel == 4 ? IO_FMT_OFF : (io_format)(IO_FMT_XYZ + sel);
    io_status st = io_parse_points(fmt, "fuzz", data + 1, size - 1, &xyz, &n, &err);
    if (st == IO_OK) {
        FZ_ASSERT(xyz != NULL && n >= 1, "IO_OK with xyz=%p n=%zu", (void *)xyz, n);
        for (size_t i = 0; i < 3 * n; i++)
            FZ_ASSERT(isfinite(xyz[i]), "IO_OK with a non-finite coordinate at %zu", i);
    } else {
        FZ_ASSERT(xyz == NULL && n == 0, "status %d with xyz=%p n=%zu", (int)st, (void *)xyz, n);
        check_failure(st, &err);
    }
    free(xyz);
    return 0;
}
