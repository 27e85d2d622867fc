/* expansion.c -- the expansion operations of expansion.h (Shewchuk 1997, written from the
 * paper's theorems; the numbering below refers to it).
 *
 * Correctness: each routine only forms Two-Sums / Two-Products of its components, which are
 * exact under the band assumption of expansion.h, and emits the error terms in increasing
 * magnitude.  With round-to-nearest-even the outputs are strongly nonoverlapping (Theorems 13
 * and 19), which is the input condition of the next operation; zero components are dropped
 * (this changes no sum and keeps expansions short: on integer-like data most error terms are 0).
 */
#include "expansion.h"

int exp_two_two_diff(double a, double b, double c, double d, double *h)
{
    double e[2], f[2];
    exp_two_prod(a, b, &e[1], &e[0]);
    exp_two_prod(c, d, &f[1], &f[0]);
    f[0] = -f[0];
    f[1] = -f[1];
    /* drop zero tails so that exp_sum sees zero-free expansions */
    int el = 0, fl = 0;
    double ee[2], ff[2];
    for (int i = 0; i < 2; i++) {
        if (e[i] != 0) ee[el++] = e[i];
        if (f[i] != 0) ff[fl++] = f[i];
    }
    return exp_sum(el, ee, fl, ff, h);
}

/* Theorem 13 (Fast-Expansion-Sum): merge e and f by increasing magnitude into g, then
 * Q_2 + h_1 = g_1 + g_2 and Q_i + h_{i-1} = Q_{i-1} + g_i; the last Q is the top component.
 * We use Two-Sum at every step (Fast-Two-Sum would need |Q| >= |g_i| or the paper's
 * argument; Two-Sum is always exact), and merge on the fly. */
int exp_sum(int elen, const double *e, int flen, const double *f, double *h)
{
    int i = 0, j = 0, n = 0;
    double q, hh;
    if (elen == 0 || flen == 0) {
        const double *src = elen ? e : f;
        int len = elen ? elen : flen;
        for (int k = 0; k < len; k++) h[k] = src[k];
        return len;
    }
    /* |f_j| > |e_i|  <=>  (f_j > e_i) == (f_j > -e_i)  (no fabs, one branch) */
    double en = e[0], fn = f[0];
    if ((fn > en) == (fn > -en)) {
        q = en;
        en = ++i < elen ? e[i] : 0;
    } else {
        q = fn;
        fn = ++j < flen ? f[j] : 0;
    }
    while (i < elen && j < flen) {
        if ((fn > en) == (fn > -en)) {
            exp_two_sum(q, en, &q, &hh);
            en = ++i < elen ? e[i] : 0;
        } else {
            exp_two_sum(q, fn, &q, &hh);
            fn = ++j < flen ? f[j] : 0;
        }
        if (hh != 0) h[n++] = hh;
    }
    for (; i < elen; i++) {
        exp_two_sum(q, e[i], &q, &hh);
        if (hh != 0) h[n++] = hh;
    }
    for (; j < flen; j++) {
        exp_two_sum(q, f[j], &q, &hh);
        if (hh != 0) h[n++] = hh;
    }
    if (q != 0 || n == 0) h[n++] = q;
    if (n == 1 && h[0] == 0) n = 0;
    return n;
}

/* Theorem 19 (Scale-Expansion): Q_2 + h_1 = e_1 * b; then for each further component,
 * T_i + t_i = e_i * b, Q' + h = Q + t_i, Q + h' = T_i + Q' (Fast-Two-Sum: |T_i| >= |Q'| by the
 * theorem). */
int exp_scale(int elen, const double *e, double b, double *h)
{
    int n = 0;
    double q, hh, t_hi, t_lo, s;
    if (elen == 0 || b == 0) return 0;
    exp_two_prod(e[0], b, &q, &hh);
    if (hh != 0) h[n++] = hh;
    for (int i = 1; i < elen; i++) {
        exp_two_prod(e[i], b, &t_hi, &t_lo);
        exp_two_sum(q, t_lo, &s, &hh);
        if (hh != 0) h[n++] = hh;
        exp_fast_two_sum(t_hi, s, &q, &hh);
        if (hh != 0) h[n++] = hh;
    }
    if (q != 0 || n == 0) h[n++] = q;
    if (n == 1 && h[0] == 0) n = 0;
    return n;
}

int exp_mul(int elen, const double *e, int flen, const double *f, double *h, double *tmp,
            double *tmp2)
{
    /* h accumulates sum_j e * f_j; alternate between h and tmp so no call aliases. */
    double *acc = h, *other = tmp;
    int n = 0;
    for (int j = 0; j < flen; j++) {
        int m = exp_scale(elen, e, f[j], tmp2);
        int k = exp_sum(n, acc, m, tmp2, other);
        double *sw = acc;
        acc = other;
        other = sw;
        n = k;
    }
    if (acc != h)
        for (int k = 0; k < n; k++) h[k] = acc[k];
    return n;
}

/* Compress (Shewchuk 1997, section 2.8): a top-down sweep of Fast-Two-Sums accumulates the
 * components into as few as possible, keeping every non-zero error term (so the sum is
 * unchanged: each step is exact), then a bottom-up sweep does the same from the other end;
 * Fast-Two-Sum's precondition holds because the running sum Q dominates the component added
 * (nonoverlapping input in increasing magnitude).  The result is nonadjacent, in increasing
 * magnitude, without zeros (except a single 0 for a zero input, which we drop). */
int exp_compress(int elen, const double *e, double *h)
{
    if (elen == 0) return 0;
    int bottom = elen - 1;
    double q = e[bottom], qn, t;
    for (int i = elen - 2; i >= 0; i--) {
        exp_fast_two_sum(q, e[i], &qn, &t);
        if (t != 0) {
            h[bottom--] = qn;
            q = t;
        } else {
            q = qn;
        }
    }
    int top = 0;
    for (int i = bottom + 1; i < elen; i++) {
        exp_fast_two_sum(h[i], q, &qn, &t);
        if (t != 0) h[top++] = t;
        q = qn;
    }
    if (q != 0) h[top++] = q;
    return top;
}
