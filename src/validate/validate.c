/* validate.c -- input validation: finite coordinates, exact duplicates, affine dimension.
 *
 * Duplicates: open-addressing hash tables keyed by the coordinates' bit patterns, with -0.0
 * folded onto +0.0 before hashing and compared with ==, so two points are duplicates exactly
 * when their coordinates compare equal: one table below 65536 points, else one small table
 * per bucket of the hash (kval_dedup_partitioned).  The first occurrence becomes the vertex;
 * every later copy maps to it (nothing the user gave is lost: the map says where each point
 * went).
 * Dimension: one linear scan with the exact predicates; no quartic search.
 */
#include "validate.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "../base/base.h"

#define DEDUP_AHEAD 16

/* The first non-finite coordinate (smallest index, whatever the thread count). */
gtet_status kval_finite(const double *xyz, size_t n, int threads, gtet_error *err)
{
    const size_t n3 = 3 * n;
    size_t first = SIZE_MAX;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(min : first) \
    if (threads > 1 && n3 > 196608)
    for (size_t i = 0; i < n3; i++)
        if (!isfinite(xyz[i]) && i < first) first = i;
    if (first == SIZE_MAX) return GTET_OK;
    base_error(err, GTET_ERR_NONFINITE, first / 3, -1, "point %zu has %s %c coordinate",
               first / 3, isnan(xyz[first]) ? "a NaN" : "an infinite", "xyz"[first % 3]);
    return GTET_ERR_NONFINITE;
}

static uint64_t coord_bits(double x)
{
    uint64_t u;
    if (x == 0.0) x = 0.0;  /* fold -0.0 onto +0.0 */
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint64_t point_hash(const double *p)
{
    uint64_t h = coord_bits(p[0]) * 0x9e3779b97f4a7c15ULL;
    h ^= coord_bits(p[1]) + 0x632be59bd9b4e019ULL + (h << 6) + (h >> 2);
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= coord_bits(p[2]) + 0x94d049bb133111ebULL + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0x94d049bb133111ebULL;
    return h ^ (h >> 29);
}

static gtet_status dedup_serial(const double *xyz, size_t n, double **verts_out,
                                uint32_t **map_out, size_t *nv_out, gtet_error *err)
{
    *verts_out = NULL;
    *map_out = NULL;
    *nv_out = 0;
    size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    uint32_t *table = malloc(cap * sizeof *table);
    uint32_t *map = malloc((n ? n : 1) * sizeof *map);
    double *verts = malloc((n ? 3 * n : 3) * sizeof *verts);
    if (!table || !map || !verts) {
        free(table);
        free(map);
        free(verts);
        base_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
                   "out of memory checking %zu points for duplicates", n);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    memset(table, 0xff, cap * sizeof *table);
    size_t nv = 0;
    const size_t mask = cap - 1;
    /* the table is larger than the caches and a probe is a random access: the slots of the
     * next DEDUP_AHEAD points are hashed and prefetched ahead (ring[] holds their hashes) */
    size_t ring[DEDUP_AHEAD];
    for (size_t i = 0; i < n && i < DEDUP_AHEAD; i++) {
        ring[i] = (size_t)point_hash(xyz + 3 * i) & mask;
        __builtin_prefetch(table + ring[i]);
    }
    for (size_t i = 0; i < n; i++) {
        const double *p = xyz + 3 * i;
        size_t h = ring[i % DEDUP_AHEAD];
        if (i + DEDUP_AHEAD < n) {
            const size_t ha = (size_t)point_hash(xyz + 3 * (i + DEDUP_AHEAD)) & mask;
            ring[i % DEDUP_AHEAD] = ha;
            __builtin_prefetch(table + ha);
        }
        for (;;) {
            uint32_t v = table[h];
            if (v == UINT32_MAX) {
                table[h] = (uint32_t)nv;
                memcpy(verts + 3 * nv, p, 3 * sizeof *p);
                map[i] = (uint32_t)nv++;
                break;
            }
            const double *q = verts + 3 * (size_t)v;
            if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
                map[i] = v;
                break;
            }
            h = (h + 1) & mask;
        }
    }
    free(table);
    if (nv < n) {
        double *shrunk = realloc(verts, (nv ? 3 * nv : 3) * sizeof *verts);
        if (shrunk) verts = shrunk;
    }
    *verts_out = verts;
    *map_out = map;
    *nv_out = nv;
    return GTET_OK;
}

