/* read_ply.c -- the .ply point reader (ascii and binary_little_endian) and the .bin reader.
 *
 * PLY: the header is parsed line by line up to "end_header"; it declares elements with
 * their counts and properties (scalars of the eight PLY types, or lists).  Only the element
 * named "vertex" is read; its properties x, y, z (any scalar type, converted exactly to
 * double) are kept and everything else is skipped.  Elements before the vertex element are
 * skipped item by item (lists have variable size); elements after it (faces) are ignored.
 * Before the point array is allocated, the declared vertex count is checked against the
 * bytes that follow the header: a binary vertex takes at least the sum of its scalar sizes
 * (a list at least its count field), an ascii vertex at least 2 bytes per property.
 *
 * .bin: a little-endian uint64 count, then exactly count*3 little-endian doubles.  The size
 * is checked (count <= (len-8)/24, then len == 8+24*count) before anything is allocated.
 * Bytes are assembled explicitly, so the readers do not depend on the host's byte order.
 * io_read_bin_file reads a regular .bin file straight into the point array (decoded in
 * place), so that reading n points needs 24n bytes, not twice that.
 */
#define _POSIX_C_SOURCE 200809L
#include "io_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

enum { PLY_MAX_ELEMENTS = 32, PLY_MAX_PROPS = 256 };

typedef struct ply_prop {
    int type;       /* scalar type, or the item type of a list */
    int count_type; /* list: type of the count; -1 for a scalar */
    int coord;      /* 0, 1, 2 for x, y, z; -1 otherwise */
} ply_prop;

typedef struct ply_element {
    char name[32];
    uint64_t count;
    int nprops;
    ply_prop props[PLY_MAX_PROPS];
} ply_element;

static const struct { const char *name; int size; char kind; } ply_types[] = {
    {"char", 1, 's'},   {"uchar", 1, 'u'},  {"short", 2, 's'},   {"ushort", 2, 'u'},
    {"int", 4, 's'},    {"uint", 4, 'u'},   {"float", 4, 'f'},   {"double", 8, 'f'},
    {"int8", 1, 's'},   {"uint8", 1, 'u'},  {"int16", 2, 's'},   {"uint16", 2, 'u'},
    {"int32", 4, 's'},  {"uint32", 4, 'u'}, {"float32", 4, 'f'}, {"float64", 8, 'f'},
};

static int ply_type(const char *s, size_t len)
{
    for (int i = 0; i < (int)(sizeof ply_types / sizeof ply_types[0]); i++)
        if (strlen(ply_types[i].name) == len && memcmp(ply_types[i].name, s, len) == 0) return i;
    return -1;
}

/* Value of a little-endian binary scalar of type ty at p, as a double (exact for every type:
 * the integers have at most 32 bits, floats widen exactly). */
static double le_value(int ty, const unsigned char *p)
{
    int size = ply_types[ty].size;
    uint64_t u = io_load_le(p, (size_t)size);
    switch (ply_types[ty].kind) {
    case 'u': return (double)u;
    case 's': {
        int64_t sv = (int64_t)(u << (64 - 8 * size)) >> (64 - 8 * size);
        return (double)sv;
    }
    default:
        if (size == 4) {
            uint32_t w = (uint32_t)u;
            float f;
            memcpy(&f, &w, 4);
            return (double)f;
        } else {
            double d;
            memcpy(&d, &u, 8);
            return d;
        }
    }
}

/* One header line [ls, le) split into up to 6 words. */
static int words(const char *ls, const char *le, const char *w[6], size_t wl[6])
{
    int k = 0;
    const char *q = ls;
    while (q < le && k < 6) {
        while (q < le && (*q == ' ' || *q == '\t' || *q == '\r')) q++;
        if (q >= le) break;
        w[k] = q;
        while (q < le && *q != ' ' && *q != '\t' && *q != '\r') q++;
        wl[k] = (size_t)(q - w[k]);
        k++;
    }
    return k;
}

static int word_is(const char *w, size_t wl, const char *s)
{
    return strlen(s) == wl && memcmp(w, s, wl) == 0;
}

