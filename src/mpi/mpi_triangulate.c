/* mpi_triangulate.c -- gtet_triangulate_mpi: the distributed Delaunay tetrahedrization whose
 * union of owned tets is exactly gtet_triangulate's mesh of all the points
 * (proofs/distributed.md has the algorithm's proof; the section names D1..D8 cited below are
 * its lemmas).
 *
 * Steps, each ended by a collective agreement on the status (mx_agree), so that no rank
 * waits in a collective that another rank has left:
 *   1. validate: input index ranges, a NaN/Inf anywhere (smallest global index);
 *   4. partition: a kd tree of boxes built by every rank from one gathered sample, one leaf
 *      (tile) per rank; points go to their tile, with their global input index;
 *   2. duplicates and global vertex ids: equal points share a tile, so when no tile holds two
 *      equal points there is no duplicate and the ids are the input indices; else points
 *      hashed by coordinates to a rank, which finds each point's first occurrence; ids = first
 *      occurrences in global input order (D1), and the first occurrences are partitioned again;
 *   3. dimension: the smallest-id affinely independent simplex (p0..p3), or an agreed
 *      GTET_ERR_DEGENERATE_INPUT naming the dimension;
 *   5. ghost seeding: each rank sends its points near another tile's bounding box to it;
 *   6. rounds: triangulate tile + ghosts (gtet_triangulate); query, for every tet and hull
 *      facet with a vertex of the tile that is new this round, the ranks whose bounding box
 *      the circumball (hull: the open side of the facet's plane) meets; they answer with
 *      their points in conflict (gtet_insphere_sos / gtet_ghost_conflict, exact) not sent
 *      before; until no rank receives a new point (D3-D5);
 *   7. ownership: a tet belongs to the rank whose tile holds its smallest vertex id; global
 *      tet ids rank by rank; neighbours across ranks by matching facets (D6-D7).
 *
 * The steps live in: mpi_ids.c (1-3), mpi_partition.c (4), mpi_ghosts.c (5-6, with the local
 * set and its triangulation), mpi_patch.c (a later round's cavity re-triangulation, D9),
 * mpi_query.c (the queries' geometry and their answers),
 * mpi_output.c (7, with mpi_pages.c: the result's room on the written pages of dead blocks);
 * mpi_internal.h declares what they share.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

void gtet_mpi_result_free(gtet_mpi_result *r)
{
    if (!r) return;
    free(r->input_map);
    free(r->tets);
    free(r->neighbors);
    free(r->tets32);
    free(r->neighbors32);
    free(r->tet_offsets);
    free(r->tile_vertex_ids);
    free(r->tile_vertices);
    free(r->used_vertex_ids);
    free(r->used_vertices);
    memset(r, 0, sizeof *r);
}

static void run_free(run *R)
{
    free(R->firsts_all);
    free(R->imap);
    free(R->fp);
    free(R->kd);
    free(R->tile);
    free(R->box);
    free(R->tcount);
    free(R->sp);
    free(R->sown);
    free(R->have.k);
    free(R->sent.k);
    free(R->sent_any);
    free(R->nsent);
    free(R->gr.start);
    free(R->gr.cb);
    free(R->gr.bb);
    free(R->gr.far);
    free(R->gr.sat);
    free(R->gr.pyr);
    free(R->prev);
    gtet_mesh_free(&R->mesh);
    free(R->ptv);
    free(R->ptn);
    free(R->c.sc);
}

/* the layer of ghost points sent before the first triangulation, in tile spacings */
#ifndef GTET_MPI_LAYER
#define GTET_MPI_LAYER 2.5
#endif

void gtet_mpi_options_init(gtet_mpi_options *mopts)
{
    if (!mopts) return;
    memset(mopts, 0, sizeof *mopts);
    mopts->id_bits = 64;
}

gtet_status gtet_triangulate_mpi(MPI_Comm comm, const double *xyz, size_t n,
                                 uint64_t first_index, const gtet_options *opts,
                                 gtet_mpi_result *result)
{
    return gtet_triangulate_mpi_opt(comm, xyz, n, first_index, opts, NULL, result);
}

/* the id width asked for (mopts->id_bits, 64 without mopts) into R->ids32: 32 or 64, the same
 * on every rank, as the output's collective steps depend on it.  Collective (one
 * MPI_Allreduce); GTET_ERR_ARGUMENT on this rank otherwise (the caller agrees on it) */
static gtet_status take_id_bits(run *R, const gtet_mpi_options *mopts)
{
    int b = mopts ? mopts->id_bits : 64;
    if (b != 32 && b != 64) b = 0;
    int mm[2] = {b, -b}, all[2];
    MPI_Allreduce(mm, all, 2, MPI_INT, MPI_MAX, R->c.comm);
    R->ids32 = b == 32;
    if (b == 0 || all[0] != -all[1])
        return mx_fail(&R->c, GTET_ERR_ARGUMENT, "rank %d: gtet_mpi_options.id_bits %s",
                       R->c.rank, b == 0 ? "must be 32 or 64" : "differs between the ranks");
    return GTET_OK;
}

