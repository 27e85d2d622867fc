/* mesh.c -- accessors and destructor of the result object (see mesh.h). */
#include "mesh.h"

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