/* The same by partitions, on T >= 1 threads, with the same result (vertex ids in order of
 * first occurrence).  The single table above is larger than the caches: every point costs a
 * miss on its slot and one on the coordinates of the vertex it finds there, and a threaded
 * form of it (a shared table filled by compare-and-swap) gains little on two threads (NOTES.md
 * D5).  Here:
 *   1. every thread counts the points of its contiguous chunk per bucket (the top `bits` bits
 *      of the hash), and after a prefix sum (bucket-major, then chunk order) writes each point
 *      as (low 32 bits of its hash << 32 | index) into its bucket: within a bucket the indices
 *      increase (the hash is computed in both loops rather than stored: a streaming read of
 *      the coordinates is cheaper than 8 more bytes per point written and read back);
 *   2. the buckets (about DEDUP_BUCKET points each) are shared out between the threads; each
 *      is deduplicated with its own open-addressing table of twice its size, which with the
 *      bucket's entries fits in the cache, comparing hash tags first and coordinates only when
 *      the tags are equal; the first entry of a set of equal points has the smallest index, so
 *      every later one is marked a duplicate of it (dup, map = that index);
 *   3. each chunk counts its first occurrences, a prefix sum over the chunks numbers them in
 *      input order, and each thread copies its chunk's and gives them their ids;
 *   4. after the barrier, a duplicate takes the id of its first occurrence (map[map[i]]).
 * The entries and the tables live in the output array of vertices, 24 bytes per point, which
 * they fill to 16 (8 + 2 x 4) and which step 3 overwrites after a barrier.  No atomics: the
 * threads write disjoint buckets' tables and disjoint points' marks. */
#define DEDUP_MAX_THREADS 256
#define DEDUP_BUCKET 8192   /* points per bucket: entries and table 128 KB, in L2 */

static size_t dedup_slot(uint32_t tag, size_t size)
{
    return (size_t)(((uint64_t)tag * size) >> 32);  /* tag scaled to [0, size) */
}

/* The state the threads of kval_dedup_partitioned share. */
typedef struct dedup_part {
    const double *xyz;
    size_t n;
    int T, bits;
    size_t nb;             /* buckets: 2^bits */
    uint32_t *map;
    double *verts;
    uint8_t *dup;          /* per point: a later copy of an earlier point */
    size_t *cnt;           /* per chunk and bucket: counts, then write positions */
    size_t *bstart;        /* nb + 1 bucket starts */
    uint64_t *ent;         /* step 1's entries (in verts) */
    uint32_t *tab;         /* step 2's tables (in verts, after the entries) */
    size_t lo[DEDUP_MAX_THREADS + 1], firsts[DEDUP_MAX_THREADS], base[DEDUP_MAX_THREADS];
} dedup_part;

/* Step 1 for chunk k, in the parallel region: count per bucket, prefix sum, scatter. */
static void dedup_scatter(dedup_part *D, int k)
{
    const size_t a = D->lo[k], b = D->lo[k + 1], nb = D->nb;
    const int bits = D->bits, shift = 64 - bits;
    const double *xyz = D->xyz;
    uint64_t *ent = D->ent;
    size_t *c = D->cnt + (size_t)k * nb;
    memset(c, 0, nb * sizeof *c);
    memset(D->dup + a, 0, b - a);
    for (size_t i = a; i < b; i++) {
        const uint64_t h = point_hash(xyz + 3 * i);
        c[bits ? h >> shift : 0]++;
    }
#pragma omp barrier
#pragma omp single
    {
        size_t off = 0;
        for (size_t q = 0; q < nb; q++) {
            D->bstart[q] = off;
            for (int j = 0; j < D->T; j++) {
                const size_t x = D->cnt[(size_t)j * nb + q];
                D->cnt[(size_t)j * nb + q] = off;
                off += x;
            }
        }
        D->bstart[nb] = off;
    }
    for (size_t i = a; i < b; i++) {
        const uint64_t h = point_hash(xyz + 3 * i);
        ent[c[bits ? h >> shift : 0]++] = (h << 32) | (uint64_t)i;
    }
}

