/* validate.c -- input validation: finite coordinates, exact duplicates, affine dimension.
 *
 * Duplicates: an open-addressing hash table keyed by the coordinates' bit patterns, with -0.0
 * folded onto +0.0 before hashing and compared with ==, so two points are duplicates exactly
 * when their coordinates compare equal.  The first occurrence becomes the vertex; every later
 * copy maps to it (nothing the user gave is lost: the map says where each point went).
 * Dimension: one linear scan with the exact predicates; no quartic search.
 */
#include "validate.h"

#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEDUP_AHEAD 16

void kval_error(gtet_error *err, gtet_status status, size_t index, int dimension,
                const char *fmt, ...)
{
    if (!err) return;
    err->status = status;
    err->index = index;
    err->dimension = dimension;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
}

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
    kval_error(err, GTET_ERR_NONFINITE, first / 3, -1, "point %zu has a %s %c coordinate",
               first / 3, isnan(xyz[first]) ? "NaN" : "infinite", "xyz"[first % 3]);
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
        kval_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
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

/* The same with T threads, and the same result (vertex ids in order of first occurrence):
 *   1. every point is inserted into a shared open-addressing table of input indices by
 *      compare-and-swap: an empty slot is claimed once and its point never changes, so equal
 *      points meet in one slot, which keeps the smallest index of them (atomic minimum); the
 *      slot of every point is remembered (pos);
 *   2. after the barrier, point i is a first occurrence iff its slot holds i; each thread
 *      counts those of its contiguous chunk and notes, for the others, the index of their
 *      first occurrence (map[i] = that index for the moment);
 *   3. a prefix sum over the chunks numbers the first occurrences in input order; each thread
 *      copies its chunk's and gives them their ids;
 *   4. after the barrier, a duplicate takes the id of its first occurrence (map[map[i]]).
 * Only step 1 writes shared memory concurrently, through atomics. */
#define DEDUP_MAX_THREADS 256
#define DEDUP_EMPTY UINT32_MAX

