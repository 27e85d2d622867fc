/* read_ply.c -- the .ply point reader (ascii, binary little- and big-endian) and the PLY surface
 * reader (faces, for sampling; io_parse_ply_surface), after ply_header.c has parsed the header.
 *
 * Only the element named "vertex" is read for points; its properties x, y, z (any scalar
 * type, converted exactly to double) are kept and everything else is skipped.  Elements
 * before the vertex element are skipped item by item (lists have variable size); an element
 * without properties has no bytes and, in ascii, only blank lines, which the text reader
 * skips anyway (NOTES.md E153: its items are not counted off lines); elements after the
 * vertex element (faces) are ignored.  Before the point array is allocated, the declared vertex
 * count is checked against the bytes that follow the header: a binary vertex takes at least
 * the sum of its scalar sizes (a list at least its count field), an ascii vertex at least 2
 * bytes per property.
 */
#include "ply.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Skip one binary property value (a scalar or a whole list) at *pos; 0 when it runs past len. */
static int bin_skip_prop(const ply_prop *pr, const unsigned char *b, size_t len, size_t *pos,
                         int big)
{
    size_t is = (size_t)ply_type_size(pr->type);
    if (pr->count_type < 0) {
        if (len - *pos < is) return 0;
        *pos += is;
        return 1;
    }
    size_t cs = (size_t)ply_type_size(pr->count_type);
    if (len - *pos < cs) return 0;
    double c = ply_bin_value(pr->count_type, b + *pos, big);
    *pos += cs;
    if (c < 0 || c > (double)((len - *pos) / is)) return 0;
    *pos += (size_t)c * is;
    return 1;
}

static int bin_skip_item(const ply_element *e, const unsigned char *b, size_t len, size_t *pos,
                         int big)
{
    for (int j = 0; j < e->nprops; j++)
        if (!bin_skip_prop(&e->props[j], b, len, pos, big)) return 0;
    return 1;
}

/* The vertices; *at: where the data starts, then where the vertex element ends. */
static io_status ply_binary(const char *name, const unsigned char *b, size_t len,
                            const ply_header *h, double *a, size_t *at, io_error *err)
{
    size_t pos = *at;
    for (int i = 0; i < h->vertex; i++)
        for (uint64_t k = 0; k < h->el[i].count && h->el[i].nprops; k++)
            if (!bin_skip_item(&h->el[i], b, len, &pos, h->binary == 2))
                return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside element '%s' item %llu",
                               name, h->el[i].name, (unsigned long long)k);
    const ply_element *e = &h->el[h->vertex];
    for (uint64_t i = 0; i < e->count; i++) {
        for (int j = 0; j < e->nprops; j++) {
            const ply_prop *pr = &e->props[j];
            if (pr->coord >= 0) {
                size_t sz = (size_t)ply_type_size(pr->type);
                if (len - pos < sz) goto short_file;
                double v = ply_bin_value(pr->type, b + pos, h->binary == 2);
                if (!isfinite(v))
                    return io_fail(err, IO_ERR_INPUT, "%s: vertex %llu (byte offset %zu): %c is %s",
                                   name, (unsigned long long)i, pos, 'x' + pr->coord,
                                   isnan(v) ? "NaN" : "infinite");
                a[3 * i + (size_t)pr->coord] = v;
                pos += sz;
            } else if (!bin_skip_prop(pr, b, len, &pos, h->binary == 2)) {
                goto short_file;
            }
        }
        continue;
    short_file:
        return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside vertex %llu of %llu", name,
                       (unsigned long long)i, (unsigned long long)e->count);
    }
    *at = pos;
    return IO_OK;
}

