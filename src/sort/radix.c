/* radix.c -- stable radix sort of (uint64 key, uint32 index) pairs on the low key_bits bits.
 *
 * Three regimes, by size:
 *   - n <= 64: insertion sort (stable: an element moves left only past strictly larger keys);
 *   - small n, or one thread and n < RADIX_HYBRID_MIN: serial LSD (least significant digit
 *     first) counting passes, all digit histograms counted in one read of the keys; a pass
 *     whose digits are all equal is skipped (few distinct values, constant high bits);
 *   - large n: the hybrid of HXT and the seed paper: one MSD pass on the top 4..11 bits,
 *     chosen for about 4096 pairs per bucket (parallel: per-thread histograms of contiguous
 *     chunks, a prefix over buckets then threads, scatter), then every bucket -- a few
 *     thousand pairs that fit in cache -- is finished by the serial LSD on the remaining bits
 *     (OpenMP dynamic schedule).  A bucket holding a large share of n (skewed keys) is
 *     instead finished by parallel LSD passes; if the top digit is constant, nothing moved
 *     and the hybrid recurses on the lower bits.
 * Digits are at most 11 bits (2048 buckets, the paper's "radix up to 2048"); fewer for small
 * buckets, so that clearing the histograms does not dominate.
 *
 * Why it is correct: every counting pass is stable (items are scattered in input order, and
 * in the parallel version thread t's chunk precedes thread t+1's and gets the lower offsets
 * within each bucket), and an LSD sequence of stable passes from the least significant digit
 * up sorts stably on the digits' union.  The MSD pass partitions stably by the top digit, so
 * sorting each bucket stably on the remaining bits sorts the whole.  A stable sort's output
 * is unique, hence independent of the thread count.
 */
#include "sort.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define RADIX_BITS 11
#define RADIX_SIZE (1u << RADIX_BITS)
#define RADIX_INSERTION_MAX 64
#define RADIX_PARALLEL_MIN 32768    /* below: one thread */
#define RADIX_HYBRID_MIN 65536      /* from here: MSD pass + per-bucket LSD */
#define RADIX_MAX_PASSES 6          /* ceil(64 / 11) */
#define RADIX_MAX_THREADS 256       /* histograms: 16 KiB per thread */
#define RADIX_BUCKET_LOG2 12        /* the hybrid aims at 2^12 pairs per MSD bucket */

static inline uint64_t low_mask(int bits)
{
    return bits >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << bits) - 1u);
}

static void insertion_sort(uint64_t *k, uint32_t *ix, size_t n, uint64_t mask)
{
    for (size_t i = 1; i < n; i++) {
        const uint64_t kk = k[i], m = kk & mask;
        const uint32_t ii = ix[i];
        size_t j = i;
        while (j > 0 && (k[j - 1] & mask) > m) {
            k[j] = k[j - 1];
            ix[j] = ix[j - 1];
            j--;
        }
        k[j] = kk;
        ix[j] = ii;
    }
}

static int floor_log2(size_t m)
{
    int l = -1;
    while (m) {
        m >>= 1;
        l++;
    }
    return l;
}

/* Stable sort of the m pairs (ak, ai) on key bits [0, nbits), m <= UINT32_MAX; (bk, bi) is
 * scratch of m entries.  The result lands in (bk, bi) if to_b, else in (ak, ai). */
