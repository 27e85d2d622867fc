/* read_mesh.c -- read a tet mesh back (for `gigatet check`): TetGen .ele + .node, Gmsh 4.1
 * ASCII .msh (tetrahedra only), VTK .vtu (ASCII DataArrays, every cell a tetra, type 10).
 *
 * The readers are as strict as the point readers: exact column counts, consecutive ids,
 * every vertex reference in range (so the checker never indexes out of bounds), counts
 * checked against the file size before allocation.  Vertex ids come back 0-based.
 */
#include "io_internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void io_mesh_free(io_mesh *m)
{
    if (!m) return;
    free(m->vertices);
    free(m->tets);
    memset(m, 0, sizeof *m);
}

static io_status read_ele(const char *path, io_mesh *m, io_error *err)
{
    char *node_path = io_ele_node_path(path), *buf = NULL;
    size_t len;
    long base;
    io_status s;
    char *nbuf;
    size_t nlen;
    if (!node_path) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
    /* the .ele first, so that a missing mesh is reported under its own name */
    if ((s = io_load_file(path, &buf, &len, err)) != IO_OK) goto out;
    if ((s = io_load_file(node_path, &nbuf, &nlen, err)) != IO_OK) goto out;
    s = io_parse_node(node_path, nbuf, nlen, &m->vertices, &m->nv, &base, err);
    free(nbuf);
    if (s != IO_OK) goto out;
    io_text t;
    const char *ts, *te;
    uint64_t h[3] = {0, 4, 0};
    static const char *const hn[3] = {"the number of tets", "the nodes per tet",
                                      "the number of region attributes"};
    static const uint64_t hmax[3] = {UINT64_MAX, 10, 100};
    io_text_init(&t, path, buf, len);
    if (!io_text_next_line(&t)) {
        s = io_fail(err, IO_ERR_INPUT, "%s: no header line (empty file)", path);
        goto out;
    }
    size_t hk = io_text_count_tokens(&t);
    if (hk < 1 || hk > 3) {
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the .ele header has %zu fields; expected "
                    "'tets nodes_per_tet attributes'", path, t.line, hk);
        goto out;
    }
    for (size_t i = 0; i < hk; i++) {
        io_text_token(&t, &ts, &te);
        if ((s = io_text_uint(&t, ts, te, hn[i], hmax[i], &h[i], err)) != IO_OK) goto out;
    }
    if (h[1] != 4 && h[1] != 10) {
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: %llu nodes per tet; expected 4 or 10", path,
                    t.line, (unsigned long long)h[1]);
        goto out;
    }
    size_t cols = 1 + (size_t)h[1] + (size_t)h[2];
    if (h[0] > len / (2 * cols)) {
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the header claims %llu tets, more than a file of "
                    "%zu bytes can hold", path, t.line, (unsigned long long)h[0], len);
        goto out;
    }
    m->nt = (size_t)h[0];
    m->tets = malloc((m->nt ? m->nt : 1) * 4 * sizeof(uint32_t));
    if (!m->tets) {
        s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %zu tets", path, m->nt);
        goto out;
    }
    uint64_t tbase = 0;
    for (size_t i = 0; i < m->nt; i++) {
        if (!io_text_next_line(&t)) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %zu of the %zu tets its "
                        "header declares", path, t.line, i, m->nt);
            goto out;
        }
        size_t k = io_text_count_tokens(&t);
        if (k != cols) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: expected %zu columns, found %zu", path,
                        t.line, cols, k);
            goto out;
        }
        uint64_t id;
        io_text_token(&t, &ts, &te);
        if ((s = io_text_uint(&t, ts, te, "the tet id", UINT64_MAX, &id, err)) != IO_OK) goto out;
        if (i == 0 && id <= 1) tbase = id;
        if (id != tbase + i) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: tet id %llu out of sequence", path, t.line,
                        (unsigned long long)id);
            goto out;
        }
        for (size_t c = 0; c < cols - 1; c++) {
            uint64_t v;
            io_text_token(&t, &ts, &te);
            if (c >= (size_t)h[1]) break; /* region attributes are not used */
            if ((s = io_text_uint(&t, ts, te, "a vertex id", UINT64_MAX, &v, err)) != IO_OK)
                goto out;
            if (v < (uint64_t)base || v - (uint64_t)base >= m->nv) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: vertex id %llu is not in %s (ids %ld..%zu)",
                            path, t.line, (unsigned long long)v, node_path, base,
                            m->nv - 1 + (size_t)base);
                goto out;
            }
            if (c < 4) m->tets[4 * i + c] = (uint32_t)(v - (uint64_t)base);
        }
    }
    if (io_text_next_line(&t)) {
        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: data after the %zu tets the header declares",
                    path, t.line, m->nt);
        goto out;
    }