gtet_status gtet_triangulate_mpi_opt(MPI_Comm comm, const double *xyz, size_t n,
                                     uint64_t first_index, const gtet_options *opts,
                                     const gtet_mpi_options *mopts, gtet_mpi_result *result)
{
    double t0 = mx_now();
    run R;
    memset(&R, 0, sizeof R);
    gtet_mpi_result res;
    memset(&res, 0, sizeof res);
    R.c.comm = comm;
    MPI_Comm_rank(comm, &R.c.rank);
    MPI_Comm_size(comm, &R.c.size);
    R.c.st = &res.stats;
    R.c.err.index = SIZE_MAX;
    R.c.err.dimension = -1;
    res.stats.ranks = R.c.size;
    gtet_options_init(&R.lopt);
    if (opts) R.lopt = *opts;
    R.lopt.check = 0;
    R.lopt.progress = NULL;
    R.lopt.degeneracies = 0;
    R.lopt.error = NULL;
    R.lopt.input_done = NULL;   /* the caller's: called once, below, not by the local runs */
    R.xyz = xyz;
    R.n = n;
    R.first = first_index;
    gtet_status s = GTET_OK;
    if (!result || (!xyz && n > 0) || (opts && opts->threads < 0))
        s = mx_fail(&R.c, GTET_ERR_ARGUMENT, "rank %d: %s", R.c.rank,
                    !result ? "result is NULL" : !xyz && n ? "xyz is NULL with n > 0"
                                                           : "threads < 0");
    R.c.sc = mx_malloc(4 * (size_t)R.c.size * sizeof(int));
    if (!R.c.sc && s == GTET_OK) s = mx_fail(&R.c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (R.c.sc) {
        R.c.sd = R.c.sc + R.c.size;
        R.c.rc = R.c.sd + R.c.size;
        R.c.rd = R.c.rc + R.c.size;
    }
    if ((s = mx_agree(&R.c, s)) != GTET_OK) goto fail;
    if ((s = mx_agree(&R.c, take_id_bits(&R, mopts))) != GTET_OK) goto fail;
    double t = mx_now(), tp = 0;
    if ((s = mx_agree(&R.c, mx_step_validate(&R))) != GTET_OK) goto fail;
    /* the caller's points partitioned with their input indices; when no tile holds two equal
     * points (no duplicate anywhere) they are the vertices with their ids, else the duplicates
     * are found and the first occurrences partitioned again (D1, NOTES.md E201) */
    double t1 = mx_now();
    if ((s = mx_agree(&R.c, mx_step_partition(&R))) != GTET_OK) goto fail;
    tp += mx_now() - t1;
    int dups = 0;
    if ((s = mx_step_distinct(&R, &dups)) != GTET_OK) goto fail;
    if (dups) {
        if ((s = mx_step_dedup(&R)) != GTET_OK) goto fail;
        t1 = mx_now();
        if ((s = mx_agree(&R.c, mx_step_partition(&R))) != GTET_OK) goto fail;
        tp += mx_now() - t1;
    }
    /* the caller's points are copied into the tiles and read no more: its input_done may free
     * them (gtet_options; the later steps can then take that memory) */
    R.xyz = NULL;
    if (opts && opts->input_done) opts->input_done(opts->input_done_user);
    if ((s = mx_agree(&R.c, mx_step_dimension(&R))) != GTET_OK) goto fail;
    res.stats.seconds_partition = tp;
    res.stats.seconds_validate = mx_now() - t - tp;
    t = mx_now();
    if ((s = mx_step_seed(&R, GTET_MPI_LAYER)) != GTET_OK) goto fail;
    res.stats.seconds_exchange = mx_now() - t;
    if ((s = mx_step_rounds(&R)) != GTET_OK) goto fail;
    res.stats.ghost_points = R.ns - R.m;
    if (opts && opts->check && R.mesh && !R.ptv) {
        /* the exact checker on this rank's local triangulation */
        double *pts = mx_malloc(3 * R.ns * sizeof *pts);
        if (!pts) {
            s = mx_fail(&R.c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        } else {
            for (size_t i = 0; i < R.ns; i++) memcpy(pts + 3 * i, R.sp[i].x, 3 * sizeof(double));
            gtet_check_report rep;
            s = gtet_check(R.mesh, pts, R.ns, 0, &rep);
            free(pts);
            if (s != GTET_OK)
                mx_fail(&R.c, s, "rank %d: local check: %s", R.c.rank, rep.message);
        }
    }
    if ((s = mx_agree(&R.c, s)) != GTET_OK) goto fail;
    t = mx_now();
    if ((s = mx_step_output(&R, &res)) != GTET_OK) goto fail;
    res.stats.seconds_output = mx_now() - t;
    res.num_points_global = R.N;
    res.num_vertices = R.V;
    res.num_duplicates = R.N - R.V;
    res.num_points = n;
    res.input_map = R.imap;
    R.imap = NULL;
    if (opts && opts->check) {
        gtet_check_report rep;
        s = gtet_check_mpi(comm, &res, &rep);
        if (s != GTET_OK) {
            mx_fail(&R.c, s, "%s", rep.message);
            goto fail;
        }
    }
    run_free(&R);
    res.stats.seconds_total = mx_now() - t0;
    *result = res;
    return GTET_OK;
fail:
    if (opts && opts->error) *opts->error = R.c.err;
    run_free(&R);
    gtet_mpi_result_free(&res);
    if (result) memset(result, 0, sizeof *result);
    return s;
}
