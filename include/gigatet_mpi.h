/* gigatet_mpi.h -- gigatet's distributed mode over MPI (prefix gtet_*_mpi).
 *
 * gtet_triangulate_mpi builds, over the ranks of an MPI communicator, exactly the mesh that
 * gtet_triangulate builds in one process from the concatenation of every rank's points: the
 * same global vertex ids (distinct points in order of first occurrence in the global input
 * order), the same input map, the same tets (tet for tet), whatever the number of ranks.
 * Each tet of that mesh is owned by exactly one rank, which returns it.  The algorithm (a
 * sample-based kd partition into tiles, local triangulations of tile + ghost points, an
 * exact conflict exchange until no rank receives a new point, ownership by the smallest
 * vertex id) and its proof are in proofs/distributed.md.
 *
 * Collective: every rank of comm calls it, with its own points (any number, 0 included).
 * Errors are agreed on: every rank returns the same status and the same gtet_error (a NaN
 * on one rank is GTET_ERR_NONFINITE on all of them, with the smallest global index); a
 * failed call returns nothing and leaks nothing.  The library never prints or exits.
 *
 * Include this header (it includes mpi.h and gigatet.h) and link libgigatet_mpi,
 * libgigatet and MPI's C library.
 */
#ifndef GIGATET_MPI_H
#define GIGATET_MPI_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

#include "gigatet.h"