out:
    free(buf);
    free(node_path);
    if (s != IO_OK) io_mesh_free(m);
    return s;
}

/* ---- Gmsh 4.1 ASCII ---------------------------------------------------------------------- */

/* Read the next data line and its n unsigned integers. */
static io_status line_uints(io_text *t, size_t n, uint64_t *v, const char *what, io_error *err)
{
    const char *ts, *te;
    if (!io_text_next_line(t))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends inside %s", t->name, t->line, what);
    if (io_text_count_tokens(t) < n)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: expected %zu numbers in %s", t->name, t->line,
                       n, what);
    for (size_t i = 0; i < n; i++) {
        io_text_token(t, &ts, &te);
        io_status s = io_text_uint(t, ts, te, what, UINT64_MAX, &v[i], err);
        if (s != IO_OK) return s;
    }
    return IO_OK;
}

static int line_is(const io_text *t, const char *s)
{
    size_t l = strlen(s);
    return (size_t)(t->le - t->lp) >= l && memcmp(t->lp, s, l) == 0;
}

static io_status read_msh(const char *path, io_mesh *m, io_error *err)
{
    char *buf;
    size_t len;
    io_status s = io_load_file(path, &buf, &len, err);
    if (s != IO_OK) return s;
    io_text t;
    io_text_init(&t, path, buf, len);
    uint32_t *tag2v = NULL;   /* node tag -> vertex index */
    size_t maxtag = 0, nt = 0, tcap = 0;
    int have_nodes = 0, have_format = 0;
    const char *ts, *te;
    while (io_text_next_line(&t)) {
        if (line_is(&t, "$MeshFormat")) {
            if (!io_text_next_line(&t) || !line_is(&t, "4.1 0")) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: only Gmsh 4.1 ASCII files are read", path, t.line);
                goto out;
            }
            have_format = 1;
        } else if (line_is(&t, "$Nodes")) {
            uint64_t h[4], bh[4];
            if ((s = line_uints(&t, 4, h, "the $Nodes header", err)) != IO_OK) goto out;
            if (h[1] > len / 8 || h[3] > len / 2 || have_nodes) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: implausible $Nodes header", path, t.line);
                goto out;
            }
            have_nodes = 1;
            m->nv = (size_t)h[1];
            maxtag = (size_t)h[3];
            m->vertices = malloc((m->nv ? m->nv : 1) * 3 * sizeof(double));
            tag2v = malloc((maxtag + 1) * sizeof(uint32_t));
            if (!m->vertices || !tag2v) {
                s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
                goto out;
            }
            memset(tag2v, 0xff, (maxtag + 1) * sizeof(uint32_t));
            size_t done = 0;
            for (uint64_t b = 0; b < h[0]; b++) {
                if ((s = line_uints(&t, 4, bh, "a node block header", err)) != IO_OK) goto out;
                if (bh[2] != 0 || bh[3] > m->nv - done) {
                    s = io_fail(err, IO_ERR_INPUT, "%s:%zu: unsupported or inconsistent node block", path, t.line);
                    goto out;
                }
                for (uint64_t i = 0; i < bh[3]; i++) {
                    uint64_t tag;
                    if ((s = line_uints(&t, 1, &tag, "a node tag", err)) != IO_OK) goto out;
                    if (tag == 0 || tag > maxtag || tag2v[tag] != UINT32_MAX) {
                        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: bad or repeated node tag %llu", path,
                                    t.line, (unsigned long long)tag);
                        goto out;
                    }
                    tag2v[tag] = (uint32_t)(done + i);
                }
                for (uint64_t i = 0; i < bh[3]; i++) {
                    if (!io_text_next_line(&t) || io_text_count_tokens(&t) != 3) {
                        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: expected a line 'x y z'", path, t.line);
                        goto out;
                    }
                    for (int c = 0; c < 3; c++) {
                        io_text_token(&t, &ts, &te);
                        if ((s = io_text_double(&t, ts, te, "a coordinate",
                                                &m->vertices[3 * (done + i) + (size_t)c], err)) != IO_OK)
                            goto out;
                    }
                }
                done += (size_t)bh[3];
            }
            if (done != m->nv) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: %zu nodes in blocks, %zu declared", path, t.line, done, m->nv);
                goto out;
            }
        } else if (line_is(&t, "$Elements")) {
            uint64_t h[4], bh[4];
            if (!have_nodes) {
                s = io_fail(err, IO_ERR_INPUT, "%s:%zu: $Elements before $Nodes", path, t.line);
                goto out;
            }
            if ((s = line_uints(&t, 4, h, "the $Elements header", err)) != IO_OK) goto out;
            for (uint64_t b = 0; b < h[0]; b++) {
                if ((s = line_uints(&t, 4, bh, "an element block header", err)) != IO_OK) goto out;
                if (bh[3] > len / 8) {
                    s = io_fail(err, IO_ERR_INPUT, "%s:%zu: implausible element count", path, t.line);
                    goto out;
                }
                int is_tet = bh[2] == 4;
                if (is_tet && nt + bh[3] > tcap) {
                    size_t nc = nt + (size_t)bh[3];
                    uint32_t *nb = realloc(m->tets, nc * 4 * sizeof(uint32_t));
                    if (!nb) {
                        s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
                        goto out;
                    }
                    m->tets = nb;
                    tcap = nc;
                }
                for (uint64_t i = 0; i < bh[3]; i++) {
                    if (!io_text_next_line(&t)) {
                        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends inside $Elements", path, t.line);
                        goto out;
                    }
                    if (!is_tet) continue;
                    uint64_t v[5];
                    if (io_text_count_tokens(&t) != 5) {
                        s = io_fail(err, IO_ERR_INPUT, "%s:%zu: expected 'tag n1 n2 n3 n4'", path, t.line);
                        goto out;
                    }
                    for (int c = 0; c < 5; c++) {
                        io_text_token(&t, &ts, &te);
                        if ((s = io_text_uint(&t, ts, te, "a node tag", UINT64_MAX, &v[c], err)) != IO_OK)
                            goto out;
                        if (c > 0 && (v[c] > maxtag || tag2v[v[c]] == UINT32_MAX)) {
                            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: unknown node tag %llu", path,
                                        t.line, (unsigned long long)v[c]);
                            goto out;
                        }
                        if (c > 0) m->tets[4 * nt + (size_t)c - 1] = tag2v[v[c]];
                    }
                    nt++;
                }
            }
        }
    }
    if (!have_format || !have_nodes) {
        s = io_fail(err, IO_ERR_INPUT, "%s: not a Gmsh 4.1 mesh (no $MeshFormat or $Nodes)", path);
        goto out;
    }
    m->nt = nt;