static void lsd_serial(uint64_t *ak, uint32_t *ai, uint64_t *bk, uint32_t *bi, size_t m,
                       int nbits, int to_b)
{
    if (m <= RADIX_INSERTION_MAX || nbits <= 0) {
        insertion_sort(ak, ai, m, low_mask(nbits));
        if (to_b) {
            memcpy(bk, ak, m * sizeof *ak);
            memcpy(bi, ai, m * sizeof *ai);
        }
        return;
    }
    /* digit width: at most 11 bits, and about m/2 buckets for small m */
    int rcap = floor_log2(m) - 1;
    rcap = rcap < 4 ? 4 : rcap > RADIX_BITS ? RADIX_BITS : rcap;
    /* passes <= 16 and passes << r <= ceil(64 / 11) << 11: the histograms fit in cnt[] */
    const int passes = (nbits + rcap - 1) / rcap;
    const int r = (nbits + passes - 1) / passes;
    const size_t nb = (size_t)1 << r;
    uint64_t pmask[16];  /* the last digit may be narrower */
    for (int p = 0; p < passes; p++)
        pmask[p] = low_mask(nbits - p * r < r ? nbits - p * r : r);
    uint32_t cnt[RADIX_MAX_PASSES * RADIX_SIZE];
    memset(cnt, 0, (size_t)passes * nb * sizeof *cnt);
    for (size_t i = 0; i < m; i++) {
        const uint64_t key = ak[i];
        for (int p = 0; p < passes; p++)
            cnt[(size_t)p * nb + ((key >> (p * r)) & pmask[p])]++;
    }
    uint64_t *sk = ak, *dk = bk;
    uint32_t *si = ai, *di = bi;
    for (int p = 0; p < passes; p++) {
        uint32_t *c = cnt + (size_t)p * nb;
        const int shift = p * r;
        const uint64_t pm = pmask[p];
        if (c[(sk[0] >> shift) & pm] == m)
            continue;  /* one digit value: the pass would not move anything */
        uint32_t sum = 0;
        for (size_t b = 0; b < nb; b++) {
            const uint32_t t = c[b];
            c[b] = sum;
            sum += t;
        }
        for (size_t i = 0; i < m; i++) {
            const uint32_t pos = c[(sk[i] >> shift) & pm]++;
            dk[pos] = sk[i];
            di[pos] = si[i];
        }
        uint64_t *tk = sk; sk = dk; dk = tk;
        uint32_t *ti = si; si = di; di = ti;
    }
    uint64_t *wk = to_b ? bk : ak;
    uint32_t *wi = to_b ? bi : ai;
    if (sk != wk) {
        memcpy(wk, sk, m * sizeof *sk);
        memcpy(wi, si, m * sizeof *si);
    }
}

/* One stable counting pass of (sk, si)[0..n) on the digit (key >> shift) & dmask into
 * (dk, di), with `threads` threads and hist of threads * RADIX_SIZE entries.  If bstart is not
 * NULL it receives the bucket starts (RADIX_SIZE + 1 entries).  Returns 0, without moving
 * anything, when all digits are equal. */
static int count_pass(const uint64_t *sk, const uint32_t *si, uint64_t *dk, uint32_t *di,
                      size_t n, int shift, uint64_t dmask, int threads, size_t *hist,
                      size_t *bstart)
{
    const size_t nb = (size_t)dmask + 1;
    int moved = 1;
#pragma omp parallel num_threads(threads)
    {
        const size_t nt = (size_t)omp_get_num_threads(), t = (size_t)omp_get_thread_num();
        const size_t lo = n / nt * t + (t < n % nt ? t : n % nt);
        const size_t hi = lo + n / nt + (t < n % nt ? 1 : 0);
        size_t *h = hist + t * RADIX_SIZE;
        memset(h, 0, nb * sizeof *h);
        for (size_t i = lo; i < hi; i++)
            h[(sk[i] >> shift) & dmask]++;
#pragma omp barrier
#pragma omp single
        {
            size_t sum = 0;
            for (size_t b = 0; b < nb; b++) {
                const size_t before = sum;
                if (bstart)
                    bstart[b] = sum;
                for (size_t u = 0; u < nt; u++) {
                    const size_t c = hist[u * RADIX_SIZE + b];
                    hist[u * RADIX_SIZE + b] = sum;
                    sum += c;
                }
                if (sum - before == n)
                    moved = 0;
            }
            if (bstart)
                bstart[nb] = sum;
        }
        if (moved) {
            for (size_t i = lo; i < hi; i++) {
                const size_t pos = h[(sk[i] >> shift) & dmask]++;
                dk[pos] = sk[i];
                di[pos] = si[i];
            }
        }
    }
    return moved;
}

static void copy_pairs(uint64_t *dk, uint32_t *di, const uint64_t *sk, const uint32_t *si,
                       size_t n, int threads)
{
    const int nt = n >= RADIX_PARALLEL_MIN ? threads : 1;
    const size_t block = 65536;
    const size_t nblocks = (n + block - 1) / block;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t b = 0; b < nblocks; b++) {
        const size_t lo = b * block, len = n - lo < block ? n - lo : block;
        memcpy(dk + lo, sk + lo, len * sizeof *dk);
        memcpy(di + lo, si + lo, len * sizeof *di);
    }
}

