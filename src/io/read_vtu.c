/* read_vtu.c -- VTK XML UnstructuredGrid (.vtu) meshes as VTK's vtkXMLUnstructuredGridWriter,
 * meshio, ParaView and gigatet write them (what is read: io.h).
 *
 * The XML is scanned, not validated: tags are found by name ("<Piece", "<Points", "<Cells",
 * "<DataArray" followed by a blank, '/' or '>'), attributes are looked up by name in any
 * order, quoted with " or '.  The XML part ends where <AppendedData begins, so raw appended
 * bytes are never scanned for tags.  An inline DataArray's data is the text between its
 * opening tag and the next '<' (VTK puts <InformationKey> children after the data).
 *
 * Binary DataArrays (inline base64 or appended) start with a header of UInt32 or UInt64
 * words (header_type): uncompressed, the data's byte count; compressed, "blocks, block
 * size, last block size (0: a full block), compressed size of each block", then the zlib
 * streams.  Every size is checked against the bytes that remain before it is allocated; a
 * compressed block may claim at most IO_ZLIB_MAX_RATIO times its compressed size, so a
 * file of n bytes never makes the reader allocate more than about 1000 n bytes.
 */
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct vtu {
    const char *name, *buf;
    size_t len;
    const char *xml_end;          /* the XML part: [buf, xml_end) */
    io_error *err;
    size_t hw;                    /* header word: 4 (UInt32) or 8 (UInt64) bytes */
    int zlib;
    const char *app;              /* appended data: the byte after its '_' */
    size_t app_len;
    int app_b64;
} vtu;

/* A DataArray's values: doubles (want_float) or non-negative integers. */
typedef struct varr {
    size_t n;
    double *d;
    uint64_t *u;
} varr;

