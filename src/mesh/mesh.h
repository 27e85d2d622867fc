/* mesh.h -- the result object behind the opaque gtet_mesh of gigatet.h.
 *
 * The kernel builds its working mesh (ghost tets, 4*t+f neighbour links, recycled slots) and,
 * at the end, compacts it in place into these plain arrays: finite tets only, positively
 * oriented, neighbours as tet ids with GTET_NO_TET on the hull.  Everything a user or the
 * checker reads goes through the accessors of mesh.c.
 */
#ifndef GTET_MESH_H
#define GTET_MESH_H

#include "gigatet.h"

struct gtet_mesh {
    size_t n_points;          /* input points as given */
    size_t n_vertices;        /* distinct points */
    size_t n_tets;            /* finite tets */
    size_t n_hull_facets;
    double *vertices;         /* 3 * n_vertices */
    uint32_t *input_map;      /* n_points: vertex id of each input point */
    uint32_t *tets;           /* 4 * n_tets, positively oriented */
    uint32_t *neighbors;      /* 4 * n_tets, GTET_NO_TET on the hull */
    gtet_stats stats;
    gtet_round_stats *rounds; /* stats.num_rounds records */
    gtet_degeneracy *degen;   /* n_degen recorded decisions (gtet_mesh_degeneracies), or NULL */
    size_t n_degen;
    uint64_t degen_total;     /* decisions made while recording (stored or not) */
};

/* Internal (not in gigatet.h): hand the mesh's tet and neighbour arrays (4 * n_tets uint32
 * each, malloc'ed: the caller frees them, or grows them with realloc) to the caller, who may
 * then rewrite them in place; the mesh keeps no tets (n_tets = 0, NULL arrays) and the rest
 * (vertices, input map, stats) as it was.  For the distributed mode, whose later rounds patch
 * the first round's local mesh where it lies (src/mpi/mpi_patch.c, NOTES.md E80) instead of
 * copying it.  Returns the number of tets handed over (0 with NULL arrays for a NULL or empty
 * mesh). */
size_t gtet_mesh_take_arrays(gtet_mesh *m, uint32_t **tets, uint32_t **neighbors);

/* Internal (not in gigatet.h): gtet_triangulate, the same mesh, whose tet and neighbour arrays
 * are each allocated with room for 32 bytes a tet slot and 16 more, twice what the working mesh
 * takes (the pages never written stay unmapped), and handed over unshrunk: their
 * malloc_usable_size is then at least 8 * (4 * n_tets + 1) bytes.  For the distributed mode,
 * which widens the local mesh's rows to its 64-bit result where they lie
 * (src/mpi/mpi_output.c, NOTES.md E130). */
gtet_status gtet_triangulate_wide(const double *xyz, size_t n, const gtet_options *opts,
                                  gtet_mesh **out);

/* Internal (not in gigatet.h): a mesh made from the arrays of one gtet_triangulate's result
 * (gtet_mesh_vertices, _input_map, _tets, _neighbors and their counts), copied: the Python
 * module's unpickling (python/gigatet/_gigatet.c, NOTES.md E180), which must give back the
 * tets in the order they were saved in -- a new run with threads may order them otherwise.
 * The arrays are checked so far as every accessor and gtet_check stay within them: every
 * coordinate finite, nv <= n, the input map in order of first occurrence (vertex k is new at
 * the first i with input_map[i] == k, all nv of them), tet vertices < nv, neighbours < nt or
 * GTET_NO_TET (their number is the hull facet count); nt and nv below GTET_NO_TET.  Nothing
 * geometric is checked (gtet_check does that).  The statistics are zero, no degeneracies are
 * recorded.  GTET_ERR_ARGUMENT with a sentence in msg when a check fails, out of memory, or
 * GTET_OK with *out set. */
gtet_status gtet_mesh_from_arrays(const double *vertices, size_t nv, const uint32_t *input_map,
                                  size_t n, const uint32_t *tets, const uint32_t *neighbors,
                                  size_t nt, gtet_mesh **out, char *msg, size_t msg_size);

/* Internal: gtet_triangulate_wide for points the caller guarantees pairwise distinct (no two
 * with equal coordinates, -0.0 counting as +0.0): the duplicate pass is skipped, vertex i is
 * point i and the input map the identity.  Duplicates here are undefined behaviour.  For the
 * distributed mode, whose local sets are distinct by construction (its own duplicate step,
 * proofs/distributed.md D1). */
gtet_status gtet_triangulate_wide_distinct(const double *xyz, size_t n, const gtet_options *opts,
                                           gtet_mesh **out);

#endif
