/* read_msh.c -- Gmsh meshes: MSH 4.1 and 2.2 (2.0 and 2.1 share 2.2's layout), each ASCII or
 * binary, as Gmsh, meshio and other tools write them.
 *
 * The file is a sequence of sections "$Name ... $EndName".  $MeshFormat must come first;
 * $Nodes and $Elements are read; $Entities is parsed in 4.1 binary (its records have known
 * sizes) and skipped as text otherwise; every other section ($PhysicalNames, $Periodic,
 * $NodeData, $ElementData, $PartitionedEntities, ...) is skipped up to its "$EndName".
 *
 * Binary layout (little-endian only: the integer 1 after the $MeshFormat line must read as 1):
 *   4.1: counts and tags are "size_t" of the data-size the $MeshFormat line gives (4 or 8),
 *        entity headers are int32, coordinates doubles; a node block's tags come first, then
 *        its coordinates, with u [v [w]] after x y z when the block is parametric (one
 *        parameter per dimension of its entity).
 *   2.2: nodes are "int32 tag, 3 doubles"; elements come in blocks "int32 type, count,
 *        number of tags" of count records "int32 id, tags, node tags".
 * A binary block of another element type is skipped by its node count (gmsh_nodes below), so
 * a type whose node count is not known is an error there; in ASCII every element is one line
 * and is skipped as a line.  Only 4-node tetrahedra (type 4) are kept; the others are counted
 * in skipped_cells.  Node tags may be sparse and in any order: tetrahedra are stored by tag
 * and mapped to vertex indices once every section was read.
 *
 * Bounds: a claimed count is compared with the bytes left in the file before anything of
 * that size is allocated, and tetrahedra are stored in an array that grows with the records
 * actually read, so memory stays proportional to the file.
 */
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct msh {
    const char *name;
    const unsigned char *b;      /* the file; b[len] == '\0' */
    size_t len, at;              /* at: the next unread byte */
    io_error *err;
    int version;                 /* 41 or 22, once $MeshFormat was read */
    int binary;
    size_t dsize;                /* width of the size_t fields of 4.1 binary: 4 or 8 */
    int have_nodes, have_elements;
    uint64_t *ntag;              /* node tags, in file order */
    double *xyz;                 /* their coordinates */
    size_t nv;
    uint64_t *ttag;              /* 4 node tags per tetrahedron */
    size_t nt, tcap;
    size_t skipped;
} msh;

/* Nodes of Gmsh element types 1..137 (Gmsh's element property table); 0: not known. */
static const unsigned short gmsh_node_count[138] = {
    0,  2,  3,  4,  4,  8,  6,  5,  3,  6,  9,  10, 27, 18, 14, 1,  8,  20, 15, 13,
    9,  10, 12, 15, 15, 21, 4,  5,  6,  20, 35, 56, 22, 28, 0,  0,  16, 25, 36, 12,
    16, 20, 28, 36, 45, 55, 66, 49, 64, 81, 100, 121, 18, 21, 24, 27, 30, 24, 28, 32,
    36, 40, 7,  8,  9,  10, 11, 0,  0,  0,  0,  84, 120, 165, 220, 286, 0, 0, 0, 34,
    40, 46, 52, 58, 1,  1,  1,  1,  1,  1,  0,  0,  64, 125, 216, 343, 512, 729, 1000, 32,
    44, 56, 68, 80, 92, 104, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 30, 55,
    91, 140, 204, 285, 385, 21, 29, 37, 45, 53, 61, 69, 1, 0, 0, 0, 0, 16};

static size_t gmsh_nodes(uint64_t type)
{
    return type < sizeof gmsh_node_count / sizeof *gmsh_node_count ? gmsh_node_count[type] : 0;
}

/* Fail at byte `at`: "FILE:LINE: ..." in an ASCII file, "FILE: at byte N: ..." in a binary
 * one (its lines mean nothing inside the binary data). */