/* The vertices, read through *tp (set at the data by the caller; left after them). */
static io_status ply_ascii(const char *name, const ply_header *h, double *a, io_text *tp,
                           io_error *err)
{
    io_text t = *tp;
    io_status s;
    for (int i = 0; i < h->vertex; i++)
        for (uint64_t k = 0; k < h->el[i].count && h->el[i].nprops; k++)
            if (!io_text_next_line(&t))
                return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends inside element '%s'",
                               name, t.line, h->el[i].name);
    const ply_element *e = &h->el[h->vertex];
    static const char *const cn[3] = {"x", "y", "z"};
    for (uint64_t i = 0; i < e->count; i++) {
        if (!io_text_next_line(&t))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %llu of the %llu "
                           "vertices the header declares", name, t.line, (unsigned long long)i,
                           (unsigned long long)e->count);
        const char *ts, *te;
        for (int j = 0; j < e->nprops; j++) {
            const ply_prop *pr = &e->props[j];
            uint64_t items = 1;
            if (!io_text_token(&t, &ts, &te)) goto few;
            if (pr->count_type >= 0) {
                if ((s = io_text_uint(&t, ts, te, "a list count", 1000000, &items, err)) != IO_OK)
                    return s;
                for (uint64_t q = 0; q < items; q++) {
                    double dummy;
                    if (!io_text_token(&t, &ts, &te)) goto few;
                    if ((s = io_text_double(&t, ts, te, "a list item", &dummy, err)) != IO_OK)
                        return s;
                }
            } else {
                double v;
                if ((s = io_text_double(&t, ts, te, pr->coord >= 0 ? cn[pr->coord] : "a property",
                                        &v, err)) != IO_OK)
                    return s;
                if (pr->coord >= 0) a[3 * i + (size_t)pr->coord] = v;
            }
        }
        if (io_text_token(&t, &ts, &te))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: vertex %llu has more values than its %d "
                           "properties", name, t.line, (unsigned long long)i, e->nprops);
        continue;
    few:
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: vertex %llu has fewer values than its %d "
                       "properties", name, t.line, (unsigned long long)i, e->nprops);
    }
    *tp = t;
    return IO_OK;
}

/* Where the reading stands after the vertices: a byte offset (binary) or a text cursor. */
typedef struct ply_cursor {
    size_t pos;
    io_text t;
} ply_cursor;

/* The vertex array of a parsed header (*xyz malloc'ed), and the cursor after the vertices. */
static io_status ply_vertices(const char *name, const char *buf, size_t len, const ply_header *h,
                              double **xyz, ply_cursor *c, io_error *err)
{
    const ply_element *e = &h->el[h->vertex];
    size_t min = 0;
    for (int j = 0; j < e->nprops; j++) {
        const ply_prop *pr = &e->props[j];
        min += h->binary ? (size_t)ply_type_size(pr->count_type >= 0 ? pr->count_type : pr->type) : 2;
    }
    /* an ascii value takes 2 bytes with its separator, and the file's last value none: 4
     * vertices "0 0 0\n...0 0 1" without a final newline are 23 bytes, not 24 */
    if (e->count > (len - h->data + !h->binary) / min)
        return io_fail(err, IO_ERR_INPUT, "%s: the header claims %llu vertices, more than the %zu "
                       "bytes after it can hold", name, (unsigned long long)e->count, len - h->data);
    double *a = malloc((size_t)e->count * 3 * sizeof(double));
    if (!a)
        return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %llu vertices", name,
                       (unsigned long long)e->count);
    c->pos = h->data;
    io_text_init(&c->t, name, buf + h->data, len - h->data);
    c->t.line = h->lines;
    io_status s = h->binary ? ply_binary(name, (const unsigned char *)buf, len, h, a, &c->pos, err)
                            : ply_ascii(name, h, a, &c->t, err);
    if (s != IO_OK) {
        free(a);
        return s;
    }
    *xyz = a;
    return IO_OK;
}

