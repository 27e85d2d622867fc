/* fuzz_predicates.c -- libFuzzer target: the predicates of src/pred against the independent
 * GMP oracle of src/oracle on adversarial point sets.
 *
 * The bytes give five points a, b, c, d, e in one of three modes (first byte):
 *   0  every coordinate from fz_coord's families (raw doubles, small integers, 1-ulp
 *      neighbours, +-2^1000 and 2^-1000 scales, denormals, small dyadics);
 *   1  small-integer points (grids: orient3d and insphere are often exactly 0) scaled by one
 *      common power of two 2^s, s in [-1070, 1000] (exact, so degeneracies survive);
 *   2  integer points of one sphere x^2+y^2+z^2 = r2 (co-spherical: insphere exactly 0),
 *      one coordinate optionally moved by a few ulps, all scaled by 2^s.
 * Properties (each a claim of src/pred/pred.h):
 *   - pred_orient3d, pred_insphere == orc_orient3d, orc_insphere (exact signs);
 *   - pred_insphere_sos == orc_insphere_sos; never 0 for five distinct points with
 *     orient3d(a,b,c,d) != 0; antisymmetric: swapping a and b flips it (a check of the
 *     symbolic perturbation, whose result depends only on the points);
 *   - pred_coplanar_orientation == orc_coplanar_orientation;
 *   - pred_ghost_conflict == orc_ghost_conflict for distinct a, b, c, e with a, b, c not
 *     collinear, and never 0 there;
 *   - pred_incircle_coplanar_sos == orc_coplanar_circle_sos when all four are coplanar.
 * The oracle shares no code with src/pred, so agreement is evidence for both.
 */
#include "fuzz_common.h"

#include "oracle/oracle.h"
#include "pred/pred.h"

static int same_point(const double *p, const double *q)
{
    return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

static void dump(const double p[5][3])
{
    for (int i = 0; i < 5; i++)
        fprintf(stderr, "  p%d = (%a, %a, %a)\n", i, p[i][0], p[i][1], p[i][2]);
}

/* r2 values with many integer points on their sphere */
static const int SPHERE_R2[8] = {2, 3, 9, 11, 25, 27, 50, 81};

static void sphere_point(int r2, unsigned pick, double out[3])
{
    int r = 0;
    while ((r + 1) * (r + 1) <= r2) r++;
    unsigned count = 0;
    for (int pass = 0; pass < 2; pass++) {
        unsigned k = 0;
        for (int x = -r; x <= r; x++)
            for (int y = -r; y <= r; y++)
                for (int z = -r; z <= r; z++) {
                    if (x * x + y * y + z * z != r2) continue;
                    if (pass == 1 && k == pick % count) {
                        out[0] = x;
                        out[1] = y;
                        out[2] = z;
                        return;
                    }
                    k++;
                }
        count = k;
    }
}

static void make_points(fz_bytes *b, double p[5][3])
{
    uint8_t mode = fz_u8(b) % 3;
    if (mode == 0) {
        double prev[15];
        size_t np = 0;
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < 3; k++) {
                p[i][k] = fz_coord(b, prev, np);
                prev[np++] = p[i][k];
            }
        return;
    }
    int s = (int)(fz_u64(b) % 2071) - 1070;
    int r2 = SPHERE_R2[fz_u8(b) % 8];
    for (int i = 0; i < 5; i++) {
        if (mode == 1) {
            for (int k = 0; k < 3; k++) p[i][k] = (double)fz_small_int(b);
        } else {
            sphere_point(r2, fz_u8(b), p[i]);
        }
    }
    if (mode == 2 && (fz_u8(b) & 1)) {
        uint8_t w = fz_u8(b) % 15;
        p[w / 3][w % 3] = fz_ulps(p[w / 3][w % 3], (int)(fz_u8(b) % 7) - 3);
    }
    for (int i = 0; i < 5; i++)
        for (int k = 0; k < 3; k++) p[i][k] = ldexp(p[i][k], s);  /* exact unless underflow */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_bytes b = {data, size, 0};
    double p[5][3];
    make_points(&b, p);
    const double *a = p[0], *bb = p[1], *c = p[2], *d = p[3], *e = p[4];
    pred_counters cnt;
    memset(&cnt, 0, sizeof cnt);

    int o = pred_orient3d(a, bb, c, d, &cnt);
    int oo = orc_orient3d(a, bb, c, d);
    if (o != oo) dump((const double(*)[3])p);
    FZ_ASSERT(o == oo, "orient3d %d, oracle %d", o, oo);

    int s = pred_insphere(a, bb, c, d, e, &cnt);
    int so = orc_insphere(a, bb, c, d, e);
    if (s != so) dump((const double(*)[3])p);
    FZ_ASSERT(s == so, "insphere %d, oracle %d", s, so);

    int distinct = 1;
    for (int i = 0; i < 5; i++)
        for (int j = i + 1; j < 5; j++)
            if (same_point(p[i], p[j])) distinct = 0;
    if (distinct && o != 0) {
        int ss = pred_insphere_sos(a, bb, c, d, e, &cnt);
        int sso = orc_insphere_sos(a, bb, c, d, e);
        int sw = pred_insphere_sos(bb, a, c, d, e, &cnt);
        if (ss == 0 || ss != sso || sw != -ss) dump((const double(*)[3])p);
        FZ_ASSERT(ss != 0, "insphere_sos is 0 for distinct points, orient %d", o);
        FZ_ASSERT(ss == sso, "insphere_sos %d, oracle %d", ss, sso);
        FZ_ASSERT(sw == -ss, "insphere_sos not antisymmetric: %d then %d", ss, sw);
        if (s != 0) FZ_ASSERT(ss == s, "insphere_sos %d differs from non-zero insphere %d", ss, s);
    }

    int co = pred_coplanar_orientation(a, bb, c, &cnt);
    int coo = orc_coplanar_orientation(a, bb, c);
    if (co != coo) dump((const double(*)[3])p);
    FZ_ASSERT(co == coo, "coplanar_orientation %d, oracle %d", co, coo);

    int abce_distinct = !same_point(a, bb) && !same_point(a, c) && !same_point(bb, c) &&
                        !same_point(a, e) && !same_point(bb, e) && !same_point(c, e);
    if (abce_distinct && coo != 0) {
        int g = pred_ghost_conflict(a, bb, c, e, &cnt);
        int go = orc_ghost_conflict(a, bb, c, e);
        if (g != go || g == 0) dump((const double(*)[3])p);
        FZ_ASSERT(g != 0, "ghost_conflict is 0");
        FZ_ASSERT(g == go, "ghost_conflict %d, oracle %d", g, go);
        if (orc_orient3d(a, bb, c, e) == 0) {
            int ic = pred_incircle_coplanar_sos(a, bb, c, e, &cnt);
            int ico = orc_coplanar_circle_sos(a, bb, c, e);
            if (ic != ico) dump((const double(*)[3])p);
            FZ_ASSERT(ic == ico, "incircle_coplanar_sos %d, oracle %d", ic, ico);
        }
    }
    return 0;
}