static io_status fail_at(const vtu *v, const char *p, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static io_status fail_at(const vtu *v, const char *p, const char *fmt, ...)
{
    char what[800];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return io_fail(v->err, IO_ERR_INPUT, "%s:%zu: %s", v->name, io_line_of(v->buf, p), what);
}

/* ---- XML scanning ------------------------------------------------------------------------ */

static int is_blank(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

/* The '>' closing the tag that starts at p (quoted values may hold '>'), or NULL. */
static const char *tag_end(const char *p, const char *lim)
{
    char q = 0;
    for (; p < lim; p++) {
        if (q) {
            if (*p == q) q = 0;
        } else if (*p == '"' || *p == '\'') {
            q = *p;
        } else if (*p == '>') {
            return p;
        }
    }
    return NULL;
}

/* The first "<name" in [p, lim) followed by a blank, '/' or '>'. */
static const char *find_tag(const char *p, const char *lim, const char *name)
{
    size_t l = strlen(name);
    while (p < lim && (p = memchr(p, '<', (size_t)(lim - p))) != NULL) {
        if ((size_t)(lim - p) > l + 1 && memcmp(p + 1, name, l) == 0 &&
            (is_blank(p[l + 1]) || p[l + 1] == '/' || p[l + 1] == '>'))
            return p;
        p++;
    }
    return NULL;
}

/* The value of attribute `key` of the tag [t, te): 1 and [*vb, *ve). */
static int attr(const char *t, const char *te, const char *key, const char **vb, const char **ve)
{
    size_t kl = strlen(key);
    const char *p = t + 1;
    while (p < te && !is_blank(*p)) p++;                 /* the tag's name */
    for (;;) {
        while (p < te && is_blank(*p)) p++;
        const char *ks = p;
        while (p < te && !is_blank(*p) && *p != '=' && *p != '>' && *p != '/') p++;
        const char *ke = p;
        while (p < te && is_blank(*p)) p++;
        if (p >= te || *p != '=' || ke == ks) return 0;
        p++;
        while (p < te && is_blank(*p)) p++;
        if (p >= te || (*p != '"' && *p != '\'')) return 0;
        char q = *p++;
        const char *e = memchr(p, q, (size_t)(te - p));
        if (!e) return 0;
        if ((size_t)(ke - ks) == kl && memcmp(ks, key, kl) == 0) {
            *vb = p;
            *ve = e;
            return 1;
        }
        p = e + 1;
    }
}

static int span_is(const char *b, const char *e, const char *s)
{
    return (size_t)(e - b) == strlen(s) && memcmp(b, s, (size_t)(e - b)) == 0;
}

/* At most 40 bytes of a value for a message, non-printable bytes as '?'. */
static const char *excerpt(const char *b, const char *e, char out[48])
{
    size_t k = 0;
    for (; b < e && k < 40; b++) out[k++] = *b >= 0x20 && *b < 0x7f ? *b : '?';
    out[k] = '\0';
    return out;
}

/* Attribute `key` as an unsigned integer; absent: 0 and *v = dflt. */
static io_status attr_uint(const vtu *v, const char *t, const char *te, const char *key,
                           uint64_t dflt, uint64_t *out)
{
    const char *b, *e;
    char ex[48];
    *out = dflt;
    if (!attr(t, te, key, &b, &e)) return IO_OK;
    uint64_t x = 0;
    const char *p = b;
    while (p < e && is_blank(*p)) p++;
    if (p == e) goto bad;
    for (; p < e && !is_blank(*p); p++) {
        if (*p < '0' || *p > '9' || x > (UINT64_MAX - 9) / 10) goto bad;
        x = x * 10 + (uint64_t)(*p - '0');
    }
    while (p < e && is_blank(*p)) p++;
    if (p != e) goto bad;
    *out = x;
    return IO_OK;
bad:
    return fail_at(v, t, "%s=\"%s\" is not a non-negative integer", key, excerpt(b, e, ex));
}

/* ---- DataArray bytes --------------------------------------------------------------------- */

/* Where a binary array's bytes come from: raw appended bytes or a base64 stream. */
typedef struct vsrc {
    int b64;
    io_b64 s;
    const unsigned char *p;
    size_t left;
} vsrc;

static int src_read(vsrc *s, unsigned char *dst, size_t n)
{
    if (s->b64) return io_b64_read(&s->s, dst, n);
    if (n > s->left) return 0;
    if (dst) memcpy(dst, s->p, n);
    s->p += n;
    s->left -= n;
    return 1;
}

static size_t src_bound(const vsrc *s) { return s->b64 ? io_b64_bound(&s->s) : s->left; }

/* Header word(s) of the array `what` whose tag is at t. */
static io_status read_words(const vtu *v, vsrc *src, const char *t, const char *what,
                            uint64_t *w, size_t n)
{
    unsigned char b[8];
    for (size_t i = 0; i < n; i++) {
        if (!src_read(src, b, v->hw))
            return fail_at(v, t, "DataArray %s: its binary header is cut short%s", what,
                           src->b64 && src->s.bad ? " (a character that is not base64)" : "");
        w[i] = io_load_le(b, v->hw);
    }
    return IO_OK;
}

/* The zlib blocks of a compressed array into *out (*nout bytes). */
static io_status inflate_blocks(const vtu *v, vsrc *src, const char *t, const char *what,
                                unsigned char **out, size_t *nout)
{
    uint64_t h[3] = {0, 0, 0};
    io_status s = read_words(v, src, t, what, h, 3);
    if (s != IO_OK) return s;
    uint64_t nb = h[0], bs = h[1], last = h[2] ? h[2] : h[1];
    if (nb > src_bound(src) / v->hw || (nb && (bs == 0 || last > bs)))
        return fail_at(v, t, "DataArray %s: implausible compression header (%llu blocks of "
                       "%llu bytes, last %llu)", what, (unsigned long long)nb,
                       (unsigned long long)bs, (unsigned long long)h[2]);
    uint64_t *cs = malloc((nb ? nb : 1) * sizeof *cs), total = 0, cmax = 0;
    unsigned char *cbuf = NULL;
    if (!cs) return io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory", v->name);
    if ((s = read_words(v, src, t, what, cs, (size_t)nb)) != IO_OK) goto out;
    for (uint64_t i = 0; i < nb; i++) {
        uint64_t ul = i + 1 == nb ? last : bs;
        if (cs[i] > src_bound(src) || ul > cs[i] * IO_ZLIB_MAX_RATIO + 64 ||
            total + ul > SIZE_MAX / 2) {
            s = fail_at(v, t, "DataArray %s: zlib block %llu claims %llu bytes from %llu "
                        "compressed, more than the data can hold", what, (unsigned long long)i,
                        (unsigned long long)ul, (unsigned long long)cs[i]);
            goto out;
        }
        total += ul;
        cmax = cs[i] > cmax ? cs[i] : cmax;
    }
    *out = malloc(total ? (size_t)total : 1);
    cbuf = malloc(cmax ? (size_t)cmax : 1);
    if (!*out || !cbuf) {
        s = io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory for %llu bytes", v->name,
                    (unsigned long long)total);
        goto out;
    }
    size_t at = 0;
    for (uint64_t i = 0; i < nb; i++) {
        size_t ul = (size_t)(i + 1 == nb ? last : bs);
        if (!src_read(src, cbuf, (size_t)cs[i])) {
            s = fail_at(v, t, "DataArray %s: zlib block %llu is cut short or not base64", what,
                        (unsigned long long)i);
            goto out;
        }
        if (!io_inflate(cbuf, (size_t)cs[i], *out + at, ul)) {
            s = fail_at(v, t, "DataArray %s: zlib block %llu is corrupt or does not inflate to "
                        "its %zu bytes", what, (unsigned long long)i, ul);
            goto out;
        }
        at += ul;
    }
    *nout = (size_t)total;
out:
    free(cs);
    free(cbuf);
    return s;
}

/* A binary array's data bytes (after its header, inflated) into *out, *nout. */
static io_status array_bytes(const vtu *v, vsrc *src, const char *t, const char *what,
                             unsigned char **out, size_t *nout)
{
    *out = NULL;
    if (v->zlib) return inflate_blocks(v, src, t, what, out, nout);
    uint64_t nb = 0;
    io_status s = read_words(v, src, t, what, &nb, 1);
    if (s != IO_OK) return s;
    if (nb > src_bound(src))
        return fail_at(v, t, "DataArray %s: its header claims %llu bytes, more than the %zu "
                       "present", what, (unsigned long long)nb, src_bound(src));
    *out = malloc(nb ? (size_t)nb : 1);
    if (!*out) return io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory", v->name);
    if (!src_read(src, *out, (size_t)nb))
        return fail_at(v, t, "DataArray %s: its data is cut short%s", what,
                       src->b64 && src->s.bad ? " (a character that is not base64)" : "");
    *nout = (size_t)nb;
    return IO_OK;
}

/* ---- DataArray values -------------------------------------------------------------------- */

/* The value type of a DataArray: kind 'f' (float), 'i' (signed), 'u' (unsigned); size. */
static int value_type(const char *b, const char *e, char *kind, size_t *size)
{
    static const struct { const char *n; char k; size_t s; } types[] = {
        {"Float32", 'f', 4}, {"Float64", 'f', 8}, {"Int8", 'i', 1},   {"UInt8", 'u', 1},
        {"Int16", 'i', 2},   {"UInt16", 'u', 2},  {"Int32", 'i', 4},  {"UInt32", 'u', 4},
        {"Int64", 'i', 8},   {"UInt64", 'u', 8}};
    for (size_t i = 0; i < sizeof types / sizeof *types; i++)
        if (span_is(b, e, types[i].n)) {
            *kind = types[i].k;
            *size = types[i].s;
            return 1;
        }
    return 0;
}

/* Convert n binary values of (kind, size) into a: into a->d when it is allocated (Points),
 * integers too (meshio writes integer coordinates as Int64, and VTK reads them; each must be
 * a double exactly, |x| <= 2^53), else into a->u. */
static io_status convert(const vtu *v, const char *t, const char *what, const unsigned char *b,
                         char kind, size_t size, varr *a)
{
    for (size_t i = 0; i < a->n; i++) {
        uint64_t x = io_load_le(b + i * size, size);
        if (kind == 'f') {
            double d;
            if (size == 4) {
                uint32_t x32 = (uint32_t)x;
                float f;
                memcpy(&f, &x32, sizeof f);
                d = f;
            } else {
                memcpy(&d, &x, sizeof d);
            }
            if (!isfinite(d))
                return fail_at(v, t, "DataArray %s: value %zu is not finite", what, i);
            a->d[i] = d;
        } else if (a->d) {
            int neg = kind == 'i' && (x >> (8 * size - 1)) & 1;
            uint64_t mag = !neg ? x : size == 8 ? ~x + 1 : ((uint64_t)1 << (8 * size)) - x;
            if (mag > (uint64_t)1 << 53)
                return fail_at(v, t, "DataArray %s: value %zu (%s%llu) is not a double exactly",
                               what, i, neg ? "-" : "", (unsigned long long)mag);
            a->d[i] = neg ? -(double)mag : (double)mag;
        } else {
            if (kind == 'i' && (x >> (8 * size - 1)) & 1)
                return fail_at(v, t, "DataArray %s: value %zu is negative", what, i);
            a->u[i] = x;
        }
    }
    return IO_OK;
}

/* ASCII values in [p, e): count them, then parse. */
static io_status ascii_values(const vtu *v, const char *what, const char *p, const char *e,
                              char kind, varr *a)
{
    size_t n = 0;
    for (const char *q = p; q < e;) {
        while (q < e && is_blank(*q)) q++;
        if (q < e) n++;
        while (q < e && !is_blank(*q)) q++;
    }
    a->n = n;
    if (kind == 'f') a->d = malloc((n ? n : 1) * sizeof *a->d);
    else a->u = malloc((n ? n : 1) * sizeof *a->u);
    if (kind == 'f' ? !a->d : !a->u) return io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory", v->name);
    for (size_t i = 0; i < n; i++) {
        char ex[48];
        while (is_blank(*p)) p++;
        const char *te = p;
        while (te < e && !is_blank(*te)) te++;
        char *ep = NULL;
        int ok = 1;
        if (kind == 'f') {
            a->d[i] = strtod(p, &ep);
            ok = ep == te && isfinite(a->d[i]);
        } else {
            uint64_t x = 0;
            ok = te > p && (te - p > 1 || *p != '-');
            for (const char *q = *p == '+' ? p + 1 : p; ok && q < te; q++) {
                ok = *q >= '0' && *q <= '9' && x <= (UINT64_MAX - 9) / 10;
                x = x * 10 + (uint64_t)(*q - '0');
            }
            a->u[i] = x;
        }
        if (!ok)
            return fail_at(v, p, "DataArray %s: value %zu is not a %s: '%s'", what, i,
                           kind == 'f' ? "finite number" : "non-negative integer",
                           excerpt(p, te, ex));
        p = te;
    }
    return IO_OK;
}

/* The values of the DataArray whose opening tag is [t, te]. */
static io_status read_array(const vtu *v, const char *t, const char *te, const char *what,
                            int want_float, varr *a)
{
    const char *b, *e;
    char kind, ex[48];
    size_t size;
    io_status s;
    if (!attr(t, te, "type", &b, &e) || !value_type(b, e, &kind, &size) ||
        (kind == 'f' && !want_float))
        return fail_at(v, t, "DataArray %s: type \"%s\" is not read here (%s)", what,
                       attr(t, te, "type", &b, &e) ? excerpt(b, e, ex) : "",
                       want_float ? "Float32, Float64 or an integer type" : "an integer type");
    if (!attr(t, te, "format", &b, &e))
        return fail_at(v, t, "DataArray %s has no format attribute", what);
    vsrc src;
    memset(&src, 0, sizeof src);
    if (span_is(b, e, "ascii") || span_is(b, e, "binary")) {
        if (te[-1] == '/') return fail_at(v, t, "DataArray %s is empty", what);
        const char *db = te + 1, *de = memchr(db, '<', (size_t)(v->xml_end - db));
        if (!de) return fail_at(v, t, "DataArray %s is not closed", what);
        if (span_is(b, e, "ascii"))
            return ascii_values(v, what, db, de, want_float ? 'f' : kind, a);
        src.b64 = 1;
        io_b64_init(&src.s, db, de);
    } else if (span_is(b, e, "appended")) {
        uint64_t off;
        if ((s = attr_uint(v, t, te, "offset", UINT64_MAX, &off)) != IO_OK) return s;
        if (!v->app || off > v->app_len)
            return fail_at(v, t, "DataArray %s: offset %llu is not inside the <AppendedData> "
                           "(%zu bytes)%s", what, (unsigned long long)off, v->app_len,
                           v->app ? "" : ": there is none");
        if (v->app_b64) {
            src.b64 = 1;
            const char *end = memchr(v->app + off, '<', v->app_len - (size_t)off);
            io_b64_init(&src.s, v->app + off, end ? end : v->app + v->app_len);
        } else {
            src.p = (const unsigned char *)v->app + off;
            src.left = v->app_len - (size_t)off;
        }
    } else {
        return fail_at(v, t, "DataArray %s: format \"%s\" is not read (ascii, binary or "
                       "appended)", what, excerpt(b, e, ex));
    }
    unsigned char *bytes = NULL;
    size_t nbytes = 0;
    if ((s = array_bytes(v, &src, t, what, &bytes, &nbytes)) == IO_OK) {
        if (nbytes % size)
            s = fail_at(v, t, "DataArray %s: %zu bytes are not a whole number of %zu-byte "
                        "values", what, nbytes, size);
        a->n = nbytes / size;
        if (s == IO_OK && want_float) a->d = malloc((a->n ? a->n : 1) * sizeof *a->d);
        if (s == IO_OK && !want_float) a->u = malloc((a->n ? a->n : 1) * sizeof *a->u);
        if (s == IO_OK && !a->d && !a->u)
            s = io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory", v->name);
        if (s == IO_OK) s = convert(v, t, what, bytes, kind, size, a);
    }
    free(bytes);
    return s;
}

static void varr_free(varr *a)
{
    free(a->d);
    free(a->u);
    memset(a, 0, sizeof *a);
}

/* ---- the file ---------------------------------------------------------------------------- */

/* <VTKFile ...> attributes and the <AppendedData> it may hold. */
static io_status file_header(vtu *v)
{
    const char *t = find_tag(v->buf, v->buf + v->len, "VTKFile"), *te, *b, *e;
    char ex[48];
    if (!t || !(te = tag_end(t, v->buf + v->len)))
        return io_fail(v->err, IO_ERR_INPUT, "%s: not a VTK XML file (no <VTKFile> tag)", v->name);
    if (attr(t, te, "type", &b, &e) && !span_is(b, e, "UnstructuredGrid"))
        return fail_at(v, t, "the VTKFile type is \"%s\", not UnstructuredGrid (the mesh "
                       "reader reads .vtu unstructured grids)", excerpt(b, e, ex));
    if (attr(t, te, "byte_order", &b, &e) && !span_is(b, e, "LittleEndian"))
        return fail_at(v, t, "byte_order \"%s\" is not read (LittleEndian is)", excerpt(b, e, ex));
    v->hw = 4;
    if (attr(t, te, "header_type", &b, &e) && !span_is(b, e, "UInt32")) {
        if (!span_is(b, e, "UInt64"))
            return fail_at(v, t, "header_type \"%s\" is not UInt32 or UInt64", excerpt(b, e, ex));
        v->hw = 8;
    }
    if (attr(t, te, "compressor", &b, &e) && b != e) {
        if (!span_is(b, e, "vtkZLibDataCompressor"))
            return fail_at(v, t, "compressor \"%s\" is not read (vtkZLibDataCompressor is; "
                           "write without compression or with zlib)", excerpt(b, e, ex));
        v->zlib = 1;
    }
    v->xml_end = v->buf + v->len;
    const char *ad = find_tag(te, v->xml_end, "AppendedData");
    if (ad) {
        const char *ae = tag_end(ad, v->xml_end), *u;
        v->xml_end = ad;
        if (!ae || !attr(ad, ae, "encoding", &b, &e) ||
            !(span_is(b, e, "raw") || span_is(b, e, "base64")))
            return fail_at(v, ad, "<AppendedData> needs encoding=\"raw\" or \"base64\"");
        v->app_b64 = span_is(b, e, "base64");
        if (!(u = memchr(ae, '_', (size_t)(v->buf + v->len - ae))))
            return fail_at(v, ad, "<AppendedData> has no '_' before its data");
        v->app = u + 1;
        v->app_len = (size_t)(v->buf + v->len - v->app);
    }
    return IO_OK;
}

/* The opening tag [*t, *te] of the DataArray in [p, lim) whose Name is `name` (any name
 * when NULL). */
static int find_array(const char *p, const char *lim, const char *name, const char **t,
                      const char **te)
{
    const char *b, *e;
    while ((p = find_tag(p, lim, "DataArray")) != NULL) {
        const char *end = tag_end(p, lim);
        if (!end) return 0;
        if (!name || (attr(p, end, "Name", &b, &e) && span_is(b, e, name))) {
            *t = p;
            *te = end;
            return 1;
        }
        p = end;
    }
    return 0;
}

/* The tetrahedra of the cells: offsets as nc ends or nc+1 starts (the first 0). */
static io_status build_cells(const vtu *v, const char *const tag[3], const varr *conn,
                             const varr *offs, const varr *types, size_t nc, io_mesh *m)
{
    if (types->n != nc)
        return fail_at(v, tag[2], "NumberOfCells=\"%zu\" but %zu types", nc, types->n);
    int starts = offs->n == nc + 1 && offs->u[0] == 0;
    if (!(offs->n == nc || starts))
        return fail_at(v, tag[1], "NumberOfCells=\"%zu\" but %zu offsets", nc, offs->n);
    for (int pass = 0; pass < 2; pass++) {
        size_t nt = 0;
        uint64_t prev = 0;
        for (size_t i = 0; i < nc; i++) {
            uint64_t b = starts ? offs->u[i] : prev, e = offs->u[i + (size_t)starts];
            if (e < b || e > conn->n)
                return fail_at(v, tag[1], "cell %zu: offsets %llu..%llu do not lie in the %zu "
                               "connectivity entries in order", i, (unsigned long long)b,
                               (unsigned long long)e, conn->n);
            prev = e;
            if (types->u[i] != 10) {
                m->skipped_cells += pass == 0;
                continue;
            }
            if (e - b != 4)
                return fail_at(v, tag[1], "cell %zu is a VTK_TETRA of %llu points", i,
                               (unsigned long long)(e - b));
            for (int c = 0; pass == 1 && c < 4; c++) {
                uint64_t id = conn->u[b + (size_t)c];
                if (id >= m->nv)
                    return fail_at(v, tag[0], "cell %zu refers to point %llu; NumberOfPoints is %zu",
                                   i, (unsigned long long)id, m->nv);
                m->tets[4 * nt + (size_t)c] = (uint32_t)id;
            }
            nt++;
        }
        if (pass == 0) {
            m->nt = nt;
            if (!(m->tets = malloc((nt ? nt : 1) * 4 * sizeof *m->tets)))
                return io_fail(v->err, IO_ERR_NOMEM, "%s: out of memory for %zu tets", v->name, nt);
        }
    }
    return IO_OK;
}

/* The Points of the piece [p, lim) with nv points. */
static io_status read_points(const vtu *v, const char *p, const char *lim, uint64_t nv,
                             io_mesh *m)
{
    const char *pt = find_tag(p, lim, "Points"), *t, *te;
    const char *pe = pt ? strstr(pt, "</Points") : NULL;
    uint64_t nco;
    varr a = {0, NULL, NULL};
    io_status s;
    if (!pt || !pe || pe > lim || !find_array(pt, pe, NULL, &t, &te))
        return fail_at(v, p, "the <Piece> has no <Points> with a DataArray");
    if ((s = attr_uint(v, t, te, "NumberOfComponents", 1, &nco)) != IO_OK) return s;
    if (nco != 3) return fail_at(v, t, "the Points have %llu components, not 3", (unsigned long long)nco);
    if ((s = read_array(v, t, te, "Points", 1, &a)) != IO_OK) goto out;
    if (a.n / 3 != nv || a.n % 3) {
        s = fail_at(v, t, "the Points DataArray holds %zu values; NumberOfPoints=\"%llu\" needs "
                    "3 each", a.n, (unsigned long long)nv);
        goto out;
    }
    m->vertices = a.d;
    m->nv = (size_t)nv;
    a.d = NULL;
out:
    varr_free(&a);
    return s;
}

/* The three cell arrays of <Cells> in [p, lim), then the tetrahedra. */
static io_status read_cells(const vtu *v, const char *p, const char *lim, uint64_t nc,
                            io_mesh *m)
{
    static const char *const names[3] = {"connectivity", "offsets", "types"};
    const char *c = find_tag(p, lim, "Cells"), *t[3] = {NULL, NULL, NULL}, *te;
    const char *ce = c ? strstr(c, "</Cells") : NULL;
    varr a[3];
    io_status s = IO_OK;
    memset(a, 0, sizeof a);
    if (!c || !ce || ce > lim) {
        if (nc == 0) return IO_OK;
        return fail_at(v, p, "the <Piece> has %llu cells but no <Cells>", (unsigned long long)nc);
    }
    for (int i = 0; i < 3 && s == IO_OK; i++) {
        if (!find_array(c, ce, names[i], &t[i], &te))
            s = fail_at(v, c, "<Cells> has no DataArray Name=\"%s\"", names[i]);
        else
            s = read_array(v, t[i], te, names[i], 0, &a[i]);
    }
    if (s == IO_OK) s = build_cells(v, t, &a[0], &a[1], &a[2], (size_t)nc, m);
    for (int i = 0; i < 3; i++) varr_free(&a[i]);
    return s;
}

io_status io_parse_vtu(const char *name, const char *buf, size_t len, io_mesh *m, io_error *err)
{
    vtu v;
    memset(&v, 0, sizeof v);
    v.name = name;
    v.buf = buf;
    v.len = len;
    v.err = err;
    io_status s = file_header(&v);
    if (s != IO_OK) return s;
    const char *pc = find_tag(buf, v.xml_end, "Piece"), *pce;
    uint64_t nv, nc;
    if (!pc || !(pce = tag_end(pc, v.xml_end)))
        return io_fail(err, IO_ERR_INPUT, "%s: no <Piece> tag", name);
    if (find_tag(pce, v.xml_end, "Piece"))
        return fail_at(&v, find_tag(pce, v.xml_end, "Piece"), "a second <Piece> (one is read)");
    if ((s = attr_uint(&v, pc, pce, "NumberOfPoints", UINT64_MAX, &nv)) != IO_OK ||
        (s = attr_uint(&v, pc, pce, "NumberOfCells", UINT64_MAX, &nc)) != IO_OK)
        return s;
    if (nv == UINT64_MAX || nc == UINT64_MAX)
        return fail_at(&v, pc, "the <Piece> lacks NumberOfPoints or NumberOfCells");
    if (nv > UINT32_MAX)
        return fail_at(&v, pc, "NumberOfPoints=\"%llu\"; at most 2^32-1 are read",
                       (unsigned long long)nv);
    const char *end = strstr(pce, "</Piece");
    if (!end || end > v.xml_end) end = v.xml_end;
    if ((s = read_points(&v, pce, end, nv, m)) != IO_OK) return s;
    return read_cells(&v, pce, end, nc, m);
}
