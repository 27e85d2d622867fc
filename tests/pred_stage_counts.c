/* pred_stage_counts.c -- how orient3d and insphere calls are decided, stage by stage, and
 * what each stage costs.  Research data for NOTES.md.
 *
 *   pred_stage_counts           1M random tuples in [0,1)^3; all 5-tuples of the 4^3 sub-grid
 *                               {0..3}^3 of the 20^3 grid; 1M random 5-tuples of distinct points
 *                               of the 20^3 grid {0..19}^3; 100k random 5-tuples of points
 *                               rounded onto the unit sphere; then ns per call of each stage.
 *   pred_stage_counts --timing  only the ns per call (CPU time of this thread).
 * "integer" counts both integer stages (small integers; the 60-bit integer form).
 *   pred_stage_counts --quick   20k random, the 3^3 sub-grid, 20k grid samples, no timing; checks
 *                               that the counters are consistent (exit status 1 if not): the
 *                               ctest test_pred_stage_counts_are_consistent.
 * For each 5-tuple (a,b,c,d,e): orient3d(a,b,c,d), then insphere(a,b,c,d,e) once: through
 * insphere_sos on the positively oriented tet (a,b swapped if needed) when orient3d != 0, plain
 * when the tet is flat.  So insphere calls = tuples; orient3d calls = tuples + the orient3d
 * evaluations of the perturbation.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "pred/filter.h"
#include "pred/pred_internal.h"
#include "pred_gen.h"
#include "testutil.h"

#include <string.h>
#include <time.h>

static int consistent = 1;

static void print_counts(const char *what, const gtet_pred_counters *c)
{
    unsigned long long oc = c->orient_calls, ic = c->insphere_calls;
    printf("%s\n", what);
    printf("  orient3d  calls %10llu  filter %10llu (%6.2f%%)  exact: integer %9llu  expansion %9llu"
           "  gmp %7llu  zero %9llu\n", oc, oc - c->orient_exact,
           oc ? 100.0 * (double)(oc - c->orient_exact) / (double)oc : 0.0,
           (unsigned long long)c->orient_int,
           (unsigned long long)(c->orient_exact - c->orient_int - c->orient_gmp),
           (unsigned long long)c->orient_gmp, (unsigned long long)c->orient_zero);
    printf("  insphere  calls %10llu  filter %10llu (%6.2f%%)  exact: integer %9llu (122-bit form"
           " %llu)  expansion %9llu  gmp %7llu  zero %9llu\n", ic, ic - c->insphere_exact,
           ic ? 100.0 * (double)(ic - c->insphere_exact) / (double)ic : 0.0,
           (unsigned long long)c->insphere_int, (unsigned long long)c->insphere_int122,
           (unsigned long long)(c->insphere_exact - c->insphere_int - c->insphere_gmp),
           (unsigned long long)c->insphere_gmp, (unsigned long long)c->insphere_zero);
    printf("  perturbation decisions %llu (term 1: %llu, term 2: %llu, term 3: %llu, term 4: %llu)\n",
           (unsigned long long)c->sos_calls, (unsigned long long)c->sos_depth[0],
           (unsigned long long)c->sos_depth[1], (unsigned long long)c->sos_depth[2],
           (unsigned long long)c->sos_depth[3]);
    if (c->orient_exact > c->orient_calls || c->orient_int + c->orient_gmp > c->orient_exact ||
        c->orient_zero > c->orient_exact || c->insphere_exact > c->insphere_calls ||
        c->insphere_int + c->insphere_gmp > c->insphere_exact ||
        c->insphere_int122 > c->insphere_int ||
        c->insphere_zero > c->insphere_exact ||
        c->sos_depth[0] + c->sos_depth[1] + c->sos_depth[2] + c->sos_depth[3] != c->sos_calls)
        consistent = 0;
}

static void tuple(gtet_pred_counters *c, const double *a, const double *b, const double *cc,
                  const double *d, const double *e)
{
    int o = pred_orient3d(a, b, cc, d, c);
    if (o > 0)
        pred_insphere_sos(a, b, cc, d, e, c); /* calls insphere once, then perturbs a zero */
    else if (o < 0)
        pred_insphere_sos(b, a, cc, d, e, c);
    else
        pred_insphere(a, b, cc, d, e, c);
}

static void random_tuples(long n)
{
    gtet_pred_counters c;
    memset(&c, 0, sizeof c);
    tu_rng r = {2026};
    double p[5][3];
    for (long t = 0; t < n; t++) {
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = tu_uniform(&r);
        tuple(&c, p[0], p[1], p[2], p[3], p[4]);
    }
    char what[128];
    snprintf(what, sizeof what, "%ld random 5-tuples, uniform in [0,1)^3:", n);
    print_counts(what, &c);
    if (c.orient_calls != (uint64_t)n) consistent = 0;
}