static gtet_status dedup_parallel(const double *xyz, size_t n, int T, double **verts_out,
                                  uint32_t **map_out, size_t *nv_out, gtet_error *err)
{
    size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    uint32_t *table = malloc(cap * sizeof *table);
    uint32_t *pos = malloc(n * sizeof *pos);  /* cap <= 2^32: n < 2^31 (gtet_triangulate) */
    uint32_t *map = malloc(n * sizeof *map);
    double *verts = malloc(3 * n * sizeof *verts);
    uint8_t *dup = malloc(n);
    if (!table || !pos || !map || !verts || !dup) {
        free(table);
        free(pos);
        free(map);
        free(verts);
        free(dup);
        kval_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
                   "out of memory checking %zu points for duplicates", n);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    const size_t mask = cap - 1;
    size_t lo[DEDUP_MAX_THREADS + 1], firsts[DEDUP_MAX_THREADS], base[DEDUP_MAX_THREADS];
    for (int k = 0; k <= T; k++) lo[k] = n / (size_t)T * (size_t)k;
    lo[T] = n;
#pragma omp parallel num_threads(T)
    {
        const int k = omp_get_thread_num();
        const size_t a = lo[k], b = lo[k + 1];
#pragma omp for schedule(static)
        for (size_t s = 0; s < cap; s++) table[s] = DEDUP_EMPTY;
        /* 1. (the implicit barrier of the loop above ends the clearing) */
        size_t ring[DEDUP_AHEAD];
        for (size_t i = a; i < b && i < a + DEDUP_AHEAD; i++) {
            ring[(i - a) % DEDUP_AHEAD] = (size_t)point_hash(xyz + 3 * i) & mask;
            __builtin_prefetch(table + ring[(i - a) % DEDUP_AHEAD], 1);
        }
        for (size_t i = a; i < b; i++) {
            const double *p = xyz + 3 * i;
            size_t h = ring[(i - a) % DEDUP_AHEAD];
            if (i + DEDUP_AHEAD < b) {
                const size_t ha = (size_t)point_hash(xyz + 3 * (i + DEDUP_AHEAD)) & mask;
                ring[(i - a) % DEDUP_AHEAD] = ha;
                __builtin_prefetch(table + ha, 1);
            }
            const uint32_t me = (uint32_t)i;
            for (;;) {
                uint32_t v = __atomic_load_n(&table[h], __ATOMIC_ACQUIRE);
                if (v == DEDUP_EMPTY) {
                    if (__atomic_compare_exchange_n(&table[h], &v, me, 0, __ATOMIC_ACQ_REL,
                                                    __ATOMIC_ACQUIRE))
                        break;
                    /* another point claimed the slot first: v is its index */
                }
                const double *q = xyz + 3 * (size_t)v;
                if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
                    while (me < v && !__atomic_compare_exchange_n(&table[h], &v, me, 0,
                                                                  __ATOMIC_ACQ_REL,
                                                                  __ATOMIC_ACQUIRE)) {
                    }
                    break;
                }
                h = (h + 1) & mask;
            }
            pos[i] = (uint32_t)h;
        }
#pragma omp barrier
        /* 2. */
        size_t cnt = 0;
        for (size_t i = a; i < b; i++) {
            const uint32_t rep = table[pos[i]];
            map[i] = rep;
            dup[i] = rep != (uint32_t)i;
            cnt += !dup[i];
        }
        firsts[k] = cnt;
#pragma omp barrier
#pragma omp single
        {
            size_t sum = 0;
            for (int j = 0; j < T; j++) {
                base[j] = sum;
                sum += firsts[j];
            }
        }
        /* 3. (the single's implicit barrier publishes base) */
        size_t vid = base[k];
        for (size_t i = a; i < b; i++) {
            if (dup[i]) continue;
            memcpy(verts + 3 * vid, xyz + 3 * i, 3 * sizeof *verts);
            map[i] = (uint32_t)vid++;
        }
#pragma omp barrier
        /* 4. */
        for (size_t i = a; i < b; i++)
            if (dup[i]) map[i] = map[map[i]];
    }
    size_t nv = 0;
    for (int k = 0; k < T; k++) nv += firsts[k];
    free(table);
    free(pos);
    free(dup);
    if (nv < n) {
        double *shrunk = realloc(verts, (nv ? 3 * nv : 3) * sizeof *verts);
        if (shrunk) verts = shrunk;
    }
    *verts_out = verts;
    *map_out = map;
    *nv_out = nv;
    return GTET_OK;
}

#define DEDUP_MIN_PARALLEL 131072  /* fewer points: the serial pass */

gtet_status kval_dedup(const double *xyz, size_t n, int threads, double **verts_out,
                       uint32_t **map_out, size_t *nv_out, gtet_error *err)
{
    *verts_out = NULL;
    *map_out = NULL;
    *nv_out = 0;
    int T = threads < 1 ? 1 : threads > DEDUP_MAX_THREADS ? DEDUP_MAX_THREADS : threads;
    while (T > 1 && n / (size_t)T < DEDUP_MIN_PARALLEL / 2) T--;
    if (T == 1) return dedup_serial(xyz, n, verts_out, map_out, nv_out, err);
    return dedup_parallel(xyz, n, T, verts_out, map_out, nv_out, err);
}

gtet_status kval_first_simplex(const double *verts, const uint32_t *order, size_t nv,
                               size_t pos[4], pred_counters *cnt, gtet_error *err)
{
    size_t i = 1;
    pos[0] = 0;
    if (nv == 0) {
        kval_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, -1,
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
    kval_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 0,
               "degenerate input of dimension 0: all points are equal (1 distinct point)");
    return GTET_ERR_DEGENERATE_INPUT;
dim1:
    kval_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 1,
               "degenerate input of dimension 1: all %zu distinct points are collinear", nv);
    return GTET_ERR_DEGENERATE_INPUT;
dim2:
    kval_error(err, GTET_ERR_DEGENERATE_INPUT, SIZE_MAX, 2,
               "degenerate input of dimension 2: all %zu distinct points are coplanar", nv);
    return GTET_ERR_DEGENERATE_INPUT;
}