/* Stable LSD sort of (k, ix)[0..n) on bits [0, nbits) with parallel passes of <= 11 bits;
 * result in (k, ix). */
static void lsd_parallel(uint64_t *k, uint32_t *ix, uint64_t *tk, uint32_t *ti, size_t n,
                         int nbits, int threads, size_t *hist)
{
    const int passes = (nbits + RADIX_BITS - 1) / RADIX_BITS;
    const int r = (nbits + passes - 1) / passes;
    uint64_t *sk = k, *dk = tk;
    uint32_t *si = ix, *di = ti;
    for (int p = 0; p < passes; p++) {
        const int shift = p * r;
        const int w = nbits - shift < r ? nbits - shift : r;
        if (count_pass(sk, si, dk, di, n, shift, low_mask(w), threads, hist, NULL)) {
            uint64_t *xk = sk; sk = dk; dk = xk;
            uint32_t *xi = si; si = di; di = xi;
        }
    }
    if (sk != k)
        copy_pairs(k, ix, sk, si, n, threads);
}

/* MSD pass on the top 11 of key_bits bits into (tk, ti), then each bucket sorted on the rest
 * back into (k, ix).  key_bits > RADIX_BITS. */
static void hybrid(uint64_t *k, uint32_t *ix, uint64_t *tk, uint32_t *ti, size_t n,
                   int key_bits, int threads, size_t *hist, size_t *bstart)
{
    /* top digit: about 4096 pairs per bucket (they and their histograms stay in cache) */
    int top = floor_log2(n) - RADIX_BUCKET_LOG2;
    top = top < 4 ? 4 : top > RADIX_BITS ? RADIX_BITS : top;
    const int low = key_bits - top;
    const size_t nb = (size_t)1 << top;
    if (!count_pass(k, ix, tk, ti, n, low, nb - 1, threads, hist, bstart)) {
        /* one top digit (constant high bits): nothing moved, recurse on the low bits */
        if (low > RADIX_BITS)
            hybrid(k, ix, tk, ti, n, low, threads, hist, bstart);
        else
            lsd_parallel(k, ix, tk, ti, n, low, threads, hist);
        return;
    }
    /* a bucket larger than this is finished by parallel passes (skewed keys), as is one
     * that would overflow the 32-bit counters of lsd_serial */
    const size_t big = threads > 1 ? n / (2 * (size_t)threads) : (size_t)UINT32_MAX;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (threads > 1)
    for (size_t b = 0; b < nb; b++) {
        const size_t lo = bstart[b], m = bstart[b + 1] - lo;
        if (m == 0 || (m > big && m > RADIX_HYBRID_MIN) || m > UINT32_MAX)
            continue;
        lsd_serial(tk + lo, ti + lo, k + lo, ix + lo, m, low, 1);
    }
    for (size_t b = 0; b < nb; b++) {
        const size_t lo = bstart[b], m = bstart[b + 1] - lo;
        if (m == 0 || !((m > big && m > RADIX_HYBRID_MIN) || m > UINT32_MAX))
            continue;
        copy_pairs(k + lo, ix + lo, tk + lo, ti + lo, m, threads);
        lsd_parallel(k + lo, ix + lo, tk + lo, ti + lo, m, low, threads, hist);
    }
}

void sort_radix_pairs(uint64_t *keys, uint32_t *idx, size_t n, int key_bits,
                      uint64_t *tmp_keys, uint32_t *tmp_idx, int threads)
{
    if (n < 2 || key_bits <= 0)
        return;
    if (key_bits > 64)
        key_bits = 64;
    if (n <= RADIX_INSERTION_MAX) {
        insertion_sort(keys, idx, n, low_mask(key_bits));
        return;
    }
    if (threads < 1 || n < RADIX_PARALLEL_MIN)
        threads = 1;
    if (threads > RADIX_MAX_THREADS)
        threads = RADIX_MAX_THREADS;
    if (threads == 1 && (n < RADIX_HYBRID_MIN || key_bits <= RADIX_BITS) && n <= UINT32_MAX) {
        lsd_serial(keys, idx, tmp_keys, tmp_idx, n, key_bits, 0);
        return;
    }
    size_t stack_hist[RADIX_SIZE], stack_bstart[RADIX_SIZE + 1];
    size_t *hist = stack_hist, *bstart = stack_bstart, *heap = NULL;
    if (threads > 1) {
        heap = malloc(((size_t)threads * RADIX_SIZE + RADIX_SIZE + 1) * sizeof *heap);
        if (heap) {
            hist = heap;
            bstart = heap + (size_t)threads * RADIX_SIZE;
        } else {
            threads = 1;  /* no memory for per-thread histograms: serial, same result */
        }
    }
    if (n < RADIX_HYBRID_MIN || key_bits <= RADIX_BITS)
        lsd_parallel(keys, idx, tmp_keys, tmp_idx, n, key_bits, threads, hist);
    else
        hybrid(keys, idx, tmp_keys, tmp_idx, n, key_bits, threads, hist, bstart);
    free(heap);
}