/* Step 2 for bucket q: a bucket of m entries has the 2m table slots from 2 * bstart. */
static void dedup_bucket(dedup_part *D, size_t q)
{
    const size_t s0 = D->bstart[q], m = D->bstart[q + 1] - s0, size = 2 * m;
    const uint64_t *e = D->ent + s0;
    const double *xyz = D->xyz;
    uint8_t *dup = D->dup;
    uint32_t *map = D->map;
    uint32_t *t = D->tab + 2 * s0;
    for (size_t j = 0; j < size; j++) t[j] = UINT32_MAX;
    for (size_t j = 0; j < m; j++) {
        const uint32_t tag = (uint32_t)(e[j] >> 32), i = (uint32_t)e[j];
        const double *p = xyz + 3 * (size_t)i;
        size_t h = dedup_slot(tag, size);
        for (;;) {
            const uint32_t v = t[h];
            if (v == UINT32_MAX) {
                t[h] = (uint32_t)j;
                break;
            }
            if ((uint32_t)(e[v] >> 32) == tag) {
                const uint32_t r = (uint32_t)e[v];
                const double *q3 = xyz + 3 * (size_t)r;
                if (q3[0] == p[0] && q3[1] == p[1] && q3[2] == p[2]) {
                    dup[i] = 1;
                    map[i] = r;
                    break;
                }
            }
            if (++h == size) h = 0;
        }
    }
}

/* Steps 3 and 4 for chunk k, in the parallel region, after every use of the scratch. */
static void dedup_number(dedup_part *D, int k)
{
    const size_t a = D->lo[k], b = D->lo[k + 1];
    const uint8_t *dup = D->dup;
    uint32_t *map = D->map;
    double *verts = D->verts;
    const double *xyz = D->xyz;
    size_t nf = 0;
    for (size_t i = a; i < b; i++) nf += !dup[i];
    D->firsts[k] = nf;
#pragma omp barrier
#pragma omp single
    {
        size_t sum = 0;
        for (int j = 0; j < D->T; j++) {
            D->base[j] = sum;
            sum += D->firsts[j];
        }
    }
    size_t vid = D->base[k];
    for (size_t i = a; i < b; i++) {
        if (dup[i]) continue;
        memcpy(verts + 3 * vid, xyz + 3 * i, 3 * sizeof *verts);
        map[i] = (uint32_t)vid++;
    }
#pragma omp barrier
    for (size_t i = a; i < b; i++)
        if (dup[i]) map[i] = map[map[i]];
}