static void subgrid_all(int k)
{
    gtet_pred_counters c;
    memset(&c, 0, sizeof c);
    int np = k * k * k;
    double pts[64][3];
    for (int i = 0; i < np; i++)
        pts[i][0] = i % k, pts[i][1] = (i / k) % k, pts[i][2] = i / (k * k);
    long n = 0;
    for (int a = 0; a < np; a++)
        for (int b = a + 1; b < np; b++)
            for (int cc = b + 1; cc < np; cc++)
                for (int d = cc + 1; d < np; d++)
                    for (int e = d + 1; e < np; e++, n++)
                        tuple(&c, pts[a], pts[b], pts[cc], pts[d], pts[e]);
    char what[160];
    snprintf(what, sizeof what, "all %ld 5-tuples (i<j<k<l<m) of the %d^3 sub-grid {0..%d}^3 of the "
             "20^3 grid:", n, k, k - 1);
    print_counts(what, &c);
    if (c.insphere_zero == 0 || c.sos_calls == 0) consistent = 0;
}

static void grid_sample(long n)
{
    gtet_pred_counters c;
    memset(&c, 0, sizeof c);
    tu_rng r = {20};
    for (long t = 0; t < n; t++) {
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            int dup;
            do {
                for (int j = 0; j < 3; j++) p[i][j] = (double)tu_below(&r, 20);
                dup = 0;
                for (int l = 0; l < i; l++) dup |= pred_lex_cmp(p[l], p[i]) == 0;
            } while (dup);
        }
        tuple(&c, p[0], p[1], p[2], p[3], p[4]);
    }
    char what[128];
    snprintf(what, sizeof what, "%ld random 5-tuples of distinct points of the 20^3 grid {0..19}^3:", n);
    print_counts(what, &c);
}

static void sphere_sample(long n)
{
    gtet_pred_counters c;
    memset(&c, 0, sizeof c);
    tu_rng r = {77};
    for (long t = 0; t < n; t++) {
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            double v[3], n2;
            do {
                for (int j = 0; j < 3; j++) v[j] = 2 * tu_uniform(&r) - 1;
                n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            } while (n2 < 0.01 || n2 > 1);
            for (int j = 0; j < 3; j++) p[i][j] = v[j] / sqrt(n2);
        }
        tuple(&c, p[0], p[1], p[2], p[3], p[4]);
    }
    char what[128];
    snprintf(what, sizeof what, "%ld random 5-tuples of points rounded onto the unit sphere:", n);
    print_counts(what, &c);
}

/* ---- timing ---------------------------------------------------------------------------- */

#define NT 4096
static double tup[NT][5][3];
static volatile int sink;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

enum { K_RANDOM, K_GRID, K_SCALED_LATTICE, K_SPHERE };

static void fill(int kind)
{
    static int64_t lat[2048][3];
    int nl = pg_sphere_lattice(425, lat, 2048);
    tu_rng r = {(uint64_t)kind + 7};
    for (int t = 0; t < NT; t++)
        for (int i = 0; i < 5; i++) {
            if (kind == K_SPHERE) { /* rounded onto the unit sphere: inexact translations */
                double v[3], n2;
                do {
                    for (int j = 0; j < 3; j++) v[j] = 2 * tu_uniform(&r) - 1;
                    n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
                } while (n2 < 0.01 || n2 > 1);
                for (int j = 0; j < 3; j++) tup[t][i][j] = v[j] / sqrt(n2);
                continue;
            }
            const int64_t *l = lat[tu_below(&r, (uint64_t)nl)];
            for (int j = 0; j < 3; j++)
                tup[t][i][j] = kind == K_RANDOM ? tu_uniform(&r)
                             : kind == K_GRID   ? (double)tu_below(&r, 20)
                                                : ldexp((double)l[j], -7);
        }
}