/* The highest bit where the two masked keys of a descent differ, -1 when there is none. */
static int descent_level(const uint64_t *keys, size_t n, uint64_t mask, int threads)
{
    int level = -1;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : level) \
    if (threads > 1 && n >= RADIX_PARALLEL_MIN)
    for (size_t i = 1; i < n; i++) {
        const uint64_t a = keys[i - 1] & mask, b = keys[i] & mask;
        if (a > b) {
            const int h = 63 - __builtin_clzll(a ^ b);
            if (h > level) level = h;
        }
    }
    return level;
}

/* The end of the run of equal bits above `low` starting at lo, and whether it holds a descent. */
static size_t group_end(const uint64_t *keys, size_t n, size_t lo, uint64_t mask, int low,
                        int *unsorted)
{
    const uint64_t top = (keys[lo] & mask) >> low;
    size_t hi = lo + 1;
    *unsorted = 0;
    for (; hi < n && ((keys[hi] & mask) >> low) == top; hi++)
        *unsorted |= (keys[hi - 1] & mask) > (keys[hi] & mask);
    return hi;
}

void sort_radix_pairs_grouped(uint64_t *keys, uint32_t *idx, size_t n, int key_bits,
                              uint64_t *tmp_keys, uint32_t *tmp_idx, int threads)
{
    if (n < 2 || key_bits <= 0)
        return;
    if (key_bits > 64)
        key_bits = 64;
    if (threads < 1)
        threads = 1;
    const uint64_t mask = low_mask(key_bits);
    const int level = descent_level(keys, n, mask, threads);
    if (level < 0)
        return;
    const int low = level + 1;  /* bits 0..level are sorted; bits above are in order */
    if (low >= key_bits) {
        sort_radix_pairs(keys, idx, n, key_bits, tmp_keys, tmp_idx, threads);
        return;
    }
    /* small groups in parallel, one thread each, in a first sweep; the long ones after.
     * Thread k takes the groups that start in [n k / T, n (k + 1) / T): their bounds start[k]
     * are found before the barrier, so no thread reads keys another one is sorting. */
    size_t start[RADIX_MAX_THREADS + 1];
    const int T = threads > RADIX_MAX_THREADS ? RADIX_MAX_THREADS : threads;
#pragma omp parallel num_threads(T) if (T > 1 && n >= RADIX_PARALLEL_MIN)
    {
        const int nt = omp_get_num_threads(), k = omp_get_thread_num();
        size_t lo = n / (size_t)nt * (size_t)k;
        while (lo > 0 && lo < n && ((keys[lo - 1] & mask) >> low) == ((keys[lo] & mask) >> low))
            lo++;  /* a group that starts before the chunk is the previous thread's */
        start[k] = lo;
        if (k == 0)
            start[nt] = n;
#pragma omp barrier
        for (size_t end = start[k + 1]; lo < end;) {
            int unsorted;
            const size_t hi = group_end(keys, end, lo, mask, low, &unsorted);
            if (unsorted && hi - lo < RADIX_PARALLEL_MIN)
                sort_radix_pairs(keys + lo, idx + lo, hi - lo, low, tmp_keys + lo, tmp_idx + lo, 1);
            lo = hi;
        }
    }
    for (size_t lo = 0; lo < n;) {
        int unsorted;
        const size_t hi = group_end(keys, n, lo, mask, low, &unsorted);
        if (unsorted && hi - lo >= RADIX_PARALLEL_MIN)
            sort_radix_pairs(keys + lo, idx + lo, hi - lo, low, tmp_keys + lo, tmp_idx + lo,
                             threads);
        lo = hi;
    }
}
