/* test_mpi_api.c -- gtet_triangulate_mpi through its C API, under mpirun -np 1..4:
 * explicit first_index ranges in reverse rank order, an empty rank, duplicates across ranks;
 * the input map, the tets and every neighbour link equal gtet_triangulate's on the whole set;
 * gtet_check_mpi accepts the result; the same with 32-bit ids (gtet_mpi_options), with the
 * fallback to 64 bits when GTET_MPI_IDS32_LIMIT says the counts do not fit, and a width that
 * is not 32 or 64 or differs between the ranks refused on every rank; opts.input_done is called exactly once on each rank (the
 * points poisoned with NaN and freed there: nothing reads them after); a NaN on the last rank
 * and overlapping index ranges give the same error on every rank; mx_pages_move (the output's
 * room lent the written pages of dead blocks, NOTES.md E221) keeps the pages already written at
 * the target, leaves both blocks mapped and writable, and the allocator sound. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gigatet_mpi.h"
#include "mpi/mpi_internal.h"

static int rank, size, fails;
#define CHECK(c, ...) do { if (!(c)) { fails++; fprintf(stderr, "rank %d: FAIL %s:%d: ", rank, __FILE__, __LINE__); \
    fprintf(stderr, __VA_ARGS__); fputc('\n', stderr); } } while (0)

static uint64_t rng = 88172645463325252ull;
static double rnd(void)
{
    rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static int cmp4(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    for (int k = 0; k < 4; k++) if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}
static void sort4(uint64_t *k)
{
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) { uint64_t t = k[j]; k[j] = k[j - 1]; k[j - 1] = t; }
}

/* opts.input_done: the caller's copy of its points, poisoned and freed when called */
typedef struct input_copy {
    double *p;
    size_t n;
    int calls;
} input_copy;

static void on_input_done(void *user)
{
    input_copy *c = user;
    c->calls++;
    if (!c->p) return;
    for (size_t i = 0; i < 3 * c->n; i++) c->p[i] = NAN;
    free(c->p);
    c->p = NULL;
}

/* mx_pages_move between two heap blocks: `to`'s first quarter written (it stands for the
 * compacted rows), the rest never written; `from` written throughout */
static void test_pages_move(void)
{
    const size_t fb = (size_t)6 << 20, tb = (size_t)16 << 20, w = tb / 4;
    unsigned char *from = malloc(fb), *to = malloc(tb);
    CHECK(from && to, "allocation");
    if (!from || !to) return;
    for (size_t i = 0; i < fb; i++) from[i] = (unsigned char)(i * 7 + 1);
    for (size_t i = 0; i < w; i++) to[i] = (unsigned char)(i * 13 + 5);
    long moved = mx_pages_move(from, fb, to, tb);
#if defined(__linux__)
    /* every whole page of `from` has a page of `to` never written to go to */
    CHECK(moved >= (long)(fb / 4096) - 2, "pages moved: %ld", moved);
#endif
    CHECK(moved >= 0, "pages move failed: %ld", moved);
    for (size_t i = 0; i < w; i++)
        if (to[i] != (unsigned char)(i * 13 + 5)) {
            CHECK(0, "a written page of the target was replaced (byte %zu)", i);
            break;
        }
    /* both blocks whole: every byte readable and writable */
    for (size_t i = 0; i < fb; i++) from[i] = (unsigned char)(i * 3);
    for (size_t i = 0; i < tb; i++) to[i] = (unsigned char)(i * 5);
    unsigned long sum = 0;
    for (size_t i = 0; i < fb; i++) sum += from[i] == (unsigned char)(i * 3);
    for (size_t i = 0; i < tb; i++) sum += to[i] == (unsigned char)(i * 5);
    CHECK(sum == fb + tb, "blocks after the move: %lu of %zu bytes kept", sum, fb + tb);
    free(from);
    free(to);
    /* the allocator: blocks over the same memory again */
    for (int k = 0; k < 8; k++) {
        unsigned char *p = malloc(((size_t)1 + (size_t)k) << 20);
        CHECK(p != NULL, "allocation after the move");
        if (p) memset(p, k, ((size_t)1 + (size_t)k) << 20);
        free(p);
    }
}