typedef int (*stage_fn)(int t);
static int f_o_filter(int t) { return pred_orient3d_filter(tup[t][0], tup[t][1], tup[t][2], tup[t][3], PRED_NO_STATIC); }
static int f_i_filter(int t) { return pred_insphere_filter(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], PRED_NO_STATIC, NULL); }
static int f_o_int(int t) { int s = 0; pred_orient3d_int(tup[t][0], tup[t][1], tup[t][2], tup[t][3], &s); return s; }
static int f_i_int(int t) { int s = 0; pred_insphere_int(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &s); return s; }
static int f_o_wide(int t) { int s = 0; pred_orient3d_wide(tup[t][0], tup[t][1], tup[t][2], tup[t][3], &s); return s; }
static int f_i_wide(int t) { int s = 0; pred_insphere_wide(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &s); return s; }
static int f_o_exp(int t) { int s = 0; pred_orient3d_exp(tup[t][0], tup[t][1], tup[t][2], tup[t][3], &s); return s; }
static int f_i_exp(int t) { int s = 0; pred_insphere_exp(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &s); return s; }
static int f_o_gmp(int t) { return pred_orient3d_gmp(tup[t][0], tup[t][1], tup[t][2], tup[t][3]); }
static int f_i_w122(int t) { int s = 0; pred_insphere_wide122(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &s); return s; }
static int f_i_gmp(int t) { return pred_insphere_gmp(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4]); }
static gtet_pred_counters tc;
static int f_o_chain(int t) { return pred_orient3d(tup[t][0], tup[t][1], tup[t][2], tup[t][3], &tc); }
static int f_i_chain(int t) { return pred_insphere(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &tc); }
static int f_i_sos(int t) { return pred_insphere_sos(tup[t][0], tup[t][1], tup[t][2], tup[t][3], tup[t][4], &tc); }

static void time_stage(const char *name, int kind, stage_fn f, long calls)
{
    fill(kind);
    int s = 0;
    double t0 = now();
    for (long k = 0; k < calls; k++) s += f((int)(k & (NT - 1)));
    double dt = now() - t0;
    sink = s;
    printf("  %-44s %8.1f ns/call\n", name, 1e9 * dt / (double)calls);
}

static void timing(void)
{
    printf("CPU ns per call (one run, %d distinct tuples cycled):\n", NT);
    time_stage("orient3d filter, random [0,1)", K_RANDOM, f_o_filter, 5000000);
    time_stage("orient3d int path, 20^3 grid", K_GRID, f_o_int, 5000000);
    time_stage("orient3d expansions translated, lattice/2^7", K_SCALED_LATTICE, f_o_exp, 500000);
    time_stage("orient3d expansions translated, random [0,1)", K_RANDOM, f_o_exp, 200000);
    time_stage("orient3d expansions raw, unit sphere", K_SPHERE, f_o_exp, 200000);
    time_stage("orient3d 60-bit integer form, unit sphere", K_SPHERE, f_o_wide, 1000000);
    time_stage("orient3d gmp, random [0,1)", K_RANDOM, f_o_gmp, 300000);
    time_stage("orient3d full chain, random [0,1)", K_RANDOM, f_o_chain, 5000000);
    time_stage("orient3d full chain, 20^3 grid", K_GRID, f_o_chain, 5000000);
    time_stage("insphere filter, random [0,1)", K_RANDOM, f_i_filter, 5000000);
    time_stage("insphere int path, 20^3 grid", K_GRID, f_i_int, 5000000);
    time_stage("insphere expansions translated, lattice/2^7", K_SCALED_LATTICE, f_i_exp, 1000000);
    time_stage("insphere expansions translated, random [0,1)", K_RANDOM, f_i_exp, 100000);
    time_stage("insphere 60-bit integer form, unit sphere", K_SPHERE, f_i_wide, 1000000);
    time_stage("insphere 60-bit integer form, random [0,1)", K_RANDOM, f_i_wide, 1000000);
    time_stage("insphere 122-bit integer form, unit sphere", K_SPHERE, f_i_w122, 300000);
    time_stage("insphere gmp, unit sphere", K_SPHERE, f_i_gmp, 100000);
    time_stage("insphere full chain, unit sphere", K_SPHERE, f_i_chain, 100000);
    time_stage("insphere gmp, random [0,1)", K_RANDOM, f_i_gmp, 300000);
    time_stage("insphere full chain, random [0,1)", K_RANDOM, f_i_chain, 5000000);
    time_stage("insphere full chain, 20^3 grid", K_GRID, f_i_chain, 5000000);
    time_stage("insphere full chain, lattice sphere/2^7", K_SCALED_LATTICE, f_i_chain, 1000000);
    time_stage("insphere_sos, lattice sphere/2^7", K_SCALED_LATTICE, f_i_sos, 1000000);
}

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    if (argc > 1 && strcmp(argv[1], "--timing") == 0) {
        timing();
        return 0;
    }
    random_tuples(quick ? 20000 : 1000000);
    subgrid_all(quick ? 3 : 4);
    grid_sample(quick ? 20000 : 1000000);
    sphere_sample(quick ? 2000 : 100000);
    if (!quick) timing();
    printf(consistent ? "counters consistent\n" : "COUNTERS INCONSISTENT\n");
    return consistent ? 0 : 1;
}