typedef struct ply_header {
    int binary;
    int nel, vertex;        /* element count, index of the vertex element */
    int face, face_prop;    /* the "face" element and its vertex_indices list, or -1 */
    size_t data;            /* offset of the first data byte */
    size_t lines;           /* header lines */
    ply_element el[PLY_MAX_ELEMENTS];
} ply_header;

/* The words of one header line, and where it is (for messages). */
typedef struct ply_line {
    const char *name;
    size_t line;
    int k;
    const char *w[6];
    size_t wl[6];
} ply_line;

/* At most 40 bytes of word i, for messages. */
#define PLY_WORD(l, i) (int)((l)->wl[i] > 40 ? 40 : (l)->wl[i]), (l)->w[i]

static io_status ply_format_line(const ply_line *l, ply_header *h, io_error *err)
{
    if (l->k != 3 || !word_is(l->w[2], l->wl[2], "1.0"))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: malformed format line", l->name, l->line);
    if (word_is(l->w[1], l->wl[1], "ascii")) h->binary = 0;
    else if (word_is(l->w[1], l->wl[1], "binary_little_endian")) h->binary = 1;
    else
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: unsupported PLY format '%.*s' (ascii and "
                       "binary_little_endian are read)", l->name, l->line, PLY_WORD(l, 1));
    return IO_OK;
}

static io_status ply_element_line(const ply_line *l, ply_header *h, io_error *err)
{
    if (l->k != 3)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: malformed element line", l->name, l->line);
    if (h->nel == PLY_MAX_ELEMENTS)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: more than %d elements", l->name, l->line,
                       PLY_MAX_ELEMENTS);
    ply_element *e = &h->el[h->nel];
    io_text t = {.name = l->name, .line = l->line};
    if (io_text_uint(&t, l->w[2], l->w[2] + l->wl[2], "the element count", UINT64_MAX,
                     &e->count, err) != IO_OK)
        return IO_ERR_INPUT;
    size_t nl = l->wl[1] < sizeof e->name ? l->wl[1] : sizeof e->name - 1;
    memcpy(e->name, l->w[1], nl);
    e->name[nl] = '\0';
    e->nprops = 0;
    if (word_is(l->w[1], l->wl[1], "vertex")) {
        if (h->vertex >= 0)
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: a second vertex element", l->name, l->line);
        h->vertex = h->nel;
    }
    if (word_is(l->w[1], l->wl[1], "face") && h->face < 0) h->face = h->nel;
    h->nel++;
    return IO_OK;
}

static io_status ply_property_line(const ply_line *l, ply_header *h, io_error *err)
{
    if (h->nel == 0)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: a property before any element", l->name, l->line);
    ply_element *e = &h->el[h->nel - 1];
    if (e->nprops == PLY_MAX_PROPS)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: more than %d properties", l->name, l->line,
                       PLY_MAX_PROPS);
    ply_prop *pr = &e->props[e->nprops];
    int last;   /* the word that names the property */
    if (l->k == 5 && word_is(l->w[1], l->wl[1], "list")) {
        pr->count_type = ply_type(l->w[2], l->wl[2]);
        pr->type = ply_type(l->w[3], l->wl[3]);
        if (pr->count_type < 0 || pr->type < 0 || ply_types[pr->count_type].kind == 'f')
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: malformed list property", l->name, l->line);
        last = 4;
    } else if (l->k == 3) {
        pr->count_type = -1;
        pr->type = ply_type(l->w[1], l->wl[1]);
        if (pr->type < 0)
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: unknown property type '%.*s'", l->name,
                           l->line, PLY_WORD(l, 1));
        last = 2;
    } else {
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: malformed property line", l->name, l->line);
    }
    const char *pn = l->w[last];
    pr->coord = -1;
    if (l->wl[last] == 1 && (*pn == 'x' || *pn == 'y' || *pn == 'z') && h->vertex == h->nel - 1) {
        int c = *pn - 'x';
        for (int i = 0; i < e->nprops; i++)
            if (e->props[i].coord == c)
                return io_fail(err, IO_ERR_INPUT, "%s:%zu: property %c declared twice", l->name,
                               l->line, *pn);
        if (pr->count_type >= 0)
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: property %c is a list", l->name, l->line, *pn);
        pr->coord = c;
    }
    if (h->face == h->nel - 1 && pr->count_type >= 0 &&
        (word_is(pn, l->wl[last], "vertex_indices") || word_is(pn, l->wl[last], "vertex_index")))
        h->face_prop = e->nprops;
    e->nprops++;
    return IO_OK;
}

