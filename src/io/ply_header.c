/* ply_header.c -- the PLY header parser (ply.h): line by line up to "end_header".
 *
 * Each line is split into at most six words.  "format" must name ascii, binary_little_endian
 * or binary_big_endian (1.0); "element" opens an element with its count; "property" adds a scalar
 * of one of the PLY types, or a list with an integer count type, to the last element; x, y, z
 * of the element named "vertex" are marked as coordinates (scalars, each once) and the
 * vertex_indices (or vertex_index) list of the first "face" element is remembered for
 * surfaces.  Nothing is allocated here: the fixed tables bound the elements and properties,
 * and read_ply.c checks the declared counts against the bytes after the header first.
 */
#include "ply.h"

#include <stdlib.h>
#include <string.h>

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

int ply_type_size(int ty) { return ply_types[ty].size; }

int ply_type_float(int ty) { return ply_types[ty].kind == 'f'; }

double ply_bin_value(int ty, const unsigned char *p, int big)
{
    int size = ply_types[ty].size;
    unsigned char r[8];
    if (big) {   /* the bytes reversed: the same value little-endian */
        for (int i = 0; i < size; i++) r[i] = p[size - 1 - i];
        p = r;
    }
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
    else if (word_is(l->w[1], l->wl[1], "binary_big_endian")) h->binary = 2;
    else
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: unsupported PLY format '%.*s' (ascii, "
                       "binary_little_endian and binary_big_endian are read)", l->name, l->line,
                       PLY_WORD(l, 1));
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
        if (pr->count_type < 0 || pr->type < 0 || ply_type_float(pr->count_type))
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

io_status ply_parse_header(const char *name, const char *buf, size_t len, ply_header *h,
                           io_error *err)
{
    const char *p = buf + io_bom_length(buf, len), *end = buf + len;
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