static io_status fail_at(msh *m, size_t at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static io_status fail_at(msh *m, size_t at, const char *fmt, ...)
{
    char what[800];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (m->binary) return io_fail(m->err, IO_ERR_INPUT, "%s: at byte %zu: %s", m->name, at, what);
    return io_fail(m->err, IO_ERR_INPUT, "%s:%zu: %s", m->name,
                   io_line_of((const char *)m->b, (const char *)m->b + at), what);
}

/* ---- ASCII tokens ------------------------------------------------------------------------ */

static int is_ws(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* The next token, [*ts, *te); with same_line, a newline ends the search (0 returned). */
static int tok(msh *m, int same_line, const char **ts, const char **te)
{
    while (m->at < m->len && is_ws(m->b[m->at]) && !(same_line && m->b[m->at] == '\n')) m->at++;
    if (m->at >= m->len || m->b[m->at] == '\n') return 0;
    *ts = (const char *)m->b + m->at;
    while (m->at < m->len && !is_ws(m->b[m->at])) m->at++;
    *te = (const char *)m->b + m->at;
    return 1;
}

static int tok_is(const char *ts, const char *te, const char *s)
{
    return (size_t)(te - ts) == strlen(s) && memcmp(ts, s, (size_t)(te - ts)) == 0;
}

/* At most 40 bytes of a token for a message, non-printable bytes as '?'. */
static const char *excerpt(const char *ts, const char *te, char out[48])
{
    size_t k = 0;
    for (const char *q = ts; q < te && k < 40; q++)
        out[k++] = *q >= 0x20 && *q < 0x7f ? *q : '?';
    out[k] = '\0';
    return out;
}

/* Past the end of the current line. */
static void next_line(msh *m)
{
    const unsigned char *nl = memchr(m->b + m->at, '\n', m->len - m->at);
    m->at = nl ? (size_t)(nl - m->b) + 1 : m->len;
}

/* To the end of the current line (its newline not consumed). */
static void rest_of_line(msh *m)
{
    const unsigned char *nl = memchr(m->b + m->at, '\n', m->len - m->at);
    m->at = nl ? (size_t)(nl - m->b) : m->len;
}

static io_status a_uint(msh *m, int same_line, const char *what, uint64_t max, uint64_t *v)
{
    const char *ts, *te;
    char ex[48];
    if (!tok(m, same_line, &ts, &te))
        return fail_at(m, m->at, "%s is missing%s", what, same_line ? " on this line" : "");
    uint64_t x = 0;
    for (const char *q = ts; q < te; q++) {
        if (*q < '0' || *q > '9')
            return fail_at(m, (size_t)(ts - (const char *)m->b), "%s is not a non-negative "
                           "integer: '%s'", what, excerpt(ts, te, ex));
        unsigned d = (unsigned)(*q - '0');
        if (x > (max - d) / 10 || d > max)
            return fail_at(m, (size_t)(ts - (const char *)m->b), "%s is too large: '%s' (at "
                           "most %llu)", what, excerpt(ts, te, ex), (unsigned long long)max);
        x = x * 10 + d;
    }
    *v = x;
    return IO_OK;
}

static io_status a_double(msh *m, const char *what, double *v)
{
    const char *ts, *te;
    char *ep, ex[48];
    if (!tok(m, 0, &ts, &te)) return fail_at(m, m->at, "the file ends before %s", what);
    double x = strtod(ts, &ep);
    if (ep != te || !isfinite(x))
        return fail_at(m, (size_t)(ts - (const char *)m->b), "%s is not a finite number: '%s'",
                       what, excerpt(ts, te, ex));
    *v = x;
    return IO_OK;
}

/* The end of a section: the token `name` must come next. */
static io_status end_section(msh *m, const char *name)
{
    const char *ts, *te;
    size_t at = m->at;
    if (!tok(m, 0, &ts, &te) || !tok_is(ts, te, name))
        return fail_at(m, at, "expected %s here (the section holds more or less data than "
                       "its counts say)", name);
    return IO_OK;
}

/* ---- binary reads ------------------------------------------------------------------------ */

/* n more bytes must be in the file (n may be any 64-bit count). */
static io_status need(msh *m, uint64_t n, const char *what)
{
    if (n > m->len - m->at)
        return fail_at(m, m->at, "the file ends inside %s (%llu bytes needed, %zu left)", what,
                       (unsigned long long)n, m->len - m->at);
    return IO_OK;
}

/* A little-endian unsigned field of w bytes; need() was checked. */
static uint64_t rd(msh *m, size_t w)
{
    uint64_t v = io_load_le(m->b + m->at, w);
    m->at += w;
    return v;
}

static double rd_double(msh *m)
{
    uint64_t u = rd(m, 8);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* A 4.1 count/tag field (size_t of dsize bytes in binary). */
static io_status rd_size(msh *m, const char *what, uint64_t *v)
{
    if (!m->binary) return a_uint(m, 0, what, UINT64_MAX, v);
    io_status s = need(m, m->dsize, what);
    if (s == IO_OK) *v = rd(m, m->dsize);
    return s;
}

/* ---- sections ---------------------------------------------------------------------------- */

static io_status sec_format(msh *m)
{
    const char *ts, *te;
    char ex[48];
    uint64_t ftype, dsize;
    io_status s;
    if (m->version) return fail_at(m, m->at, "a second $MeshFormat section");
    if (!tok(m, 0, &ts, &te)) return fail_at(m, m->at, "the file ends inside $MeshFormat");
    if (tok_is(ts, te, "4.1")) m->version = 41;
    else if (tok_is(ts, te, "2.2") || tok_is(ts, te, "2.1") || tok_is(ts, te, "2.0") ||
             tok_is(ts, te, "2"))
        m->version = 22;
    else
        return fail_at(m, (size_t)(ts - (const char *)m->b), "MSH version '%s' is not read "
                       "(4.1 and 2.2 are; Gmsh converts with -format msh41 or msh22)",
                       excerpt(ts, te, ex));
    if ((s = a_uint(m, 1, "the file type", 1, &ftype)) != IO_OK ||
        (s = a_uint(m, 1, "the data size", 64, &dsize)) != IO_OK)
        return s;
    if (ftype == 1) {
        if (m->version == 41 ? dsize != 4 && dsize != 8 : dsize != 8)
            return fail_at(m, m->at, "binary data size %llu is not read (%s)",
                           (unsigned long long)dsize, m->version == 41 ? "4 or 8" : "8");
        m->dsize = (size_t)dsize;
        next_line(m);
        m->binary = 1;
        if ((s = need(m, 4, "$MeshFormat")) != IO_OK) return s;
        uint64_t one = rd(m, 4);
        if (one != 1)
            return fail_at(m, m->at - 4, "the binary check integer reads %llu, not 1: a "
                           "big-endian file (not read) or a corrupt header",
                           (unsigned long long)one);
    }
    return end_section(m, "$EndMeshFormat");
}

/* Skip a section whose name is [ts, te) up to its "$End..." token. */
static io_status skip_section(msh *m, const char *ts, const char *te)
{
    char end[80], ex[48];
    size_t nl = (size_t)(te - ts) - 1;
    if (nl == 0 || nl > 64)
        return fail_at(m, (size_t)(ts - (const char *)m->b), "'%s' is not a section name",
                       excerpt(ts, te, ex));
    memcpy(end, "$End", 4);
    memcpy(end + 4, ts + 1, nl);
    size_t el = 4 + nl;
    for (size_t i = m->at; i + el <= m->len; i++) {
        const unsigned char *d = memchr(m->b + i, '$', m->len - i);
        if (!d) break;
        i = (size_t)(d - m->b);
        if (i + el <= m->len && memcmp(d, end, el) == 0 && (i + el == m->len || is_ws(d[el])) &&
            (i == 0 || is_ws(d[-1]))) {
            m->at = i + el;
            return IO_OK;
        }
    }
    end[el] = '\0';
    return fail_at(m, (size_t)(ts - (const char *)m->b), "section %s has no %s",
                   excerpt(ts, te, ex), end);
}

/* 4.1 binary $Entities: points "int tag, 3 doubles, physicals", curves, surfaces and volumes
 * "int tag, 6 doubles, physicals, bounding entities", each list a size_t count of ints. */
static io_status sec_entities_bin(msh *m)
{
    uint64_t count[4];
    io_status s;
    next_line(m);
    for (int d = 0; d < 4; d++)
        if ((s = rd_size(m, "the $Entities counts", &count[d])) != IO_OK) return s;
    for (int d = 0; d < 4; d++) {
        for (uint64_t i = 0; i < count[d]; i++) {
            uint64_t k;
            if ((s = need(m, 4 + (d ? 48 : 24), "an entity")) != IO_OK) return s;
            m->at += 4 + (d ? 48 : 24);
            for (int list = 0; list < (d ? 2 : 1); list++) {
                if ((s = rd_size(m, "an entity's list length", &k)) != IO_OK ||
                    (s = need(m, k > UINT64_MAX / 4 ? UINT64_MAX : 4 * k, "an entity")) != IO_OK)
                    return s;
                m->at += (size_t)(4 * k);
            }
        }
    }
    return end_section(m, "$EndEntities");
}

/* Room for one more tetrahedron's 4 node tags. */
static io_status push_tet(msh *m, const uint64_t t[4])
{
    if (m->nt == m->tcap) {
        size_t nc = m->tcap ? 2 * m->tcap : 1024;
        uint64_t *nb = nc > SIZE_MAX / 32 ? NULL : realloc(m->ttag, nc * 4 * sizeof *nb);
        if (!nb) return io_fail(m->err, IO_ERR_NOMEM, "%s: out of memory after %zu tetrahedra",
                                m->name, m->nt);
        m->ttag = nb;
        m->tcap = nc;
    }
    memcpy(m->ttag + 4 * m->nt, t, 4 * sizeof *t);
    m->nt++;
    return IO_OK;
}

/* The node arrays for n nodes, n checked against the bytes left (a node takes at least
 * min_bytes of them). */
static io_status alloc_nodes(msh *m, uint64_t n, size_t min_bytes)
{
    if (m->have_nodes) return fail_at(m, m->at, "a second $Nodes section");
    m->have_nodes = 1;
    if (n > (m->len - m->at) / min_bytes)
        return fail_at(m, m->at, "$Nodes claims %llu nodes, more than the %zu bytes left can "
                       "hold", (unsigned long long)n, m->len - m->at);
    m->nv = (size_t)n;
    m->ntag = malloc((m->nv ? m->nv : 1) * sizeof *m->ntag);
    m->xyz = malloc((m->nv ? m->nv : 1) * 3 * sizeof *m->xyz);
    if (!m->ntag || !m->xyz)
        return io_fail(m->err, IO_ERR_NOMEM, "%s: out of memory for %zu nodes", m->name, m->nv);
    return IO_OK;
}

/* x y z of node i, then `extra` parametric coordinates that are not kept. */
static io_status node_coords(msh *m, size_t i, size_t extra)
{
    io_status s;
    if (m->binary) {
        for (size_t c = 0; c < 3 + extra; c++) {
            size_t at = m->at;
            double d = rd_double(m);
            if (!isfinite(d))
                return fail_at(m, at, "node %zu has a coordinate that is not finite", i);
            if (c < 3) m->xyz[3 * i + c] = d;
        }
        return IO_OK;
    }
    for (size_t c = 0; c < 3 + extra; c++) {
        double d;
        if ((s = a_double(m, c < 3 ? "a node coordinate" : "a parametric coordinate", &d)) != IO_OK)
            return s;
        if (c < 3) m->xyz[3 * i + c] = d;
    }
    return IO_OK;
}

/* 4.1 $Nodes: "blocks nodes min_tag max_tag", then per block "dim entity parametric count",
 * the count tags, then the count coordinate records. */
static io_status sec_nodes41(msh *m)
{
    uint64_t h[4], dim, param, count;
    io_status s;
    const char *ts, *te;
    if (m->binary) next_line(m);
    for (int i = 0; i < 4; i++)
        if ((s = rd_size(m, "the $Nodes header", &h[i])) != IO_OK) return s;
    if ((s = alloc_nodes(m, h[1], m->binary ? m->dsize + 24 : 8)) != IO_OK) return s;
    size_t done = 0;
    for (uint64_t b = 0; b < h[0]; b++) {
        size_t at = m->at;
        if (m->binary) {
            if ((s = need(m, 12 + m->dsize, "a node block header")) != IO_OK) return s;
            dim = rd(m, 4);
            m->at += 4;                                  /* the entity tag */
            param = rd(m, 4);
            count = rd(m, m->dsize);
        } else if ((s = a_uint(m, 0, "a node block's dimension", 3, &dim)) != IO_OK ||
                   (tok(m, 1, &ts, &te) ? 0 : (s = fail_at(m, m->at, "a node block header "
                                                           "is incomplete"))) != IO_OK ||
                   (s = a_uint(m, 1, "a node block's parametric flag", 1, &param)) != IO_OK ||
                   (s = a_uint(m, 1, "a node block's size", UINT64_MAX, &count)) != IO_OK) {
            return s;
        }
        if (dim > 3 || param > 1)
            return fail_at(m, at, "node block %llu: dimension %llu, parametric flag %llu",
                           (unsigned long long)b, (unsigned long long)dim,
                           (unsigned long long)param);
        if (count > m->nv - done)
            return fail_at(m, at, "node block %llu holds %llu nodes, more than the %zu the "
                           "$Nodes header declares", (unsigned long long)b,
                           (unsigned long long)count, m->nv);
        size_t extra = param ? (size_t)dim : 0, n = (size_t)count;
        if (m->binary && (s = need(m, (uint64_t)n * (m->dsize + 8 * (3 + extra)),
                                   "a node block")) != IO_OK)
            return s;
        for (size_t i = 0; i < n; i++)
            if ((s = rd_size(m, "a node tag", &m->ntag[done + i])) != IO_OK) return s;
        for (size_t i = 0; i < n; i++)
            if ((s = node_coords(m, done + i, extra)) != IO_OK) return s;
        done += n;
    }
    if (done != m->nv)
        return fail_at(m, m->at, "the node blocks hold %zu nodes, the $Nodes header declares %zu",
                       done, m->nv);
    return end_section(m, "$EndNodes");
}

/* 2.2 $Nodes: the count on its own line, then "tag x y z" records. */
static io_status sec_nodes22(msh *m)
{
    uint64_t n, tag;
    io_status s;
    if (m->binary) next_line(m);
    if ((s = a_uint(m, 0, "the number of nodes", UINT64_MAX, &n)) != IO_OK ||
        (s = alloc_nodes(m, n, m->binary ? 28 : 8)) != IO_OK)
        return s;
    if (m->binary) {
        next_line(m);
        if ((s = need(m, 28 * n, "$Nodes")) != IO_OK) return s;
    }
    for (size_t i = 0; i < m->nv; i++) {
        if (m->binary) tag = rd(m, 4);
        else if ((s = a_uint(m, 0, "a node tag", UINT64_MAX, &tag)) != IO_OK) return s;
        m->ntag[i] = tag;
        if ((s = node_coords(m, i, 0)) != IO_OK) return s;
    }
    return end_section(m, "$EndNodes");
}

/* One ASCII element line: a tetrahedron's node tags after `skip` leading fields, or the
 * whole line skipped for another type.  Leaves m->at at the end of the line. */
static io_status ascii_element(msh *m, int is_tet, uint64_t skip)
{
    const char *ts, *te;
    uint64_t t[4];
    io_status s;
    if (!is_tet) {
        if (!tok(m, 1, &ts, &te)) return fail_at(m, m->at, "an element line is empty");
        m->skipped++;
        rest_of_line(m);
        return IO_OK;
    }
    for (uint64_t i = 0; i < skip; i++)
        if (!tok(m, 1, &ts, &te)) return fail_at(m, m->at, "an element line is incomplete");
    for (int c = 0; c < 4; c++)
        if ((s = a_uint(m, 1, "a tetrahedron's node tag", UINT64_MAX, &t[c])) != IO_OK) return s;
    if (tok(m, 1, &ts, &te))
        return fail_at(m, (size_t)(ts - (const char *)m->b), "a 4-node tetrahedron's line has "
                       "more than 4 node tags");
    return push_tet(m, t);
}

/* count binary records of `per` fields of `width` bytes: the fields [first, first + 4) of a
 * tetrahedron's record are its node tags; other types are skipped. */
static io_status binary_records(msh *m, uint64_t type, uint64_t count, size_t per,
                                size_t first, size_t width)
{
    io_status s;
    if (count > (m->len - m->at) / (per * width))
        return fail_at(m, m->at, "an element block of %llu elements of type %llu is longer "
                       "than the rest of the file", (unsigned long long)count,
                       (unsigned long long)type);
    if (type != 4) {
        m->at += (size_t)count * per * width;
        m->skipped += (size_t)count;
        return IO_OK;
    }
    for (uint64_t i = 0; i < count; i++) {
        uint64_t t[4];
        m->at += first * width;
        for (int c = 0; c < 4; c++) t[c] = rd(m, width);
        m->at += (per - first - 4) * width;
        if ((s = push_tet(m, t)) != IO_OK) return s;
    }
    return IO_OK;
}

/* A binary element type's node count, or an error: its records cannot be skipped without. */
static io_status binary_type(msh *m, size_t at, uint64_t type, size_t *nn)
{
    *nn = gmsh_nodes(type);
    if (*nn == 0)
        return fail_at(m, at, "element type %llu is not a Gmsh type this reader knows the node "
                       "count of, so its binary block cannot be skipped",
                       (unsigned long long)type);
    return IO_OK;
}

/* 4.1 $Elements: "blocks elements min_tag max_tag", then per block "dim entity type count"
 * and count records "tag node_tags...". */
static io_status sec_elements41(msh *m)
{
    uint64_t h[4], dim, type, count;
    io_status s;
    const char *ts, *te;
    if (m->binary) next_line(m);
    for (int i = 0; i < 4; i++)
        if ((s = rd_size(m, "the $Elements header", &h[i])) != IO_OK) return s;
    for (uint64_t b = 0; b < h[0]; b++) {
        size_t at = m->at, nn;
        if (m->binary) {
            if ((s = need(m, 12 + m->dsize, "an element block header")) != IO_OK) return s;
            dim = rd(m, 4);
            m->at += 4;
            type = rd(m, 4);
            count = rd(m, m->dsize);
            if ((s = binary_type(m, at, type, &nn)) != IO_OK ||
                (s = binary_records(m, type, count, 1 + nn, 1, m->dsize)) != IO_OK)
                return s;
            continue;
        }
        if ((s = a_uint(m, 0, "an element block's dimension", 3, &dim)) != IO_OK) return s;
        if (!tok(m, 1, &ts, &te)) return fail_at(m, m->at, "an element block header is incomplete");
        if ((s = a_uint(m, 1, "an element type", UINT64_MAX, &type)) != IO_OK ||
            (s = a_uint(m, 1, "an element block's size", UINT64_MAX, &count)) != IO_OK)
            return s;
        for (uint64_t i = 0; i < count; i++) {
            next_line(m);
            if ((s = ascii_element(m, type == 4, 1)) != IO_OK) return s;
        }
    }
    (void)dim;
    return end_section(m, "$EndElements");
}

/* 2.2 $Elements: the count, then "id type ntags tags... nodes..." lines (ASCII) or blocks
 * "type count ntags" of int32 records (binary). */
static io_status sec_elements22(msh *m)
{
    uint64_t n, id, type, ntags;
    io_status s;
    if (m->binary) next_line(m);
    if ((s = a_uint(m, 0, "the number of elements", UINT64_MAX, &n)) != IO_OK) return s;
    if (m->binary) {
        next_line(m);
        for (uint64_t done = 0; done < n;) {
            size_t at = m->at, nn;
            if ((s = need(m, 12, "an element block header")) != IO_OK) return s;
            type = rd(m, 4);
            uint64_t count = rd(m, 4);
            ntags = rd(m, 4);
            if (count == 0 || count > n - done)
                return fail_at(m, at, "an element block of %llu elements where %llu remain",
                               (unsigned long long)count, (unsigned long long)(n - done));
            if ((s = binary_type(m, at, type, &nn)) != IO_OK ||
                (s = binary_records(m, type, count, 1 + (size_t)ntags + nn, 1 + (size_t)ntags,
                                    4)) != IO_OK)
                return s;
            done += count;
        }
        return end_section(m, "$EndElements");
    }
    for (uint64_t i = 0; i < n; i++) {
        next_line(m);
        if ((s = a_uint(m, 1, "an element id", UINT64_MAX, &id)) != IO_OK ||
            (s = a_uint(m, 1, "an element type", UINT64_MAX, &type)) != IO_OK ||
            (s = a_uint(m, 1, "an element's number of tags", UINT64_MAX, &ntags)) != IO_OK ||
            (s = ascii_element(m, type == 4, ntags)) != IO_OK)
            return s;
    }
    return end_section(m, "$EndElements");
}

/* ---- node tags to vertex indices --------------------------------------------------------- */

typedef struct tag_index { uint64_t tag; uint32_t index; } tag_index;

static int tag_cmp(const void *a, const void *b)
{
    uint64_t x = ((const tag_index *)a)->tag, y = ((const tag_index *)b)->tag;
    return (x > y) - (x < y);
}

/* Replace the tetrahedra's node tags by vertex indices into out.  Dense tags (the usual
 * 1..n) use a direct table; sparse ones a sorted list and binary search.  Both cost memory
 * proportional to the node count. */
static io_status resolve(msh *m, io_mesh *out)
{
    if (m->nv > UINT32_MAX)
        return io_fail(m->err, IO_ERR_INPUT, "%s: %zu nodes; at most 2^32-1 are read", m->name,
                       m->nv);
    uint64_t lo = UINT64_MAX, hi = 0;
    for (size_t i = 0; i < m->nv; i++) {
        lo = m->ntag[i] < lo ? m->ntag[i] : lo;
        hi = m->ntag[i] > hi ? m->ntag[i] : hi;
    }
    int direct = m->nv > 0 && hi - lo < 2 * (uint64_t)m->nv + 1024;
    size_t tn = direct ? (size_t)(hi - lo) + 1 : m->nv;
    uint32_t *table = direct ? malloc(tn * sizeof *table) : NULL;
    tag_index *sorted = direct ? NULL : malloc((tn ? tn : 1) * sizeof *sorted);
    out->tets = malloc((m->nt ? m->nt : 1) * 4 * sizeof *out->tets);
    io_status s = IO_OK;
    if ((direct ? !table : !sorted) || !out->tets) {
        s = io_fail(m->err, IO_ERR_NOMEM, "%s: out of memory for %zu tetrahedra", m->name, m->nt);
        goto done;
    }
    uint64_t dup = 0;
    int has_dup = 0;
    if (direct) {
        memset(table, 0xff, tn * sizeof *table);
        for (size_t i = 0; i < m->nv && !has_dup; i++) {
            uint32_t *e = &table[m->ntag[i] - lo];
            if (*e != UINT32_MAX) has_dup = 1, dup = m->ntag[i];
            *e = (uint32_t)i;
        }
    } else {
        for (size_t i = 0; i < m->nv; i++) sorted[i] = (tag_index){m->ntag[i], (uint32_t)i};
        qsort(sorted, m->nv, sizeof *sorted, tag_cmp);
        for (size_t i = 1; i < m->nv && !has_dup; i++)
            if (sorted[i].tag == sorted[i - 1].tag) has_dup = 1, dup = sorted[i].tag;
    }
    if (has_dup) {
        s = io_fail(m->err, IO_ERR_INPUT, "%s: node tag %llu appears twice in $Nodes", m->name,
                    (unsigned long long)dup);
        goto done;
    }
    for (size_t i = 0; i < 4 * m->nt; i++) {
        uint64_t t = m->ttag[i];
        uint32_t v = UINT32_MAX;
        if (direct && t >= lo && t <= hi) {
            v = table[t - lo];
        } else if (!direct) {
            tag_index key = {t, 0};
            const tag_index *f = bsearch(&key, sorted, m->nv, sizeof *sorted, tag_cmp);
            if (f) v = f->index;
        }
        if (v == UINT32_MAX) {
            s = io_fail(m->err, IO_ERR_INPUT, "%s: tetrahedron %zu refers to node tag %llu, "
                        "which $Nodes does not define", m->name, i / 4, (unsigned long long)t);
            goto done;
        }
        out->tets[i] = v;
    }
    out->nt = m->nt;
done:
    free(table);
    free(sorted);
    return s;
}

static io_status sections(msh *m)
{
    const char *ts, *te;
    char ex[48];
    io_status s;
    while (tok(m, 0, &ts, &te)) {
        size_t at = (size_t)(ts - (const char *)m->b);
        if (!m->version && !tok_is(ts, te, "$MeshFormat"))
            return fail_at(m, at, "not a Gmsh mesh: it must begin with $MeshFormat, not '%s'",
                           excerpt(ts, te, ex));
        if (*ts != '$')
            return fail_at(m, at, "expected a section such as $Nodes, found '%s'",
                           excerpt(ts, te, ex));
        if (tok_is(ts, te, "$MeshFormat")) s = sec_format(m);
        else if (tok_is(ts, te, "$Nodes")) s = m->version == 41 ? sec_nodes41(m) : sec_nodes22(m);
        else if (tok_is(ts, te, "$Elements") && m->have_elements)
            s = fail_at(m, at, "a second $Elements section");
        else if (tok_is(ts, te, "$Elements"))
            s = (m->have_elements = 1, m->version == 41 ? sec_elements41(m) : sec_elements22(m));
        else if (tok_is(ts, te, "$Entities") && m->version == 41 && m->binary)
            s = sec_entities_bin(m);
        else s = skip_section(m, ts, te);
        if (s != IO_OK) return s;
    }
    if (!m->version)
        return fail_at(m, m->at, "not a Gmsh mesh: no $MeshFormat (the file is empty)");
    if (!m->have_nodes) return fail_at(m, m->at, "the file has no $Nodes section");
    if (!m->have_elements) return fail_at(m, m->at, "the file has no $Elements section");
    return IO_OK;
}

io_status io_parse_msh(const char *name, const char *buf, size_t len, io_mesh *out,
                       io_error *err)
{
    msh m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.b = (const unsigned char *)buf;
    m.len = len;
    m.at = io_bom_length(buf, len);
    m.err = err;
    io_status s = sections(&m);
    if (s == IO_OK) s = resolve(&m, out);
    free(m.ntag);
    free(m.ttag);
    if (s == IO_OK) {
        out->vertices = m.xyz;
        out->nv = m.nv;
        out->skipped_cells = m.skipped;
    } else {
        free(m.xyz);
    }
    return s;
}