#ifdef __cplusplus
extern "C" {
#endif

/* first_index: the global input index of this rank's first point (its points are
 * first_index, first_index + 1, ...).  The ranks' ranges must be disjoint and cover
 * [0, total points).  GTET_MPI_AUTO_INDEX on every rank: the points are numbered rank by
 * rank (an exclusive prefix sum of the counts). */
#define GTET_MPI_AUTO_INDEX UINT64_MAX
/* A global tet id or vertex id that does not exist (a hull facet's neighbour). */
#define GTET_MPI_NO_TET UINT64_MAX
/* The same in a 32-bit result (gtet_mpi_options.id_bits = 32); equal to GTET_NO_TET. */
#define GTET_MPI_NO_TET32 UINT32_MAX

typedef struct gtet_mpi_stats {
    int ranks;                  /* size of the communicator */
    int rounds;                 /* exchange rounds this run needed (the same on every rank): 1
                                   when the seeded ghost layer was already enough; each later
                                   round re-triangulates only its new points' cavity */
    int rebuilds;               /* later rounds in which this rank triangulated its whole
                                   local set again instead (0 unless that cavity could not be
                                   patched: proofs/distributed.md D9) */
    int scans;                  /* later rounds in which this rank found the new points'
                                   cavity by testing every local tet instead of locating
                                   each point (0 unless a walk failed: D10) */
    uint64_t tile_points;       /* distinct points of this rank's tile */
    uint64_t ghost_points;      /* other tiles' points this rank triangulated with its own */
    uint64_t ghost_seeded;      /* ... of which it received in the seeding step */
    uint64_t queries_sent;      /* conflict queries (circumballs, hull halfspaces) it sent */
    uint64_t bytes_sent;        /* bytes it sent to other ranks, all steps (MPI payload) */
    uint64_t bytes_sent_ghost;  /* ... of which for ghost points and queries */
    uint64_t answer_tests;      /* exact conflict tests (insphere, hull rule) its answers to
                                   other ranks' queries made: near-linear in the points on every
                                   input (proofs/distributed.md D12) */
    int answer_lifts;           /* rounds in which it answered the circumball queries from a
                                   triangulation of its tile and their vertices (D12) instead
                                   of scanning its tile's grid */
    uint64_t answers_near;      /* its answers to tet queries that held more points than a
                                   threshold and were cut to those near the asker's box, as
                                   hull facets' answers are (proofs/distributed.md step 6c) */
    double seconds_validate;    /* NaN scan, duplicates, global vertex ids, dimension */
    double seconds_partition;   /* kd tiles from a sample, points to their tiles */
    double seconds_triangulate; /* local gtet_triangulate calls, summed over rounds */
    double seconds_exchange;    /* ghost seeding, queries and their answers */
    double seconds_output;      /* ownership, global tet ids, neighbours */
    double seconds_total;
} gtet_mpi_stats;

typedef struct gtet_mpi_result {
    /* global figures (equal on every rank) */
    uint64_t num_points_global;   /* input points over all ranks */
    uint64_t num_vertices;        /* distinct points: global vertex ids are 0..num_vertices-1 */
    uint64_t num_duplicates;
    uint64_t num_tets_global;     /* tets of the global mesh */
    uint64_t num_hull_facets;     /* its hull facets */
    /* this rank's input points: the global vertex id of each (duplicates: their first) */
    size_t num_points;
    uint64_t *input_map;
    /* the tets this rank owns, global ids tet_offset .. tet_offset + num_tets - 1; the
       global tets are numbered rank by rank: rank r owns [tet_offsets[r], tet_offsets[r+1]) */
    size_t num_tets;
    int id_bits;                  /* 64: the owned tets are in tets and neighbors (tets32 and
                                     neighbors32 NULL); 32: in tets32 and neighbors32 (tets
                                     and neighbors NULL), asked for with gtet_mpi_options and
                                     given only when the global counts fit, see below.  The
                                     same on every rank */
    uint64_t *tets;               /* 4 global vertex ids per tet, positively oriented */
    uint64_t *neighbors;          /* global tet id across the facet opposite vertex i, on any
                                     rank, or GTET_MPI_NO_TET on the hull */
    uint32_t *tets32;             /* the same ids as tets, 32 bits */
    uint32_t *neighbors32;        /* the same as neighbors, GTET_MPI_NO_TET32 on the hull */
    uint64_t tet_offset;
    uint64_t *tet_offsets;        /* ranks + 1 entries */
    /* the distinct points of this rank's tile (every global vertex is in exactly one tile) */
    size_t num_tile_vertices;
    uint64_t *tile_vertex_ids;
    double *tile_vertices;        /* 3 per vertex: the coordinates of its first occurrence */
    /* the vertices the owned tets use (tile and ghost points), sorted by global id */
    size_t num_used_vertices;
    uint64_t *used_vertex_ids;
    double *used_vertices;
    gtet_mpi_stats stats;
} gtet_mpi_result;

/* Collective.  opts as for gtet_triangulate (threads per rank; opts->error filled on
 * failure with the agreed error; check: each rank runs the exact checker on its local
 * triangulation and the ranks check their shared facets, see gtet_check_mpi; input_done, when
 * set, is called once on each rank as soon as the run has copied that rank's points, after
 * the duplicate step: the caller may free xyz from then on).  On success
 * *result is filled (free it with gtet_mpi_result_free); on failure it is zeroed. */
GTET_API gtet_status gtet_triangulate_mpi(MPI_Comm comm, const double *xyz, size_t n,
                                          uint64_t first_index, const gtet_options *opts,
                                          gtet_mpi_result *result);

/* What gtet_triangulate_mpi_opt adds to gtet_options.  Fill with gtet_mpi_options_init,
 * then set what differs. */
typedef struct gtet_mpi_options {
    /* The width of the result's tet rows and neighbours: 64 (the default) or 32.  With 32,
     * result->id_bits is 32 when the global mesh's vertex and tet counts are both below
     * GTET_MPI_NO_TET32 (every id and tet id then fits, and GTET_MPI_NO_TET32 is no id);
     * otherwise the call falls back to a 64-bit result (id_bits 64), never failing or
     * truncating for it.  A 32-bit result is the rank's local rows, written in place; a
     * 64-bit one takes twice their memory (gtet_triangulate's own result is 32-bit).
     * The vertex ids of input_map, tile_vertex_ids and used_vertex_ids stay 64-bit. */
    int id_bits;
} gtet_mpi_options;

/* Fill *mopts with the defaults above (id_bits 64). */
GTET_API void gtet_mpi_options_init(gtet_mpi_options *mopts);

/* gtet_triangulate_mpi with gtet_mpi_options (mopts NULL: the defaults; then it is
 * gtet_triangulate_mpi).  Collective; mopts->id_bits must be 32 or 64, the same on every
 * rank (GTET_ERR_ARGUMENT on every rank otherwise).  The environment variable
 * GTET_MPI_IDS32_LIMIT=N (for tests) lowers the largest count a 32-bit result is given for
 * to N, so that small inputs take the fallback. */
GTET_API gtet_status gtet_triangulate_mpi_opt(MPI_Comm comm, const double *xyz, size_t n,
                                              uint64_t first_index, const gtet_options *opts,
                                              const gtet_mpi_options *mopts,
                                              gtet_mpi_result *result);

GTET_API void gtet_mpi_result_free(gtet_mpi_result *result);   /* NULL-safe; zeroes it */

/* Collective: the cross-rank part of the checker on a result of either id width.  Every owned
 * tet positively oriented (exact), every neighbour link symmetric (the tet across names this
 * one back, wherever it lives) with the two tets sharing the facet's three vertices and lying
 * on opposite sides of it, every interior facet locally Delaunay in the perturbed sense
 * (gtet_insphere_sos with the apex across, fetched from its rank), every global vertex used by
 * some tet.  (With opts.check, gtet_triangulate_mpi adds the full exact checker, gtet_check, on
 * each rank's local triangulation.)  GTET_OK or GTET_ERR_CHECK_FAILED on every rank,
 * report->message saying the first failure; report->tets counts the global tets,
 * report->hull_facets the hull facets, report->facets_checked the interior links. */
GTET_API gtet_status gtet_check_mpi(MPI_Comm comm, const gtet_mpi_result *result,
                                    gtet_check_report *report);

#ifdef __cplusplus
}
#endif
#endif /* GIGATET_MPI_H */