io_status io_parse_ply(const char *name, const char *buf, size_t len, double **xyz, size_t *n,
                       io_error *err)
{
    *xyz = NULL;
    *n = 0;
    ply_header *h = malloc(sizeof *h);
    if (!h) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", name);
    ply_cursor c;
    io_status s = ply_parse_header(name, buf, len, h, err);
    if (s == IO_OK && (s = ply_vertices(name, buf, len, h, xyz, &c, err)) == IO_OK)
        *n = (size_t)h->el[h->vertex].count;
    free(h);
    return s;
}

/* ---- faces (io_parse_ply_surface) ----
 * One face's index list is fanned from its first corner while it is read: corner j >= 2
 * gives the triangle (first, previous, j).  `where` names the line (text) or byte offset. */
typedef struct ply_fan {
    const char *name;
    char where[48];
    uint64_t face, nv, j;
    uint32_t first, prev;
} ply_fan;

static io_status fan_start(ply_fan *f, uint64_t face, double k, io_error *err)
{
    f->face = face;
    f->j = 0;
    if (k < 3)
        return io_fail(err, IO_ERR_INPUT, "%s%s: face %llu has %g corners (at least 3)", f->name,
                       f->where, (unsigned long long)face, k);
    return IO_OK;
}

static io_status fan_add(ply_fan *f, double v, io_tvec *tv, io_error *err)
{
    if (!(v >= 0.0 && v < (double)f->nv && v == floor(v)))
        return io_fail(err, IO_ERR_INPUT, "%s%s: face %llu: vertex index %g out of range (%llu "
                       "vertices)", f->name, f->where, (unsigned long long)f->face, v,
                       (unsigned long long)f->nv);
    uint32_t id = (uint32_t)v;
    io_status s = IO_OK;
    if (f->j == 0) f->first = id;
    if (f->j >= 2) s = io_tvec_push3(tv, f->first, f->prev, id, f->name, err);
    f->prev = id;
    f->j++;
    return s;
}

static io_status faces_binary(const unsigned char *b, size_t len, const ply_header *h,
                              size_t pos, ply_fan *f, io_tvec *tv, io_error *err)
{
    for (int i = h->vertex + 1; i < h->face; i++)
        for (uint64_t k = 0; k < h->el[i].count && h->el[i].nprops; k++)
            if (!bin_skip_item(&h->el[i], b, len, &pos, h->binary == 2))
                return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside element '%s' item %llu",
                               f->name, h->el[i].name, (unsigned long long)k);
    const ply_element *e = &h->el[h->face];
    const ply_prop *fp = &e->props[h->face_prop];
    size_t is = (size_t)ply_type_size(fp->type), cs = (size_t)ply_type_size(fp->count_type);
    io_status s;
    for (uint64_t i = 0; i < e->count; i++)
        for (int j = 0; j < e->nprops; j++) {
            if (j != h->face_prop) {
                if (!bin_skip_prop(&e->props[j], b, len, &pos, h->binary == 2)) goto short_file;
                continue;
            }
            if (len - pos < cs) goto short_file;
            snprintf(f->where, sizeof f->where, " (byte offset %zu)", pos);
            double k = ply_bin_value(fp->count_type, b + pos, h->binary == 2);
            pos += cs;
            if ((s = fan_start(f, i, k, err)) != IO_OK) return s;
            if (k > (double)((len - pos) / is)) goto short_file;
            for (uint64_t q = 0; q < (uint64_t)k; q++, pos += is)
                if ((s = fan_add(f, ply_bin_value(fp->type, b + pos, h->binary == 2), tv, err)) !=
                    IO_OK)
                    return s;
            continue;
        short_file:
            return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside face %llu of %llu",
                           f->name, (unsigned long long)i, (unsigned long long)e->count);
        }
    return IO_OK;
}