/* After end_header: a format line was seen, and one vertex element with x, y, z and points. */
static io_status ply_header_complete(const char *name, int have_format, const ply_header *h,
                                     io_error *err)
{
    if (!have_format) return io_fail(err, IO_ERR_INPUT, "%s: the PLY header has no format line", name);
    if (h->vertex < 0) return io_fail(err, IO_ERR_INPUT, "%s: the PLY header declares no vertex element", name);
    const ply_element *v = &h->el[h->vertex];
    int seen = 0;
    for (int i = 0; i < v->nprops; i++)
        if (v->props[i].coord >= 0) seen |= 1 << v->props[i].coord;
    if (seen != 7)
        return io_fail(err, IO_ERR_INPUT, "%s: the vertex element lacks property %c", name,
                       !(seen & 1) ? 'x' : !(seen & 2) ? 'y' : 'z');
    if (v->count == 0) return io_fail(err, IO_ERR_INPUT, "%s: the PLY file declares 0 vertices", name);
    return IO_OK;
}

static io_status ply_parse_header(const char *name, const char *buf, size_t len, ply_header *h,
                                  io_error *err)
{
    const char *p = buf, *end = buf + len;
    ply_line l = {.name = name};
    int have_format = 0, done = 0;
    io_status s = IO_OK;
    h->nel = 0;
    h->vertex = h->face = h->face_prop = -1;
    while (p < end && !done && s == IO_OK) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl) return io_fail(err, IO_ERR_INPUT, "%s:%zu: the PLY header has no end_header", name, l.line + 1);
        l.k = words(p, nl, l.w, l.wl);
        l.line++;
        p = nl + 1;
        if (l.line == 1) {
            if (l.k != 1 || !word_is(l.w[0], l.wl[0], "ply"))
                return io_fail(err, IO_ERR_INPUT, "%s:1: not a PLY file (the first line is not 'ply')", name);
            continue;
        }
        if (l.k == 0) continue;
        const char *w0 = l.w[0];
        size_t wl0 = l.wl[0];
        if (word_is(w0, wl0, "comment") || word_is(w0, wl0, "obj_info")) continue;
        if (word_is(w0, wl0, "end_header")) {
            done = 1;
        } else if (word_is(w0, wl0, "format")) {
            s = ply_format_line(&l, h, err);
            have_format = 1;
        } else if (word_is(w0, wl0, "element")) {
            s = ply_element_line(&l, h, err);
        } else if (word_is(w0, wl0, "property")) {
            s = ply_property_line(&l, h, err);
        } else {
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: unknown PLY header keyword '%.*s'", name,
                           l.line, PLY_WORD(&l, 0));
        }
    }
    if (s != IO_OK) return s;
    if (!done) return io_fail(err, IO_ERR_INPUT, "%s: the PLY header has no end_header", name);
    if ((s = ply_header_complete(name, have_format, h, err)) != IO_OK) return s;
    h->data = (size_t)(p - buf);
    h->lines = l.line;
    return IO_OK;
}

/* Skip one binary property value (a scalar or a whole list) at *pos; 0 when it runs past len. */
static int bin_skip_prop(const ply_prop *pr, const unsigned char *b, size_t len, size_t *pos)
{
    size_t is = (size_t)ply_types[pr->type].size;
    if (pr->count_type < 0) {
        if (len - *pos < is) return 0;
        *pos += is;
        return 1;
    }
    size_t cs = (size_t)ply_types[pr->count_type].size;
    if (len - *pos < cs) return 0;
    double c = le_value(pr->count_type, b + *pos);
    *pos += cs;
    if (c < 0 || c > (double)((len - *pos) / is)) return 0;
    *pos += (size_t)c * is;
    return 1;
}

