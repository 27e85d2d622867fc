/* read_off.c -- the Geomview OFF surface reader (what it accepts: io.h).
 *
 * The file is read as lines of tokens (io_text: '#' starts a comment, blank lines are
 * skipped): the keyword [ST][C][N]OFF, alone or followed by the counts "nv nf [ne]" on its
 * line; nv vertex lines whose first three tokens are x y z (colour, normal and texture
 * columns after them are dropped); nf face lines "k i1 .. ik" (a face colour after the
 * indices is dropped); nothing after the last face.  A polygon is fanned from its first
 * corner while it is read (k - 2 triangles, no array of its corners), so a face of any size
 * costs no memory beyond its triangles.  The vertex array is allocated only after nv was
 * checked against the bytes left (a vertex line takes at least 5 bytes: "0 0 0").
 */
#include "io_internal.h"

#include <stdlib.h>
#include <string.h>

io_status io_tvec_push3(io_tvec *v, uint32_t a, uint32_t b, uint32_t c, const char *name,
                        io_error *err)
{
    if (v->n + 3 > v->cap) {
        size_t nc = v->cap ? v->cap * 2 : 3 * 1024;
        uint32_t *na = nc > SIZE_MAX / sizeof(uint32_t) ? NULL : realloc(v->a, nc * sizeof(uint32_t));
        if (!na) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory after %zu triangles", name,
                                v->n / 3);
        v->a = na;
        v->cap = nc;
    }
    v->a[v->n++] = a;
    v->a[v->n++] = b;
    v->a[v->n++] = c;
    return IO_OK;
}

/* The keyword: [ST][C][N]OFF, in this order, each prefix at most once. */
static io_status off_keyword(const io_text *t, const char *ts, const char *te, io_error *err)
{
    size_t n = (size_t)(te - ts);
    const char *q = ts;
    if (n >= 2 && q[0] == 'S' && q[1] == 'T') q += 2;
    if (q < te && *q == 'C') q++;
    if (q < te && *q == 'N') q++;
    if (te - q == 3 && memcmp(q, "OFF", 3) == 0) return IO_OK;
    if (n >= 3 && memcmp(te - 3, "OFF", 3) == 0)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: unsupported OFF variant '%.*s' (only 3D "
                       "[ST][C][N]OFF is read; 4OFF and nOFF are not)", t->name, t->line,
                       (int)(n > 40 ? 40 : n), ts);
    return io_fail(err, IO_ERR_INPUT, "%s:%zu: not an OFF file (the first word is not OFF)",
                   t->name, t->line);
}

/* The header: keyword, then nv nf [ne] on the same line or the next. */
static io_status off_header(io_text *t, uint64_t *nv, uint64_t *nf, io_error *err)
{
    const char *ts, *te;
    io_status s;
    if (!io_text_next_line(t) || !io_text_token(t, &ts, &te))
        return io_fail(err, IO_ERR_INPUT, "%s: empty file (expected the keyword OFF)", t->name);
    if ((s = off_keyword(t, ts, te, err)) != IO_OK) return s;
    if (!io_text_token(t, &ts, &te)) {
        if (!io_text_next_line(t) || !io_text_token(t, &ts, &te))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends before the counts nv nf ne",
                           t->name, t->line);
    } else if (te - ts == 6 && memcmp(ts, "BINARY", 6) == 0) {
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: binary OFF is not read (only text)", t->name,
                       t->line);
    }
    if ((s = io_text_uint(t, ts, te, "the vertex count", UINT32_MAX, nv, err)) != IO_OK) return s;
    if (!io_text_token(t, &ts, &te))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the face count is missing", t->name, t->line);
    if ((s = io_text_uint(t, ts, te, "the face count", UINT64_MAX, nf, err)) != IO_OK) return s;
    uint64_t ne;
    if (io_text_token(t, &ts, &te) &&
        (s = io_text_uint(t, ts, te, "the edge count", UINT64_MAX, &ne, err)) != IO_OK)
        return s;
    if (io_text_token(t, &ts, &te))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: more than three counts (nv nf ne)", t->name,
                       t->line);
    if (*nv == 0) return io_fail(err, IO_ERR_INPUT, "%s:%zu: the OFF file declares 0 vertices",
                                 t->name, t->line);
    return IO_OK; /* nf == 0: a point cloud, which io_parse_surface refuses */
}