out:
    free(tag2v);
    free(buf);
    if (s != IO_OK) io_mesh_free(m);
    return s;
}

/* ---- VTK XML UnstructuredGrid, ASCII ----------------------------------------------------- */

static size_t line_at(const char *buf, const char *p)
{
    size_t l = 1;
    for (const char *q = buf; q < p; q++) l += *q == '\n';
    return l;
}

/* The text of the ASCII DataArray whose opening tag contains `key`: [*b, *e). */
static io_status vtu_array(const char *path, const char *buf, const char *key, const char **b,
                           const char **e, io_error *err)
{
    const char *k = strstr(buf, key);
    if (!k) return io_fail(err, IO_ERR_INPUT, "%s: no DataArray %s", path, key);
    const char *open = k;
    while (open > buf && *open != '<') open--;
    const char *gt = strchr(k, '>');
    if (!gt) return io_fail(err, IO_ERR_INPUT, "%s:%zu: unterminated tag", path, line_at(buf, k));
    const char *fmt = strstr(open, "format=\"ascii\"");
    if (!fmt || fmt > gt)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: only format=\"ascii\" DataArrays are read",
                       path, line_at(buf, k));
    const char *end = strstr(gt, "</DataArray>");
    if (!end) return io_fail(err, IO_ERR_INPUT, "%s:%zu: no </DataArray>", path, line_at(buf, k));
    *b = gt + 1;
    *e = end;
    return IO_OK;
}