static int bin_skip_item(const ply_element *e, const unsigned char *b, size_t len, size_t *pos)
{
    for (int j = 0; j < e->nprops; j++)
        if (!bin_skip_prop(&e->props[j], b, len, pos)) return 0;
    return 1;
}

/* The vertices; *at: where the data starts, then where the vertex element ends. */
static io_status ply_binary(const char *name, const unsigned char *b, size_t len,
                            const ply_header *h, double *a, size_t *at, io_error *err)
{
    size_t pos = *at;
    for (int i = 0; i < h->vertex; i++)
        for (uint64_t k = 0; k < h->el[i].count; k++)
            if (!bin_skip_item(&h->el[i], b, len, &pos))
                return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside element '%s' item %llu",
                               name, h->el[i].name, (unsigned long long)k);
    const ply_element *e = &h->el[h->vertex];
    for (uint64_t i = 0; i < e->count; i++) {
        for (int j = 0; j < e->nprops; j++) {
            const ply_prop *pr = &e->props[j];
            if (pr->coord >= 0) {
                size_t sz = (size_t)ply_types[pr->type].size;
                if (len - pos < sz) goto short_file;
                double v = le_value(pr->type, b + pos);
                if (!isfinite(v))
                    return io_fail(err, IO_ERR_INPUT, "%s: vertex %llu (byte offset %zu): %c is %s",
                                   name, (unsigned long long)i, pos, 'x' + pr->coord,
                                   isnan(v) ? "NaN" : "infinite");
                a[3 * i + (size_t)pr->coord] = v;
                pos += sz;
            } else if (!bin_skip_prop(pr, b, len, &pos)) {
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
        for (uint64_t k = 0; k < h->el[i].count; k++)
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
        min += h->binary ? (size_t)ply_types[pr->count_type >= 0 ? pr->count_type : pr->type].size : 2;
    }
    if (e->count > (len - h->data) / min)
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
        for (uint64_t k = 0; k < h->el[i].count; k++)
            if (!bin_skip_item(&h->el[i], b, len, &pos))
                return io_fail(err, IO_ERR_INPUT, "%s: the file ends inside element '%s' item %llu",
                               f->name, h->el[i].name, (unsigned long long)k);
    const ply_element *e = &h->el[h->face];
    const ply_prop *fp = &e->props[h->face_prop];
    size_t is = (size_t)ply_types[fp->type].size, cs = (size_t)ply_types[fp->count_type].size;
    io_status s;
    for (uint64_t i = 0; i < e->count; i++)
        for (int j = 0; j < e->nprops; j++) {
            if (j != h->face_prop) {
                if (!bin_skip_prop(&e->props[j], b, len, &pos)) goto short_file;
                continue;
            }
            if (len - pos < cs) goto short_file;
            snprintf(f->where, sizeof f->where, " (byte offset %zu)", pos);
            double k = le_value(fp->count_type, b + pos);
            pos += cs;
            if ((s = fan_start(f, i, k, err)) != IO_OK) return s;
            if (k > (double)((len - pos) / is)) goto short_file;
            for (uint64_t q = 0; q < (uint64_t)k; q++, pos += is)
                if ((s = fan_add(f, le_value(fp->type, b + pos), tv, err)) != IO_OK) return s;
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
        for (uint64_t k = 0; k < h->el[i].count; k++)
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
    if (ply_types[h->el[h->face].props[h->face_prop].type].kind == 'f')
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
    double *a = malloc((size_t)count * 3 * sizeof(double));
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
        /* directories, pipes: the generic path reports or handles them */
        close(fd);
        char *buf;
        size_t len;
        io_status s = io_load_file(path, &buf, &len, err);
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
    double *a = malloc((size_t)count * 24);
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