static io_status off_vertices(io_text *t, double *a, uint64_t nv, io_error *err)
{
    static const char *const cn[3] = {"x", "y", "z"};
    for (uint64_t i = 0; i < nv; i++) {
        if (!io_text_next_line(t))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %llu of the %llu "
                           "vertices the header declares", t->name, t->line,
                           (unsigned long long)i, (unsigned long long)nv);
        for (int c = 0; c < 3; c++) {
            const char *ts, *te;
            if (!io_text_token(t, &ts, &te))
                return io_fail(err, IO_ERR_INPUT, "%s:%zu: vertex %llu has fewer than 3 "
                               "coordinates", t->name, t->line, (unsigned long long)i);
            io_status s = io_text_double(t, ts, te, cn[c], &a[3 * i + (size_t)c], err);
            if (s != IO_OK) return s;
        }
    }
    return IO_OK;
}

/* One face line: k, then k indices below nv, fanned into k - 2 triangles. */
static io_status off_face(io_text *t, uint64_t f, uint64_t nv, io_tvec *tv, io_error *err)
{
    const char *ts, *te;
    uint64_t k, id, first = 0, prev = 0;
    io_status s;
    if (!io_text_token(t, &ts, &te)) return IO_ERR_INPUT; /* not reached: the line has a token */
    if ((s = io_text_uint(t, ts, te, "the corner count", UINT32_MAX, &k, err)) != IO_OK) return s;
    if (k < 3)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: face %llu has %llu corners (at least 3)",
                       t->name, t->line, (unsigned long long)f, (unsigned long long)k);
    for (uint64_t j = 0; j < k; j++) {
        if (!io_text_token(t, &ts, &te))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: face %llu has fewer than the %llu corner "
                           "indices it declares", t->name, t->line, (unsigned long long)f,
                           (unsigned long long)k);
        if ((s = io_text_uint(t, ts, te, "a vertex index", UINT32_MAX, &id, err)) != IO_OK) return s;
        if (id >= nv)
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: face %llu: vertex index %llu out of range "
                           "(%llu vertices)", t->name, t->line, (unsigned long long)f,
                           (unsigned long long)id, (unsigned long long)nv);
        if (j == 0) first = id;
        if (j >= 2 && (s = io_tvec_push3(tv, (uint32_t)first, (uint32_t)prev, (uint32_t)id,
                                         t->name, err)) != IO_OK)
            return s;
        prev = id;
    }
    return IO_OK; /* tokens after the indices: a face colour, dropped */
}

io_status io_parse_off(const char *name, const char *buf, size_t len, io_surface *out,
                       io_error *err)
{
    io_text t;
    uint64_t nv, nf;
    io_status s;
    io_text_init(&t, name, buf, len);
    if ((s = off_header(&t, &nv, &nf, err)) != IO_OK) return s;
    if (nv > (size_t)(t.end - t.p) / 5)
        return io_fail(err, IO_ERR_INPUT, "%s: the header claims %llu vertices, more than the "
                       "%zu bytes after it can hold", name, (unsigned long long)nv,
                       (size_t)(t.end - t.p));
    out->vertices = malloc((size_t)nv * 3 * sizeof(double));
    if (!out->vertices)
        return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %llu vertices", name,
                       (unsigned long long)nv);
    out->nv = (size_t)nv;
    if ((s = off_vertices(&t, out->vertices, nv, err)) != IO_OK) return s;
    io_tvec tv = {0};
    for (uint64_t f = 0; f < nf && s == IO_OK; f++) {
        if (!io_text_next_line(&t)) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %llu of the %llu faces "
                        "the header declares", name, t.line, (unsigned long long)f,
                        (unsigned long long)nf);
            break;
        }
        s = off_face(&t, f, nv, &tv, err);
    }
    if (s == IO_OK && io_text_next_line(&t))
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: data after the %llu faces the header declares",
                    name, t.line, (unsigned long long)nf);
    out->tris = tv.a;
    out->nt = tv.n / 3;
    return s;
}
