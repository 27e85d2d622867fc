/* mesh.c -- accessors and destructor of the result object (see mesh.h). */
#include "mesh.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void gtet_mesh_free(gtet_mesh **mesh)
{
    if (!mesh || !*mesh) return;
    gtet_mesh *m = *mesh;
    free(m->vertices);
    free(m->input_map);
    free(m->tets);
    free(m->neighbors);
    free(m->rounds);
    free(m->degen);
    free(m);
    *mesh = NULL;
}

size_t gtet_mesh_take_arrays(gtet_mesh *m, uint32_t **tets, uint32_t **neighbors)
{
    *tets = m ? m->tets : NULL;
    *neighbors = m ? m->neighbors : NULL;
    size_t nt = m && m->tets && m->neighbors ? m->n_tets : 0;
    if (m) {
        m->tets = m->neighbors = NULL;
        m->n_tets = 0;
    }
    return nt;
}

size_t gtet_mesh_num_points(const gtet_mesh *m) { return m ? m->n_points : 0; }
size_t gtet_mesh_num_vertices(const gtet_mesh *m) { return m ? m->n_vertices : 0; }
size_t gtet_mesh_num_duplicates(const gtet_mesh *m) { return m ? m->n_points - m->n_vertices : 0; }
size_t gtet_mesh_num_tets(const gtet_mesh *m) { return m ? m->n_tets : 0; }
size_t gtet_mesh_num_hull_facets(const gtet_mesh *m) { return m ? m->n_hull_facets : 0; }
const double *gtet_mesh_vertices(const gtet_mesh *m) { return m ? m->vertices : NULL; }
const uint32_t *gtet_mesh_input_map(const gtet_mesh *m) { return m ? m->input_map : NULL; }
const uint32_t *gtet_mesh_tets(const gtet_mesh *m) { return m ? m->tets : NULL; }
const uint32_t *gtet_mesh_neighbors(const gtet_mesh *m) { return m ? m->neighbors : NULL; }

const gtet_degeneracy *gtet_mesh_degeneracies(const gtet_mesh *m, size_t *stored,
                                              uint64_t *total)
{
    if (stored) *stored = m ? m->n_degen : 0;
    if (total) *total = m ? m->degen_total : 0;
    return m && m->n_degen ? m->degen : NULL;
}

void gtet_mesh_stats(const gtet_mesh *m, gtet_stats *stats)
{
    if (!stats) return;
    if (!m) {
        memset(stats, 0, sizeof *stats);
        return;
    }
    *stats = m->stats;
    stats->rounds = m->rounds;
}

static gtet_status refuse(char *msg, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static gtet_status refuse(char *msg, size_t size, const char *fmt, ...)
{
    if (msg && size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, size, fmt, ap);
        va_end(ap);
    }
    return GTET_ERR_ARGUMENT;
}

/* The checks of mesh.h's contract; on success the number of hull facets in *nhull. */
static gtet_status arrays_valid(const double *V, size_t nv, const uint32_t *map, size_t n,
                                const uint32_t *T, const uint32_t *N, size_t nt, size_t *nhull,
                                char *msg, size_t size)
{
    if ((!V && nv) || (!map && n) || ((!T || !N) && nt))
        return refuse(msg, size, "a NULL array with a nonzero count");
    if (nv > n) return refuse(msg, size, "%zu vertices for %zu points", nv, n);
    if (nv >= GTET_NO_VERTEX || nt >= GTET_NO_TET / 4 || n >= UINT32_MAX)
        return refuse(msg, size, "more points, vertices or tets than 32-bit ids hold");
    for (size_t i = 0; i < 3 * nv; i++)
        if (!isfinite(V[i])) return refuse(msg, size, "vertex %zu is not finite", i / 3);
    size_t next = 0;  /* vertices seen so far: ids are given in order of first occurrence */
    for (size_t i = 0; i < n; i++) {
        if (map[i] > next || map[i] >= nv)
            return refuse(msg, size, "input_map[%zu] = %u is not a vertex seen before or the "
                          "next one (%zu)", i, (unsigned)map[i], next);
        if (map[i] == next) next++;
    }
    if (next != nv) return refuse(msg, size, "the input map names %zu of %zu vertices", next, nv);
    size_t h = 0;
    for (size_t i = 0; i < 4 * nt; i++) {
        if (T[i] >= nv)
            return refuse(msg, size, "tet %zu has vertex %u of %zu", i / 4, (unsigned)T[i], nv);
        if (N[i] == GTET_NO_TET) h++;
        else if (N[i] >= nt)
            return refuse(msg, size, "tet %zu has neighbour %u of %zu", i / 4, (unsigned)N[i],
                          nt);
    }
    *nhull = h;
    return GTET_OK;
}

static void *copy_of(const void *src, size_t bytes)
{
    void *p = malloc(bytes ? bytes : 1);
    if (p && bytes) memcpy(p, src, bytes);
    return p;
}

gtet_status gtet_mesh_from_arrays(const double *vertices, size_t nv, const uint32_t *input_map,
                                  size_t n, const uint32_t *tets, const uint32_t *neighbors,
                                  size_t nt, gtet_mesh **out, char *msg, size_t msg_size)
{
    if (!out) return refuse(msg, msg_size, "no place for the mesh");
    *out = NULL;
    size_t nhull = 0;
    gtet_status s = arrays_valid(vertices, nv, input_map, n, tets, neighbors, nt, &nhull, msg,
                                 msg_size);
    if (s != GTET_OK) return s;
    gtet_mesh *m = calloc(1, sizeof *m);
    if (!m) return GTET_ERR_OUT_OF_MEMORY;
    m->n_points = n;
    m->n_vertices = nv;
    m->n_tets = nt;
    m->n_hull_facets = nhull;
    m->vertices = copy_of(vertices, 3 * nv * sizeof *vertices);
    m->input_map = copy_of(input_map, n * sizeof *input_map);
    m->tets = copy_of(tets, 4 * nt * sizeof *tets);
    m->neighbors = copy_of(neighbors, 4 * nt * sizeof *neighbors);
    if (!m->vertices || !m->input_map || !m->tets || !m->neighbors) {
        gtet_mesh_free(&m);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    *out = m;
    return GTET_OK;
}