/* One text face line: every property of the face element, the index list fanned. */
static io_status face_line_ascii(io_text *t, const ply_element *e, int fprop, uint64_t i,
                                 ply_fan *f, io_tvec *tv, io_error *err)
{
    const char *ts, *te;
    io_status s;
    snprintf(f->where, sizeof f->where, ":%zu", t->line);
    for (int j = 0; j < e->nprops; j++) {
        uint64_t items = 1;
        if (!io_text_token(t, &ts, &te)) goto few;
        if (e->props[j].count_type >= 0) {
            if ((s = io_text_uint(t, ts, te, "a list count", UINT32_MAX, &items, err)) != IO_OK)
                return s;
            if (j == fprop && (s = fan_start(f, i, (double)items, err)) != IO_OK) return s;
            if (!io_text_token(t, &ts, &te) && items) goto few;
        }
        for (uint64_t q = 0; q < items; q++) {
            double v;
            if (q && !io_text_token(t, &ts, &te)) goto few;
            if ((s = io_text_double(t, ts, te, j == fprop ? "a vertex index" : "a property", &v,
                                    err)) != IO_OK)
                return s;
            if (j == fprop && (s = fan_add(f, v, tv, err)) != IO_OK) return s;
        }
    }
    if (io_text_token(t, &ts, &te))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: face %llu has more values than its %d "
                       "properties", t->name, t->line, (unsigned long long)i, e->nprops);
    return IO_OK;
few:
    return io_fail(err, IO_ERR_INPUT, "%s:%zu: face %llu has fewer values than its properties "
                   "declare", t->name, t->line, (unsigned long long)i);
}

static io_status faces_ascii(io_text *t, const ply_header *h, ply_fan *f, io_tvec *tv,
                             io_error *err)
{
    for (int i = h->vertex + 1; i < h->face; i++)
        for (uint64_t k = 0; k < h->el[i].count && h->el[i].nprops; k++)
            if (!io_text_next_line(t))
                return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends inside element '%s'",
                               t->name, t->line, h->el[i].name);
    const ply_element *e = &h->el[h->face];
    for (uint64_t i = 0; i < e->count; i++) {
        if (!io_text_next_line(t))
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %llu of the %llu faces "
                           "the header declares", t->name, t->line, (unsigned long long)i,
                           (unsigned long long)e->count);
        io_status s = face_line_ascii(t, e, h->face_prop, i, f, tv, err);
        if (s != IO_OK) return s;
    }
    return IO_OK;
}

/* What a surface needs of the header: a face element after the vertex element, with an
 * integer index list. */
static io_status ply_surface_header(const char *name, const ply_header *h, io_error *err)
{
    if (h->face < 0 || h->face_prop < 0)
        return io_fail(err, IO_ERR_INPUT, "%s: the PLY header declares no face element with a "
                       "vertex_indices list: a point cloud, not a surface", name);
    if (h->face < h->vertex)
        return io_fail(err, IO_ERR_INPUT, "%s: the face element comes before the vertex element "
                       "(not read)", name);
    if (ply_type_float(h->el[h->face].props[h->face_prop].type))
        return io_fail(err, IO_ERR_INPUT, "%s: the face list vertex_indices has a floating-point "
                       "type", name);
    return IO_OK;
}

io_status io_parse_ply_surface(const char *name, const char *buf, size_t len, io_surface *out,
                               io_error *err)
{
    ply_header *h = malloc(sizeof *h);
    if (!h) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", name);
    ply_cursor c;
    io_status s = ply_parse_header(name, buf, len, h, err);
    if (s == IO_OK) s = ply_surface_header(name, h, err);
    if (s == IO_OK) s = ply_vertices(name, buf, len, h, &out->vertices, &c, err);
    if (s == IO_OK) {
        out->nv = (size_t)h->el[h->vertex].count;
        ply_fan f = {.name = name, .nv = out->nv};
        io_tvec tv = {0};
        s = h->binary ? faces_binary((const unsigned char *)buf, len, h, c.pos, &f, &tv, err)
                      : faces_ascii(&c.t, h, &f, &tv, err);
        out->tris = tv.a;
        out->nt = tv.n / 3;
    }
    free(h);
    return s;
}