gtet_status kval_dedup_partitioned(const double *xyz, size_t n, int T, double **verts_out,
                                   uint32_t **map_out, size_t *nv_out, gtet_error *err)
{
    *verts_out = NULL;
    *map_out = NULL;
    *nv_out = 0;
    dedup_part D;
    D.xyz = xyz;
    D.n = n;
    D.T = T < 1 ? 1 : T > DEDUP_MAX_THREADS ? DEDUP_MAX_THREADS : T;
    T = D.T;
    D.bits = 0;
    while (D.bits < 20 && (n >> D.bits) > DEDUP_BUCKET) D.bits++;
    D.nb = (size_t)1 << D.bits;
    D.map = base_alloc_big((n ? n : 1) * sizeof *D.map);
    D.verts = base_alloc_big((n ? 3 * n : 3) * sizeof *D.verts);
    D.dup = base_alloc_big(n ? n : 1);
    D.cnt = malloc((size_t)T * D.nb * sizeof *D.cnt);
    D.bstart = malloc((D.nb + 1) * sizeof *D.bstart);
    if (!D.map || !D.verts || !D.dup || !D.cnt || !D.bstart) {
        free(D.map);
        free(D.verts);
        free(D.dup);
        free(D.cnt);
        free(D.bstart);
        base_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
                   "out of memory checking %zu points for duplicates", n);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    D.ent = (uint64_t *)(void *)D.verts;  /* 24n bytes: entries (8n), then the tables (2 x 4n) */
    D.tab = (uint32_t *)(D.ent + n);
    for (int k = 0; k <= T; k++) D.lo[k] = n / (size_t)T * (size_t)k;
    D.lo[T] = n;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        const int k = omp_get_thread_num();
        dedup_scatter(&D, k);
#pragma omp barrier
#pragma omp for schedule(dynamic, 8)
        for (size_t q = 0; q < D.nb; q++) dedup_bucket(&D, q);
        /* the loop's implicit barrier ends every use of the scratch */
        dedup_number(&D, k);
    }
    size_t nv = 0;
    for (int k = 0; k < T; k++) nv += D.firsts[k];
    free(D.dup);
    free(D.cnt);
    free(D.bstart);
    double *verts = D.verts;
    if (nv < n) {
        double *shrunk = realloc(verts, (nv ? 3 * nv : 3) * sizeof *verts);
        if (shrunk) verts = shrunk;
    }
    *verts_out = verts;
    *map_out = D.map;
    *nv_out = nv;
    return GTET_OK;
}

#define DEDUP_MIN_PARTITIONED 65536  /* fewer points: the one table is in the cache */

gtet_status kval_dedup(const double *xyz, size_t n, int threads, double **verts_out,
                       uint32_t **map_out, size_t *nv_out, gtet_error *err)
{
    if (n < DEDUP_MIN_PARTITIONED) return dedup_serial(xyz, n, verts_out, map_out, nv_out, err);
    int T = threads < 1 ? 1 : threads;
    while (T > 1 && n / (size_t)T < DEDUP_MIN_PARTITIONED / 2) T--;
    return kval_dedup_partitioned(xyz, n, T, verts_out, map_out, nv_out, err);
}

gtet_status kval_first_simplex(const double *verts, const uint32_t *order, size_t nv,
                               size_t pos[4], pred_counters *cnt, gtet_error *err)
{
    size_t i = 1;
    pos[0] = 0;
    if (nv == 0) {
        base_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, -1,
                   "no points: a tetrahedrization needs at least 4 distinct points");
        return GTET_ERR_DEGENERATE_INPUT;
    }
    const double *a = verts + 3 * (size_t)order[0];
    /* vertices are distinct, so the second one differs from the first */
    if (nv < 2) goto dim0;
    pos[1] = 1;
    const double *b = verts + 3 * (size_t)order[1];
    for (i = 2; i < nv; i++)
        if (pred_coplanar_orientation(a, b, verts + 3 * (size_t)order[i], cnt) != 0) break;
    if (i == nv) goto dim1;
    pos[2] = i;
    const double *c = verts + 3 * (size_t)order[i];
    for (i = i + 1; i < nv; i++)
        if (pred_orient3d(a, b, c, verts + 3 * (size_t)order[i], cnt) != 0) break;
    if (i == nv) goto dim2;
    pos[3] = i;
    return GTET_OK;
dim0:
    base_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 0,
               "degenerate input of dimension 0: all points are equal (1 distinct point)");
    return GTET_ERR_DEGENERATE_INPUT;
dim1:
    base_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 1,
               "degenerate input of dimension 1: all %zu distinct points are collinear", nv);
    return GTET_ERR_DEGENERATE_INPUT;
dim2:
    base_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 2,
               "degenerate input of dimension 2: all %zu distinct points are coplanar", nv);
    return GTET_ERR_DEGENERATE_INPUT;
}
