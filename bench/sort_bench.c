/* sort_bench.c -- timings of the spatial sort (not a test).
 *
 * For n uniform points in the unit cube (32-byte records, as the kernel stores vertices) and
 * 1 and 2 threads: Moore keys with 21 bits per axis, the radix sort of the (key, index) pairs
 * on 63 bits, keys + sort with the bits a BRIO round of n points uses (sort_brio_bits), the
 * whole BRIO order (shuffle + rounds), and qsort of the same 63-bit pairs for comparison
 * (the seed paper's Table 2: 10M points in 0.23 s on 4 cores, qsort 3.16 s).  Each figure is
 * the median of `runs` runs; inputs are regenerated identically before each run.
 *
 * Usage: sort_bench [runs] [n ...]     (default: 5 runs, n = 1000000 10000000)
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, CLOCK_PROCESS_CPUTIME_ID */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sort/sort.h"

typedef struct pair {
    uint64_t key;
    uint32_t idx;
} pair;

static int pair_cmp(const void *a, const void *b)
{
    const pair *x = a, *y = b;
    return x->key < y->key ? -1 : x->key > y->key;
}

static int dbl_cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *t, int runs)
{
    qsort(t, (size_t)runs, sizeof *t, dbl_cmp);
    return runs % 2 ? t[runs / 2] : 0.5 * (t[runs / 2 - 1] + t[runs / 2]);
}

/* CPU time of the whole process: on a shared machine, a steadier measure of the work than
 * the wall clock (for 2 threads it is the sum over both). */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static uint64_t rng_next(uint64_t *s)
{
    return sort_hash64(*s += 0x9e3779b97f4a7c15ULL);
}

/* One line per thread count for n points; 1 on a failure (printed). */
static int bench_size(size_t n, int runs)
{
    double *xyz = malloc(4 * n * sizeof *xyz);
    uint64_t *keys = malloc(n * sizeof *keys), *tk = malloc(n * sizeof *tk);
    uint32_t *idx = malloc(n * sizeof *idx), *ti = malloc(n * sizeof *ti);
    pair *pairs = malloc(n * sizeof *pairs);
    if (!xyz || !keys || !tk || !idx || !ti || !pairs) {
        fprintf(stderr, "sort_bench: out of memory for n = %zu\n", n);
        return 1;
    }
    uint64_t st = 12345;
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++)
            xyz[4 * i + a] = (double)(rng_next(&st) >> 11) * 0x1p-53;
        xyz[4 * i + 3] = 0.0;
    }
    const double box[6] = {0, 0, 0, 1, 1, 1};
    const int bb = sort_brio_bits(n);
    double tq[99], cq[99];
    for (int r = 0; r < runs; r++) {
        sort_moore_keys(xyz, 4, n, box, 21, keys, 2);
        for (size_t i = 0; i < n; i++)
            pairs[i] = (pair){keys[i], (uint32_t)i};
        double c0 = cpu_now(), t0 = omp_get_wtime();
        qsort(pairs, n, sizeof *pairs, pair_cmp);
        tq[r] = omp_get_wtime() - t0;
        cq[r] = cpu_now() - c0;
    }
    const double qs = median(tq, runs), qc = median(cq, runs);
    for (int thr = 1; thr <= 2; thr++) {
        double tkeys[99], tsort[99], tb[99], tbrio[99], csort[99];
        for (int r = 0; r < runs; r++) {
            double t0 = omp_get_wtime();
            sort_moore_keys(xyz, 4, n, box, 21, keys, thr);
            double t1 = omp_get_wtime();
            for (size_t i = 0; i < n; i++)
                idx[i] = (uint32_t)i;
            double c2 = cpu_now(), t2 = omp_get_wtime();
            sort_radix_pairs(keys, idx, n, 63, tk, ti, thr);
            double t3 = omp_get_wtime();
            csort[r] = cpu_now() - c2;
            tkeys[r] = t1 - t0;
            tsort[r] = t3 - t2;
            for (size_t i = 1; i < n; i++)
                if (keys[i - 1] > keys[i]) {
                    fprintf(stderr, "sort_bench: not sorted!\n");
                    return 1;
                }
            for (size_t i = 0; i < n; i++)
                idx[i] = (uint32_t)i;
            t0 = omp_get_wtime();
            sort_moore_keys(xyz, 4, n, box, bb, keys, thr);
            sort_radix_pairs(keys, idx, n, 3 * bb, tk, ti, thr);
            tb[r] = omp_get_wtime() - t0;
            for (size_t i = 0; i < n; i++)
                idx[i] = (uint32_t)i;
            size_t end[64];
            int rounds;
            t0 = omp_get_wtime();
            if (sort_brio(xyz, 4, idx, n, 7, 2048, 7.5, end, &rounds, thr) != GTET_OK) {
                fprintf(stderr, "sort_bench: sort_brio failed\n");
                return 1;
            }
            tbrio[r] = omp_get_wtime() - t0;
        }
        const double mk = median(tkeys, runs), ms = median(tsort, runs);
        const double mb = median(tb, runs), mbr = median(tbrio, runs);
        printf("%10zu %3d %9.4f %9.4f %9.4f %8.4f(%2d) %9.4f %8.1fx %9.4f %9.4f\n", n, thr,
               mk, ms, qs, mb, 3 * bb, mbr, qs / ms, median(csort, runs), qc);
        fflush(stdout);
    }
    free(xyz); free(keys); free(tk); free(idx); free(ti); free(pairs);
    return 0;
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 5;
    if (runs < 1 || runs > 99)
        runs = 5;
    size_t sizes[16] = {1000000, 10000000};
    int nsizes = 2;
    if (argc > 2) {
        nsizes = 0;
        for (int a = 2; a < argc && nsizes < 16; a++)
            sizes[nsizes++] = (size_t)strtoull(argv[a], NULL, 10);
    }
    char load[64] = "?";
    FILE *f = fopen("/proc/loadavg", "r");  /* the machine may be shared: say how busy */
    if (f) {
        if (!fgets(load, sizeof load, f))
            strcpy(load, "?\n");
        fclose(f);
    }
    printf("# sort_bench: median of %d runs, seconds; omp_get_max_threads() = %d; loadavg %s",
           runs, omp_get_max_threads(), load);
    printf("%10s %3s %9s %9s %9s %12s %9s %9s %9s %9s\n", "n", "thr", "keys63", "radix63",
           "qsort63", "keys+radixB", "brio", "speedup", "cpu:radix", "cpu:qsort");
    for (int s = 0; s < nsizes; s++) {
        if (bench_size(sizes[s], runs)) return 1;
    }
    printf("# keys63: Moore keys, 21 bits/axis; radix63: sort_radix_pairs on 63 bits;\n"
           "# qsort63: qsort of the same (key, idx) pairs, 1 thread; keys+radixB: keys and sort\n"
           "# with the BRIO bits for n points (key bits in parentheses); brio: sort_brio\n"
           "# (first 2048, ratio 7.5); speedup = qsort63 / radix63 (wall clock);\n"
           "# cpu:radix / cpu:qsort: process CPU time of radix63 / qsort63.\n");
    return 0;
}
