/* read_ele.c -- TetGen .ele meshes with the .node file beside them.
 *
 * .node: as the point reader reads it (io_parse_node: "n 3 [attributes [markers]]", ids
 * consecutive from 0 or 1, attribute and marker columns read and dropped).  .ele: header
 * "tets [nodes_per_tet [region_attributes]]" with 4 or 10 nodes per tet (of a 10-node tet the
 * first 4, its corners, are kept), then "id n1 .. nk [attributes]" with ids consecutive from
 * 0 or 1 and node ids in the .node file's numbering (its first id says 0- or 1-based, as
 * TetGen's -z does).  Region attributes are not read.  The tet count is checked against the
 * file size before the array is allocated.
 *
 * TetGen's -o2 appends the mid-edge nodes of its 10-node tets after every corner vertex in
 * the .node; kept, they would be vertices in no tet, and `check` would fail a Delaunay mesh
 * for them ("vertex 792 ... is in no tet").  So the trailing run of nodes that no tet names as
 * a corner and some tet names as a mid-edge node is dropped: the vertices left keep their
 * positions in the file, which is what check's messages number.  Any node before that run
 * (a duplicate input point TetGen kept, in no tet) is kept, as in a 4-node file.
 */
#include "io_internal.h"

#include <stdlib.h>

/* The "tets nodes attributes" header, into h[3]. */
static io_status ele_header(io_text *t, size_t len, uint64_t h[3], io_error *err)
{
    static const char *const hn[3] = {"the number of tets", "the nodes per tet",
                                      "the number of region attributes"};
    static const uint64_t hmax[3] = {UINT64_MAX, 10, 100};
    const char *ts, *te;
    io_status s;
    if (!io_text_next_line(t))
        return io_fail(err, IO_ERR_INPUT, "%s: no header line (empty file)", t->name);
    size_t hk = io_text_count_tokens(t);
    if (hk < 1 || hk > 3)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the .ele header has %zu fields; expected "
                       "'tets nodes_per_tet attributes'", t->name, t->line, hk);
    for (size_t i = 0; i < hk; i++) {
        io_text_token(t, &ts, &te);
        if ((s = io_text_uint(t, ts, te, hn[i], hmax[i], &h[i], err)) != IO_OK) return s;
    }
    if (h[1] != 4 && h[1] != 10)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: %llu nodes per tet; expected 4 or 10",
                       t->name, t->line, (unsigned long long)h[1]);
    if (h[0] > len / (2 * (1 + h[1] + h[2])))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: the header claims %llu tets, more than a file "
                       "of %zu bytes can hold", t->name, t->line, (unsigned long long)h[0], len);
    return IO_OK;
}

/* Tet line i: its id in sequence, then its node ids (0-based into m->tets; mid-edge nodes,
 * the 5th to 10th, marked in mid[] when it is not NULL). */
static io_status ele_line(io_text *t, size_t i, const uint64_t h[3], uint64_t *tbase,
                          const char *node_name, long base, io_mesh *m, unsigned char *mid,
                          io_error *err)
{
    const char *ts, *te;
    io_status s;
    size_t cols = 1 + (size_t)h[1] + (size_t)h[2];
    size_t k = io_text_count_tokens(t);
    if (k != cols)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: expected %zu columns, found %zu", t->name,
                       t->line, cols, k);
    uint64_t id;
    io_text_token(t, &ts, &te);
    if ((s = io_text_uint(t, ts, te, "the tet id", UINT64_MAX, &id, err)) != IO_OK) return s;
    if (i == 0 && id <= 1) *tbase = id;
    if (id != *tbase + i)
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: tet id %llu out of sequence", t->name,
                       t->line, (unsigned long long)id);
    for (size_t c = 0; c < (size_t)h[1]; c++) {
        uint64_t v;
        io_text_token(t, &ts, &te);
        if ((s = io_text_uint(t, ts, te, "a vertex id", UINT64_MAX, &v, err)) != IO_OK) return s;
        if (v < (uint64_t)base || v - (uint64_t)base >= m->nv)
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: vertex id %llu is not in %s (ids "
                           "%ld..%zu)", t->name, t->line, (unsigned long long)v, node_name,
                           base, m->nv - 1 + (size_t)base);
        if (c < 4) m->tets[4 * i + c] = (uint32_t)(v - (uint64_t)base);
        else if (mid) mid[v - (uint64_t)base] = 1;
    }
    return IO_OK;
}

/* Drop the trailing nodes that are only mid-edge nodes of 10-node tets (the comment above). */
static void drop_mid_nodes(io_mesh *m, const unsigned char *mid)
{
    size_t last = 0;   /* 1 + the largest corner id */
    for (size_t k = 0; k < 4 * m->nt; k++)
        if (m->tets[k] + (size_t)1 > last) last = m->tets[k] + (size_t)1;
    size_t nv = m->nv;
    while (nv > last && mid[nv - 1]) nv--;
    if (nv > 0) m->nv = nv;
}

io_status io_parse_ele(const char *name, const char *buf, size_t len, const char *node_name,
                       const char *nbuf, size_t nlen, io_mesh *m, io_error *err)
{
    long base;
    io_status s = io_parse_node(node_name, nbuf, nlen, &m->vertices, &m->nv, &base, err);
    if (s != IO_OK) return s;
    if (m->nv > UINT32_MAX)
        return io_fail(err, IO_ERR_INPUT, "%s: %zu points; at most 2^32-1 are read", node_name,
                       m->nv);
    io_text t;
    uint64_t h[3] = {0, 4, 0}, tbase = 0;
    io_text_init(&t, name, buf, len);
    if ((s = ele_header(&t, len, h, err)) != IO_OK) return s;
    m->nt = (size_t)h[0];
    m->tets = malloc((m->nt ? m->nt : 1) * 4 * sizeof(uint32_t));
    if (!m->tets) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %zu tets", name, m->nt);
    unsigned char *mid = NULL;
    if (h[1] == 10 && !(mid = calloc(m->nv ? m->nv : 1, 1)))
        return io_fail(err, IO_ERR_NOMEM, "%s: out of memory for %zu nodes", name, m->nv);
    for (size_t i = 0; i < m->nt; i++) {
        if (!io_text_next_line(&t)) {
            free(mid);
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: the file ends after %zu of the %zu tets "
                           "its header declares", name, t.line, i, m->nt);
        }
        if ((s = ele_line(&t, i, h, &tbase, node_name, base, m, mid, err)) != IO_OK) {
            free(mid);
            return s;
        }
    }
    if (mid) drop_mid_nodes(m, mid);
    free(mid);
    if (io_text_next_line(&t))
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: data after the %zu tets the header declares",
                       name, t.line, m->nt);
    return IO_OK;
}
