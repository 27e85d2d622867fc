/* fuzz_readers.c -- libFuzzer target: the point-file parsers of src/io on arbitrary bytes.
 *
 * data[0] % 4 picks the format (.xyz, .node, .ply, .bin); the rest is the file's content,
 * handed to io_parse_points, the same parser io_read_points runs on a file.  Properties
 * (src/io/io.h): never a crash, a leak or undefined behaviour (ASan + UBSan + LeakSanitizer
 * watch); the result is either IO_OK with n >= 1 finite points, or an error status with a
 * non-empty message, *xyz == NULL and *n == 0.  Allocations are bounded by the input size
 * (a header claiming 2^60 points is checked against the bytes present first), which
 * libFuzzer's -rss_limit_mb / -malloc_limit_mb enforce.
 */
#include "fuzz_common.h"

#include "io/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    double *xyz = NULL;
    size_t n = 12345;
    io_error err;
    err.message[0] = '\0';
    io_status st = io_parse_points((io_format)(IO_FMT_XYZ + data[0] % 4), "fuzz", data + 1,
                                   size - 1, &xyz, &n, &err);
    if (st == IO_OK) {
        FZ_ASSERT(xyz != NULL && n >= 1, "IO_OK with xyz=%p n=%zu", (void *)xyz, n);
        for (size_t i = 0; i < 3 * n; i++)
            FZ_ASSERT(isfinite(xyz[i]), "IO_OK with a non-finite coordinate at %zu", i);
    } else {
        FZ_ASSERT(xyz == NULL && n == 0, "status %d with xyz=%p n=%zu", (int)st, (void *)xyz, n);
        FZ_ASSERT(st == IO_ERR_INPUT || st == IO_ERR_NOMEM || st == IO_ERR_ARGUMENT,
                  "unexpected status %d", (int)st);
        FZ_ASSERT(err.message[0] != '\0' && memchr(err.message, '\0', sizeof err.message),
                  "status %d without a message", (int)st);
    }
    free(xyz);
    return 0;
}
