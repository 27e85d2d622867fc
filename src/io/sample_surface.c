/* sample_surface.c -- triangle meshes (io_read_surface, io_parse_surface: the dispatch to
 * read_off.c and read_ply.c) and points sampled uniformly by area on them
 * (io_sample_surface, the `surface` generator kind).
 *
 * Sampling: the triangles' areas |(b-a) x (c-a)| / 2 are summed into a cumulative table
 * cum[i] = area[0] + .. + area[i] (in order, so the table is the same bits on every run).
 * A point draws r uniform in [0, total) and takes the first triangle with cum[i] > r (binary
 * search): triangle i has probability area[i] / total up to the rounding of the table, and a
 * triangle of zero area is never taken (its interval [cum[i-1], cum[i]) is empty).  In the
 * triangle, s = sqrt(u1) and the weights (1 - s, s (1 - u2), s u2) with u1, u2 uniform in
 * [0, 1) give a point uniform in it (the density of s is 2s, the area element of the
 * triangle's sweep from a).  The point is a convex combination computed in binary64, so it
 * lies on the triangle's plane within a few ulps of the coordinates.  The random bits are
 * splitmix64's from the seed (generate.c), and the arithmetic is IEEE with contraction off
 * (the root CMakeLists.txt), sqrt correctly rounded: the same (mesh, n, seed) gives the same
 * bits on every machine.
 */
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void io_surface_free(io_surface *s)
{
    if (!s) return;
    free(s->vertices);
    free(s->tris);
    memset(s, 0, sizeof *s);
}

static io_status unknown_surface(io_error *err, const char *name)
{
    char list[128];
    return io_fail(err, IO_ERR_INPUT, "%s: unknown surface mesh extension (%s are read)", name,
                   io_format_list(IO_READ_SURFACE, 0, list, sizeof list));
}

static io_status parse_nul(io_format fmt, const char *name, const char *buf, size_t len,
                           io_surface *s, io_error *err)
{
    io_status st;
    if ((st = io_text_encoding(name, buf, len, err)) != IO_OK) return st;
    switch (fmt) {
    case IO_FMT_OFF: st = io_parse_off(name, buf, len, s, err); break;
    case IO_FMT_PLY: st = io_parse_ply_surface(name, buf, len, s, err); break;
    default: return unknown_surface(err, name);
    }
    if (st == IO_OK && s->nt == 0)
        return io_fail(err, IO_ERR_INPUT, "%s: the file has vertices but no faces: a point "
                       "cloud, not a surface", name);
    return st;
}

io_status io_parse_surface(io_format fmt, const char *name, const void *data, size_t len,
                           io_surface *s, io_error *err)
{
    memset(s, 0, sizeof *s);
    char *copy = len < SIZE_MAX ? malloc(len + 1) : NULL;
    if (!copy) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", name);
    if (len) memcpy(copy, data, len);
    copy[len] = '\0';
    io_status st = parse_nul(fmt, name, copy, len, s, err);
    free(copy);
    if (st != IO_OK) io_surface_free(s);
    return st;
}

io_status io_read_surface(const char *path, io_surface *s, io_error *err)
{
    memset(s, 0, sizeof *s);
    io_format fmt = io_format_of(path);
    if (!io_format_can(fmt, IO_READ_SURFACE)) return unknown_surface(err, path);
    char *buf;
    size_t len;
    io_status st = io_load_file(path, &buf, &len, err);
    if (st != IO_OK) return st;
    st = parse_nul(fmt, path, buf, len, s, err);
    free(buf);
    if (st != IO_OK) io_surface_free(s);
    return st;
}

/* Twice the area of triangle t: |(b - a) x (c - a)|. */
static double area2(const io_surface *s, size_t t)
{
    const double *a = s->vertices + 3 * (size_t)s->tris[3 * t],
                 *b = s->vertices + 3 * (size_t)s->tris[3 * t + 1],
                 *c = s->vertices + 3 * (size_t)s->tris[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
           z = u[0] * v[1] - u[1] * v[0];
    return sqrt(x * x + y * y + z * z);
}

/* The cumulative table of twice the areas; *last = the last triangle of non-zero area. */
static io_status cumulate(const io_surface *s, const char *name, double *cum, size_t *last,
                          io_error *err)
{
    double sum = 0.0;
    *last = SIZE_MAX;
    for (size_t t = 0; t < s->nt; t++) {
        double a = area2(s, t);
        if (!isfinite(a) || !isfinite(sum + a))
            return io_fail(err, IO_ERR_INPUT, "%s: the area of triangle %zu (or the total up to "
                           "it) overflows a double", name, t);
        if (a > 0.0) *last = t;
        sum += a;
        cum[t] = sum;
    }
    if (*last == SIZE_MAX)
        return io_fail(err, IO_ERR_INPUT, "%s: every one of the %zu triangles has zero area: "
                       "nothing to sample", name, s->nt);
    return IO_OK;
}

static double unit(uint64_t *st) { return (double)(io_splitmix64(st) >> 11) * 0x1p-53; }

/* The first t with cum[t] > r, or `last` when rounding put r at the total. */
static size_t pick(const double *cum, size_t nt, size_t last, double r)
{
    size_t lo = 0, hi = nt;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cum[mid] > r) hi = mid;
        else lo = mid + 1;
    }
    return lo < nt ? lo : last;
}

io_status io_sample_surface(const io_surface *s, const char *name, size_t n, uint64_t seed,
                            double **xyz, io_error *err)
{
    *xyz = NULL;
    if (n < 1 || n > (size_t)UINT32_MAX)
        return io_fail(err, IO_ERR_ARGUMENT, "the number of points must be in 1..%u", UINT32_MAX);
    if (s->nt < 1) return io_fail(err, IO_ERR_INPUT, "%s: the mesh has no triangle", name);
    double *cum = malloc(s->nt * sizeof(double));
    double *a = malloc(n * 3 * sizeof(double));
    size_t last = 0;
    io_status st = !cum || !a ? io_fail(err, IO_ERR_NOMEM, "out of memory for %zu points", n)
                              : cumulate(s, name, cum, &last, err);
    if (st != IO_OK) {
        free(cum);
        free(a);
        return st;
    }
    uint64_t rs = seed;
    double total = cum[s->nt - 1];
    for (size_t i = 0; i < n; i++) {
        size_t t = pick(cum, s->nt, last, unit(&rs) * total);
        double r = sqrt(unit(&rs)), u2 = unit(&rs);
        double w[3] = {1.0 - r, r * (1.0 - u2), r * u2};
        for (int d = 0; d < 3; d++) {
            double x = 0.0;
            for (int k = 0; k < 3; k++) x += w[k] * s->vertices[3 * (size_t)s->tris[3 * t + (size_t)k] + (size_t)d];
            a[3 * i + (size_t)d] = x;
        }
    }
    free(cum);
    *xyz = a;
    return IO_OK;
}