/* the result r (either width) against the single-process mesh ref of the whole set: the input
 * map of this rank's points [a, b), the counts, gtet_check_mpi, and on rank 0 the gathered tets
 * (the same set) and every neighbour (the same tet across the same facet) */
static void compare(const gtet_mpi_result *r, const gtet_mesh *ref, size_t a, size_t b)
{
    const uint32_t *map = gtet_mesh_input_map(ref);
    for (size_t i = a; i < b; i++) CHECK(r->input_map[i - a] == map[i], "input map of %zu", i);
    CHECK(r->num_vertices == gtet_mesh_num_vertices(ref), "vertices");
    CHECK(r->num_tets_global == gtet_mesh_num_tets(ref), "tets %llu vs %zu",
          (unsigned long long)r->num_tets_global, gtet_mesh_num_tets(ref));
    gtet_check_report rep;
    CHECK(gtet_check_mpi(MPI_COMM_WORLD, r, &rep) == GTET_OK, "check (%d bits): %s", r->id_bits,
          rep.message);
    /* this rank's rows as 64-bit ids (GTET_MPI_NO_TET32 as GTET_MPI_NO_TET) */
    uint64_t *lt = malloc((4 * r->num_tets + 1) * sizeof *lt), *ln = malloc((4 * r->num_tets + 1) * sizeof *ln);
    for (size_t i = 0; i < 4 * r->num_tets; i++) {
        if (r->id_bits == 32) {
            lt[i] = r->tets32[i];
            ln[i] = r->neighbors32[i] == GTET_MPI_NO_TET32 ? GTET_MPI_NO_TET : r->neighbors32[i];
        } else {
            lt[i] = r->tets[i];
            ln[i] = r->neighbors[i];
        }
    }
    /* gather tets and neighbours (global id order) to rank 0 */
    uint64_t T = r->num_tets_global;
    uint64_t *gt = malloc((4 * T + 1) * sizeof *gt), *gn = malloc((4 * T + 1) * sizeof *gn);
    int *cnt = malloc(2 * (size_t)size * sizeof *cnt), mine = (int)(4 * r->num_tets);
    MPI_Allgather(&mine, 1, MPI_INT, cnt, 1, MPI_INT, MPI_COMM_WORLD);
    for (int q = 0, at = 0; q < size; q++) { cnt[size + q] = at; at += cnt[q]; }
    MPI_Allgatherv(lt, mine, MPI_UINT64_T, gt, cnt, cnt + size, MPI_UINT64_T, MPI_COMM_WORLD);
    MPI_Allgatherv(ln, mine, MPI_UINT64_T, gn, cnt, cnt + size, MPI_UINT64_T, MPI_COMM_WORLD);
    if (rank == 0) {
        size_t nt = gtet_mesh_num_tets(ref);
        const uint32_t *rt = gtet_mesh_tets(ref), *rn = gtet_mesh_neighbors(ref);
        uint64_t (*rk)[5] = malloc(nt * sizeof *rk), (*dk)[5] = malloc(T * sizeof *dk);
        for (size_t t = 0; t < nt; t++) { for (int k = 0; k < 4; k++) rk[t][k] = rt[4 * t + k]; sort4(rk[t]); rk[t][4] = t; }
        for (uint64_t t = 0; t < T; t++) { for (int k = 0; k < 4; k++) dk[t][k] = gt[4 * t + k]; sort4(dk[t]); dk[t][4] = t; }
        qsort(rk, nt, sizeof *rk, cmp4);
        int same = T == nt;
        for (size_t t = 0; same && t < nt; t++) same = !cmp4(rk[t], dk[0]) || 1;
        /* set equality */
        uint64_t (*ds)[5] = malloc(T * sizeof *ds);
        memcpy(ds, dk, T * sizeof *ds);
        qsort(ds, T, sizeof *ds, cmp4);
        for (size_t t = 0; same && t < nt; t++) same = !cmp4(rk[t], ds[t]);
        CHECK(same, "the tets differ from the single-process mesh");
        /* neighbours: across the facet opposite vertex v, the same tet as in the reference */
        for (uint64_t t = 0; same && t < T; t++) {
            uint64_t *f = bsearch(dk[t], rk, nt, sizeof *rk, cmp4);
            size_t rt_i = (size_t)f[4];
            for (int k = 0; k < 4; k++) {
                uint64_t v = gt[4 * t + k], g = gn[4 * t + k];
                int rf = 0;
                while (rt[4 * rt_i + rf] != v) rf++;
                uint32_t rnb = rn[4 * rt_i + rf];
                if (rnb == GTET_NO_TET) { CHECK(g == GTET_MPI_NO_TET, "tet %llu: hull facet has a neighbour", (unsigned long long)t); continue; }
                uint64_t want[4];
                for (int j = 0; j < 4; j++) want[j] = rt[4 * (size_t)rnb + j];
                sort4(want);
                CHECK(g != GTET_MPI_NO_TET && g < T && !cmp4(dk[g], want), "tet %llu facet %d: wrong neighbour", (unsigned long long)t, k);
            }
        }
        free(rk); free(dk); free(ds);
        printf("api: %d ranks, %d-bit ids, %llu tets identical, neighbours identical, check ok\n", size, r->id_bits, (unsigned long long)T);
    }
    free(gt); free(gn); free(cnt); free(lt); free(ln);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    test_pages_move();
    const size_t N = 3000;
    double *all = malloc(3 * N * sizeof *all);
    for (size_t i = 0; i < N; i++) {
        if (i > 100 && i % 7 == 0) {   /* a duplicate of an earlier point */
            size_t j = (size_t)(rnd() * (double)(i - 1));
            memcpy(all + 3 * i, all + 3 * j, 3 * sizeof(double));
        } else {
            for (int k = 0; k < 3; k++) all[3 * i + k] = floor(rnd() * 64) / 8;  /* a lattice: ties */
        }
    }
    /* reference */
    gtet_mesh *ref = NULL;
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 1;
    if (gtet_triangulate(all, N, &o, &ref) != GTET_OK) { fprintf(stderr, "reference failed\n"); return 1; }
    /* slices: rank r gets chunk (size-1-r); with 3+ ranks rank 0 gets nothing */
    int chunks = size >= 3 ? size - 1 : size;
    int c = size >= 3 ? (rank == 0 ? -1 : size - 1 - rank) : size - 1 - rank;
    size_t a = c < 0 ? 0 : N * (size_t)c / (size_t)chunks, b = c < 0 ? 0 : N * (size_t)(c + 1) / (size_t)chunks;
    gtet_error err;
    o.error = &err;
    gtet_mpi_result r;
    input_copy in = {malloc((3 * (b - a) + 3) * sizeof(double)), b - a, 0};
    memcpy(in.p, all + 3 * a, 3 * (b - a) * sizeof(double));
    o.input_done = on_input_done;
    o.input_done_user = &in;
    gtet_status s = gtet_triangulate_mpi(MPI_COMM_WORLD, in.p, b - a, a, &o, &r);
    CHECK(s == GTET_OK, "status %d: %s", (int)s, err.message);
    CHECK(in.calls == 1, "input_done called %d times", in.calls);
    free(in.p);
    o.input_done = NULL;
    if (s == GTET_OK) {
        CHECK(r.id_bits == 64 && r.tets && !r.tets32, "the default result: id_bits %d", r.id_bits);
        compare(&r, ref, a, b);
        gtet_mpi_result_free(&r);
    }
    /* 32-bit ids asked for: given (the counts fit), the same mesh; then the fallback to 64 bits
     * (GTET_MPI_IDS32_LIMIT below the tet count; at the vertex count only the tets do not fit),
     * and the limit at the tet count (both fit, the boundary) */
    size_t nv = gtet_mesh_num_vertices(ref), ntr = gtet_mesh_num_tets(ref);
    struct { size_t limit; int want; } w[] = {{0, 32}, {nv, 64}, {ntr - 1, 64}, {ntr, 32}, {100, 64}};
    for (size_t k = 0; k < sizeof w / sizeof w[0]; k++) {
        char lim[32];
        snprintf(lim, sizeof lim, "%zu", w[k].limit);
        if (w[k].limit) setenv("GTET_MPI_IDS32_LIMIT", lim, 1);
        else unsetenv("GTET_MPI_IDS32_LIMIT");
        gtet_mpi_options mo;
        gtet_mpi_options_init(&mo);
        CHECK(mo.id_bits == 64, "gtet_mpi_options_init: id_bits %d", mo.id_bits);
        mo.id_bits = 32;
        s = gtet_triangulate_mpi_opt(MPI_COMM_WORLD, all + 3 * a, b - a, a, &o, &mo, &r);
        CHECK(s == GTET_OK, "32 bits, limit %s: status %d: %s", lim, (int)s, err.message);
        if (s != GTET_OK) continue;
        CHECK(r.id_bits == w[k].want, "32 bits asked, limit %s: id_bits %d, want %d", lim,
              r.id_bits, w[k].want);
        CHECK(r.id_bits == 32 ? r.tets32 && r.neighbors32 && !r.tets && !r.neighbors
                              : r.tets && r.neighbors && !r.tets32 && !r.neighbors32,
              "limit %s: the arrays of the other width", lim);
        compare(&r, ref, a, b);
        gtet_mpi_result_free(&r);
    }
    unsetenv("GTET_MPI_IDS32_LIMIT");
    /* a width that is not 32 or 64, and widths that differ between the ranks: refused on every
     * rank */
    for (int k = 0; k < (size > 1 ? 2 : 1); k++) {
        gtet_mpi_options mo;
        gtet_mpi_options_init(&mo);
        mo.id_bits = k == 0 ? 16 : rank == 0 ? 32 : 64;
        s = gtet_triangulate_mpi_opt(MPI_COMM_WORLD, all + 3 * a, b - a, a, &o, &mo, &r);
        CHECK(s == GTET_ERR_ARGUMENT, "id_bits %d: status %d", mo.id_bits, (int)s);
    }
    /* a NaN on the last rank: GTET_ERR_NONFINITE everywhere with its global index */
    double *mine_pts = malloc((3 * (b - a) + 3) * sizeof *mine_pts);
    memcpy(mine_pts, all + 3 * a, 3 * (b - a) * sizeof(double));
    if (rank == size - 1 && b - a > 5) mine_pts[3 * 5 + 1] = NAN;
    size_t nanidx = 0;
    { int lr = size - 1, lc = size >= 3 ? (lr == 0 ? -1 : size - 1 - lr) : size - 1 - lr;
      nanidx = N * (size_t)lc / (size_t)chunks + 5; }
    s = gtet_triangulate_mpi(MPI_COMM_WORLD, mine_pts, b - a, a, &o, &r);
    CHECK(s == GTET_ERR_NONFINITE && err.index == nanidx, "NaN: status %d index %zu (want %zu): %s", (int)s, err.index, nanidx, err.message);
    /* overlapping ranges */
    if (size > 1) {
        s = gtet_triangulate_mpi(MPI_COMM_WORLD, all, 10, 0, &o, &r);
        CHECK(s == GTET_ERR_ARGUMENT, "overlap: status %d", (int)s);
    }
    free(mine_pts);
    free(all);
    gtet_mesh_free(&ref);
    int tot = 0;
    MPI_Allreduce(&fails, &tot, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    MPI_Finalize();
    return tot ? 1 : 0;
}
