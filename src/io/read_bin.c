/* read_bin.c -- the .bin point reader: a little-endian uint64 count, then exactly count*3
 * little-endian doubles.
 *
 * The size is checked (count <= (len-8)/24, then len == 8+24*count) before anything is
 * allocated.  Bytes are assembled explicitly, so the reader does not depend on the host's byte
 * order.  io_read_bin_file reads a regular .bin file straight into the point array (decoded in
 * place), so that reading n points needs 24n bytes, not twice that.
 */
#define _POSIX_C_SOURCE 200809L
#include "io_internal.h"
#include "../base/base.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

io_status io_parse_bin(const char *name, const unsigned char *buf, size_t len, double **xyz,
                       size_t *n, io_error *err)
{
    *xyz = NULL;
    *n = 0;
    if (len == 0) return io_fail(err, IO_ERR_INPUT, "%s: empty file (expected a uint64 count)", name);
    if (len < 8)
        return io_fail(err, IO_ERR_INPUT, "%s: %zu bytes, too short for the 8-byte point count",
                       name, len);
    uint64_t count = io_load_le(buf, 8);
    if (count == 0) return io_fail(err, IO_ERR_INPUT, "%s: the header declares 0 points", name);
    if (count > (len - 8) / 24)
        return io_fail(err, IO_ERR_INPUT, "%s: the header claims %llu points, but the file holds "
                       "only %zu bytes of coordinates (%zu points)", name,
                       (unsigned long long)count, len - 8, (len - 8) / 24);
    if (len != 8 + 24 * count)
        return io_fail(err, IO_ERR_INPUT, "%s: %zu bytes after the %llu points the header "
                       "declares (byte offset %llu)", name, len - 8 - 24 * (size_t)count,
                       (unsigned long long)count, (unsigned long long)(8 + 24 * count));
    double *a = base_alloc_big((size_t)count * 3 * sizeof(double));  /* NOTES.md E110 */
    if (!a) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %llu points", name,
                           (unsigned long long)count);
    for (size_t i = 0; i < 3 * (size_t)count; i++) {
        uint64_t u = io_load_le(buf + 8 + 8 * i, 8);
        double d;
        memcpy(&d, &u, 8);
        if (!isfinite(d)) {
            free(a);
            return io_fail(err, IO_ERR_INPUT, "%s: point %zu (byte offset %zu): %c is %s", name,
                           i / 3, 8 + 8 * i, (int)('x' + i % 3), isnan(d) ? "NaN" : "infinite");
        }
        a[i] = d;
    }
    *xyz = a;
    *n = (size_t)count;
    return IO_OK;
}

/* Check the decoded coordinates a[0..3*count) in place: little-endian bytes -> doubles. */
static io_status bin_decode(const char *name, double *a, size_t count, io_error *err)
{
    for (size_t i = 0; i < 3 * count; i++) {
        unsigned char b[8];
        memcpy(b, &a[i], 8);
        uint64_t u = io_load_le(b, 8);
        double d;
        memcpy(&d, &u, 8);
        if (!isfinite(d))
            return io_fail(err, IO_ERR_INPUT, "%s: point %zu (byte offset %zu): %c is %s", name,
                           i / 3, 8 + 8 * i, (int)('x' + i % 3), isnan(d) ? "NaN" : "infinite");
        a[i] = d;
    }
    return IO_OK;
}

static int read_full(int fd, void *buf, size_t len)
{
    unsigned char *p = buf;
    while (len) {
        ssize_t r = read(fd, p, len);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return 0;
        p += r;
        len -= (size_t)r;
    }
    return 1;
}

io_status io_read_bin_file(const char *path, double **xyz, size_t *n, io_error *err)
{
    *xyz = NULL;
    *n = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return io_fail(err, IO_ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        /* directories, pipes: the generic path reports or handles them, on this descriptor
         * (a named pipe opened a second time waited for a second writer: NOTES.md E158) */
        char *buf;
        size_t len;
        io_status s = io_load_fd(fd, path, &buf, &len, err);
        if (s != IO_OK) return s;
        s = io_parse_bin(path, (const unsigned char *)buf, len, xyz, n, err);
        free(buf);
        return s;
    }
    size_t len = (size_t)st.st_size;
    unsigned char h[8];
    io_status s;
    if (len < 8 || !read_full(fd, h, 8)) {
        close(fd);
        /* the in-memory parser words the short-file errors */
        return io_parse_bin(path, h, len < 8 ? len : 0, xyz, n, err);
    }
    uint64_t count = io_load_le(h, 8);
    if (count == 0 || count > (len - 8) / 24 || len != 8 + 24 * count) {
        close(fd);
        /* same checks and messages as io_parse_bin, without reading the data */
        if (count == 0) return io_fail(err, IO_ERR_INPUT, "%s: the header declares 0 points", path);
        if (count > (len - 8) / 24)
            return io_fail(err, IO_ERR_INPUT, "%s: the header claims %llu points, but the file "
                           "holds only %zu bytes of coordinates (%zu points)", path,
                           (unsigned long long)count, len - 8, (len - 8) / 24);
        return io_fail(err, IO_ERR_INPUT, "%s: %zu bytes after the %llu points the header "
                       "declares (byte offset %llu)", path, len - 8 - 24 * (size_t)count,
                       (unsigned long long)count, (unsigned long long)(8 + 24 * count));
    }
    double *a = base_alloc_big((size_t)count * 24);  /* huge pages: NOTES.md E110 */
    if (!a) {
        close(fd);
        return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %llu points", path,
                       (unsigned long long)count);
    }
    if (!read_full(fd, a, (size_t)count * 24)) {
        int e = errno;
        close(fd);
        free(a);
        return io_fail(err, IO_ERR_INPUT, "%s: read error: %s", path, e ? strerror(e) : "short read");
    }
    close(fd);
    if ((s = bin_decode(path, a, (size_t)count, err)) != IO_OK) {
        free(a);
        return s;
    }
    *xyz = a;
    *n = (size_t)count;
    return IO_OK;
}