/* Next number of [*p, e): a double (integer = 0) or an unsigned integer (integer = 1). */
static int vtu_number(const char **p, const char *e, int integer, double *d, uint64_t *u)
{
    const char *q = *p;
    while (q < e && (*q == ' ' || *q == '\n' || *q == '\t' || *q == '\r')) q++;
    if (q >= e) return 0;
    char *end;
    errno = 0;
    if (integer) {
        if (*q < '0' || *q > '9') return 0;
        *u = strtoull(q, &end, 10);
    } else {
        *d = strtod(q, &end);
        if (!isfinite(*d)) return 0;
    }
    /* ERANGE matters for integers only: strtod sets it for denormal results too */
    if (end == q || end > e || (integer && errno == ERANGE) || (end < e && *end != ' ' && *end != '\n' &&
                                                   *end != '\t' && *end != '\r'))
        return 0;
    *p = end;
    return 1;
}

static io_status read_vtu(const char *path, io_mesh *m, io_error *err)
{
    char *buf;
    size_t len;
    io_status s = io_load_file(path, &buf, &len, err);
    if (s != IO_OK) return s;
    const char *piece = strstr(buf, "<Piece"), *b, *e;
    unsigned long long nv, nt;
    if (!piece || sscanf(piece, "<Piece NumberOfPoints=\"%llu\" NumberOfCells=\"%llu\"", &nv, &nt) != 2 ||
        nv > len / 2 || nt > len / 2) {
        s = io_fail(err, IO_ERR_INPUT, "%s: no <Piece NumberOfPoints=\"..\" NumberOfCells=\"..\">"
                    " with plausible counts", path);
        goto out;
    }
    m->nv = (size_t)nv;
    m->nt = (size_t)nt;
    m->vertices = malloc((m->nv ? m->nv : 1) * 3 * sizeof(double));
    m->tets = malloc((m->nt ? m->nt : 1) * 4 * sizeof(uint32_t));
    if (!m->vertices || !m->tets) {
        s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
        goto out;
    }
    const char *pts = strstr(buf, "<Points>");
    if (!pts || (s = vtu_array(path, pts, "NumberOfComponents=\"3\"", &b, &e, err)) != IO_OK) {
        if (!pts) s = io_fail(err, IO_ERR_INPUT, "%s: no <Points>", path);
        goto out;
    }
    uint64_t u;
    double d;
    for (size_t i = 0; i < 3 * m->nv; i++)
        if (!vtu_number(&b, e, 0, &m->vertices[i], &u)) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: point coordinate %zu missing or not a finite "
                        "number", path, line_at(buf, b), i);
            goto out;
        }
    if ((s = vtu_array(path, buf, "Name=\"connectivity\"", &b, &e, err)) != IO_OK) goto out;
    for (size_t i = 0; i < 4 * m->nt; i++) {
        if (!vtu_number(&b, e, 1, &d, &u) || u >= m->nv) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: connectivity entry %zu missing or not a vertex "
                        "id below %zu", path, line_at(buf, b), i, m->nv);
            goto out;
        }
        m->tets[i] = (uint32_t)u;
    }
    if ((s = vtu_array(path, buf, "Name=\"offsets\"", &b, &e, err)) != IO_OK) goto out;
    for (size_t i = 0; i < m->nt; i++)
        if (!vtu_number(&b, e, 1, &d, &u) || u != 4 * (uint64_t)(i + 1)) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: offset %zu is not %llu (cells must be "
                        "tetrahedra)", path, line_at(buf, b), i, 4 * (unsigned long long)(i + 1));
            goto out;
        }
    if ((s = vtu_array(path, buf, "Name=\"types\"", &b, &e, err)) != IO_OK) goto out;
    for (size_t i = 0; i < m->nt; i++)
        if (!vtu_number(&b, e, 1, &d, &u) || u != 10) {
            s = io_fail(err, IO_ERR_INPUT, "%s:%zu: cell %zu is not of type 10 (VTK_TETRA)", path,
                        line_at(buf, b), i);
            goto out;
        }
out:
    free(buf);
    if (s != IO_OK) io_mesh_free(m);
    return s;
}

io_status io_read_mesh(const char *path, io_mesh *m, io_error *err)
{
    memset(m, 0, sizeof *m);
    switch (io_format_of(path)) {
    case IO_FMT_ELE: return read_ele(path, m, err);
    case IO_FMT_MSH: return read_msh(path, m, err);
    case IO_FMT_VTU: return read_vtu(path, m, err);
    default:
        return io_fail(err, IO_ERR_INPUT, "%s: unknown mesh file extension (.ele, .msh or .vtu "
                       "are read)", path);
    }
}
