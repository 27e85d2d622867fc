/* read_text.c -- the .xyz and TetGen .node point readers.
 *
 * Both are strict: a data line has exactly the columns the format says, every column is a
 * number strtod consumes whole, coordinates are finite.  The .node header's point count is
 * compared with the file size before the point array is allocated: a point line of k columns
 * takes at least 2k bytes (a digit and a separator per column), so a header claiming more
 * than len / 2k points cannot be honest, and 2^60 points are refused without an allocation.
 */
#include "io_internal.h"
#include "../base/base.h"

#include <stdlib.h>

static const char *const coord_name[3] = {"x coordinate", "y coordinate", "z coordinate"};

io_status io_parse_xyz(const char *name, const char *buf, size_t len, double **xyz, size_t *n,
                       io_error *err)
{
    io_text t;
    io_dvec v = {0};
    io_status s = IO_OK;
    io_text_init(&t, name, buf, len);
    *xyz = NULL;
    *n = 0;
    while (io_text_next_line(&t)) {
        size_t k = io_text_count_tokens(&t);
        if (k != 3) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: expected 3 numbers (x y z), found %zu",
                        name, t.line, k);
            goto fail;
        }
        double x[3];
        for (int c = 0; c < 3; c++) {
            const char *ts, *te;
            io_text_token(&t, &ts, &te);
            if ((s = io_text_double(&t, ts, te, coord_name[c], &x[c], err)) != IO_OK) goto fail;
        }
        if ((s = io_dvec_push3(&v, x, name, err)) != IO_OK) goto fail;
    }
    if (v.n == 0) {
        s = io_fail(err, IO_ERR_INPUT, "%s: no points (the file is empty or only comments)",
                    name);
        goto fail;
    }
    *xyz = v.a;
    *n = v.n / 3;
    return IO_OK;
fail:
    free(v.a);
    return s;
}

io_status io_parse_node(const char *name, const char *buf, size_t len, double **xyz,
                        size_t *n, long *first_id, io_error *err)
{
    io_text t;
    io_status s;
    const char *ts, *te;
    uint64_t hdr[4] = {0, 3, 0, 0};
    static const char *const hdr_name[4] = {"the number of points", "the dimension",
                                            "the number of attributes",
                                            "the number of boundary markers"};
    static const uint64_t hdr_max[4] = {UINT64_MAX, 3, 1000, 1};
    double *a = NULL;
    *xyz = NULL;
    *n = 0;
    io_text_init(&t, name, buf, len);
    if (!io_text_next_line(&t))
        return io_fail(err, IO_ERR_INPUT, "%s: no header line (the file is empty or only comments)",
                       name);
    size_t hk = io_text_count_tokens(&t);
    if (hk > 4)
        return io_fail(err, IO_ERR_INPUT,
                       "%s:%zu: the .node header has %zu fields; expected "
                       "'points [dim [attributes [markers]]]'", name, t.line, hk);
    for (size_t i = 0; i < hk; i++) {
        io_text_token(&t, &ts, &te);
        if ((s = io_text_uint(&t, ts, te, hdr_name[i], hdr_max[i], &hdr[i], err)) != IO_OK)
            return s;
    }
    if (hdr[1] != 3)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the dimension is %llu; gigatet needs 3", name,
                       t.line, (unsigned long long)hdr[1]);
    if (hdr[0] == 0)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the header declares 0 points", name, t.line);
    size_t cols = 4 + (size_t)hdr[2] + (size_t)hdr[3];
    if (hdr[0] > len / (2 * cols))
        return io_fail(err, IO_ERR_INPUT,
                       "%s:%zu: the header claims %llu points, more than a file of %zu bytes "
                       "can hold", name, t.line, (unsigned long long)hdr[0], len);
    size_t np = (size_t)hdr[0];
    a = base_alloc_big(np * 3 * sizeof(double));  /* NOTES.md E110 */
    if (!a) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %zu points", name, np);
    long base = 0;
    for (size_t i = 0; i < np; i++) {
        if (!io_text_next_line(&t)) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %zu of the %zu points "
                        "its header declares", name, t.line, i, np);
            goto fail;
        }
        size_t k = io_text_count_tokens(&t);
        if (k != cols) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: expected %zu columns (id x y z%s%s), found %zu",
                        name, t.line, cols, hdr[2] ? " attributes" : "",
                        hdr[3] ? " marker" : "", k);
            goto fail;
        }
        uint64_t id;
        io_text_token(&t, &ts, &te);
        if ((s = io_text_uint(&t, ts, te, "the point id", UINT64_MAX, &id, err)) != IO_OK)
            goto fail;
        if (i == 0) {
            if (id > 1) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the first point id is %llu; expected 0 "
                            "or 1", name, t.line, (unsigned long long)id);
                goto fail;
            }
            base = (long)id;
        } else if (id != (uint64_t)base + i) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: point id %llu out of sequence; expected %llu",
                        name, t.line, (unsigned long long)id,
                        (unsigned long long)((uint64_t)base + i));
            goto fail;
        }
        for (int c = 0; c < 3; c++) {
            io_text_token(&t, &ts, &te);
            if ((s = io_text_double(&t, ts, te, coord_name[c], &a[3 * i + c], err)) != IO_OK)
                goto fail;
        }
        for (size_t c = 4; c < cols; c++) {
            double dummy;
            io_text_token(&t, &ts, &te);
            if ((s = io_text_double(&t, ts, te, c < 4 + hdr[2] ? "an attribute" : "the marker",
                                    &dummy, err)) != IO_OK)
                goto fail;
        }
    }
    if (io_text_next_line(&t)) {
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: data after the %zu points the header declares",
                    name, t.line, np);
        goto fail;
    }
    *xyz = a;
    *n = np;
    *first_id = base;
    return IO_OK;
fail:
    free(a);
    return s;
}
