/* fuzz_triangulate.c -- libFuzzer target: gtet_triangulate on small degenerate point sets.
 *
 * The bytes give up to MAX_POINTS points.  A header picks a scale 2^s and a family for the
 * set; then each point takes one of: a grid point (small integers: every insphere of a cube is
 * degenerate), an integer point of one sphere (co-spherical), a point of one plane, a point
 * of one line, a duplicate of an earlier point (with the sign of its zeros flipped), or a
 * point from fz_coord's adversarial families.  Most sets are a mixture, so near-degenerate
 * configurations of every kind meet.
 * Properties:
 *   - the status is GTET_ERR_DEGENERATE_INPUT exactly when the input is degenerate (fewer than
 *     4 distinct points, or all collinear / coplanar), decided here independently with the
 *     GMP oracle; otherwise GTET_OK and gtet_check passes (with the O(n*m) empty-sphere test
 *     for small sets);
 *   - the canonical tet list (each tet's four points in lexicographic order, the list
 *     sorted) is the same for threads = 1, threads = 2 and a permutation of the input:
 *     the perturbed Delaunay tetrahedrization is unique (proofs/perturbation.md).
 */
#include "fuzz_common.h"

#include "../tests/canon.h"
#include "gigatet.h"
#include "oracle/oracle.h"

#define MAX_POINTS 300

/* Degenerate: no 4 distinct, affinely independent points (decided with the oracle). */
static int is_degenerate(const double *p, size_t n)
{
    size_t ia = 0, ib = SIZE_MAX, ic = SIZE_MAX;
    if (n == 0) return 1;
    for (size_t i = 1; i < n && ib == SIZE_MAX; i++)
        if (canon_cmp_point(p, p + 3 * i) != 0) ib = i;
    if (ib == SIZE_MAX) return 1;
    for (size_t i = 1; i < n && ic == SIZE_MAX; i++)
        if (orc_coplanar_orientation(p + 3 * ia, p + 3 * ib, p + 3 * i) != 0) ic = i;
    if (ic == SIZE_MAX) return 1;
    for (size_t i = 1; i < n; i++)
        if (orc_orient3d(p + 3 * ia, p + 3 * ib, p + 3 * ic, p + 3 * i) != 0) return 0;
    return 1;
}

static void make_points(fz_bytes *b, double *p, size_t *n_out)
{
    size_t n = 4 + fz_u8(b) % 64;  /* grown below while bytes last */
    n += (size_t)fz_u8(b) * (fz_u8(b) & 1);
    if (n > MAX_POINTS) n = MAX_POINTS;
    int s = (int)(fz_u8(b) % 41) - 20;
    if (fz_u8(b) % 8 == 0) s = (fz_u8(b) & 1) ? 990 : -1060;  /* extreme scales */
    int grid_k = 2 + fz_u8(b) % 7;
    int r2 = 3 + fz_u8(b) % 60;
    double pn[3] = {fz_small_int(b), fz_small_int(b), 1 + fz_u8(b) % 3};  /* plane normal-ish */
    double ld[3] = {fz_small_int(b), fz_small_int(b), fz_small_int(b)};   /* line direction */
    uint8_t family_mask = fz_u8(b) | 1;
    for (size_t i = 0; i < n; i++) {
        double *q = p + 3 * i;
        uint8_t f = fz_u8(b) % 7;
        if (!(family_mask & (1u << f))) f = 0;
        switch (f) {
        case 0:  /* grid */
            for (int k = 0; k < 3; k++) q[k] = fz_u8(b) % grid_k;
            break;
        case 1: { /* sphere x^2+y^2+z^2 = r2 (nearest integer point found by search) */
            int x = fz_small_int(b), y = fz_small_int(b), sgn = (fz_u8(b) & 1) ? 1 : -1;
            int rest = r2 - x * x - y * y, z = 0;
            while ((z + 1) * (z + 1) <= rest) z++;
            q[0] = x;
            q[1] = y;
            q[2] = sgn * z;  /* on the sphere only when rest is a square: near it otherwise */
            break;
        }
        case 2: { /* plane pn . q = 0 with q[2] derived, integers kept exact */
            double x = fz_small_int(b), y = fz_small_int(b);
            q[0] = x * pn[2];
            q[1] = y * pn[2];
            q[2] = -(pn[0] * x + pn[1] * y);
            break;
        }
        case 3: { /* line t * ld + offset */
            double t = fz_small_int(b);
            for (int k = 0; k < 3; k++) q[k] = t * ld[k] + 1.0;
            break;
        }
        case 4:  /* duplicate, zeros' signs flipped */
            if (i > 0) {
                const double *src = p + 3 * (fz_u8(b) % i);
                for (int k = 0; k < 3; k++) q[k] = src[k] == 0 ? -src[k] : src[k];
                continue;  /* not rescaled: already scaled */
            }
            for (int k = 0; k < 3; k++) q[k] = 0;
            break;
        case 5:  /* adversarial coordinates (not rescaled) */
            for (int k = 0; k < 3; k++) q[k] = fz_coord(b, p, 3 * i);
            continue;
        default: /* a grid point moved by an ulp */
            for (int k = 0; k < 3; k++) q[k] = fz_u8(b) % grid_k;
            q[fz_u8(b) % 3] = fz_ulps(q[0], (fz_u8(b) & 1) ? 1 : -1);
            break;
        }
        for (int k = 0; k < 3; k++) q[k] = ldexp(q[k], s);
    }
    *n_out = n;
}

static gtet_mesh *run(const double *p, size_t n, int threads, gtet_status *st)
{
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.threads = threads;
    o.error = &err;
    gtet_mesh *m = NULL;
    *st = gtet_triangulate(p, n, &o, &m);
    FZ_ASSERT(*st == GTET_OK || *st == GTET_ERR_DEGENERATE_INPUT,
              "n=%zu threads=%d: status %d: %s", n, threads, (int)*st, err.message);
    FZ_ASSERT((*st == GTET_OK) == (m != NULL), "status %d with mesh %p", (int)*st, (void *)m);
    return m;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_bytes b = {data, size, 0};
    double *p = malloc(3 * MAX_POINTS * sizeof *p);
    double *q = malloc(3 * MAX_POINTS * sizeof *q);
    FZ_ASSERT(p && q, "out of memory");
    size_t n;
    make_points(&b, p, &n);
    int degenerate = is_degenerate(p, n);

    gtet_status st;
    gtet_mesh *m1 = run(p, n, 1, &st);
    FZ_ASSERT((st == GTET_ERR_DEGENERATE_INPUT) == degenerate,
              "n=%zu: status %d but the oracle says degenerate=%d", n, (int)st, degenerate);
    if (m1) {
        gtet_check_report rep;
        gtet_status cs = gtet_check(m1, p, n, n <= 64 ? GTET_CHECK_FULL : 0, &rep);
        FZ_ASSERT(cs == GTET_OK && rep.ok, "n=%zu: check failed: %s", n, rep.message);

        /* same tets with 2 threads and for a permutation (a rotation plus swaps) */
        size_t rot = fz_u8(&b) % n;
        for (size_t i = 0; i < n; i++) memcpy(q + 3 * i, p + 3 * ((i + rot) % n), 3 * sizeof *q);
        for (size_t i = n; i > 1; i--) {
            size_t j = (fz_u8(&b) + 31 * i) % i;
            double t[3];
            memcpy(t, q + 3 * (i - 1), sizeof t);
            memcpy(q + 3 * (i - 1), q + 3 * j, sizeof t);
            memcpy(q + 3 * j, t, sizeof t);
        }
        gtet_status st2, st3;
        gtet_mesh *m2 = run(p, n, 2, &st2);
        gtet_mesh *m3 = run(q, n, 1, &st3);
        FZ_ASSERT(st2 == GTET_OK && st3 == GTET_OK, "status %d / %d", (int)st2, (int)st3);
        size_t n1 = gtet_mesh_num_tets(m1), n2 = gtet_mesh_num_tets(m2);
        size_t n3 = gtet_mesh_num_tets(m3);
        canon_tet *c1 = canon_coords(m1), *c2 = canon_coords(m2), *c3 = canon_coords(m3);
        FZ_ASSERT(c1 && c2 && c3, "out of memory");
        FZ_ASSERT(n1 == n2 && memcmp(c1, c2, n1 * sizeof *c1) == 0,
                  "threads=2 gives other tets (%zu vs %zu)", n1, n2);
        FZ_ASSERT(n1 == n3 && memcmp(c1, c3, n1 * sizeof *c1) == 0,
                  "a permutation of the input gives other tets (%zu vs %zu)", n1, n3);
        free(c1);
        free(c2);
        free(c3);
        gtet_mesh_free(&m2);
        gtet_mesh_free(&m3);
        gtet_mesh_free(&m1);
    }
    free(p);
    free(q);
    return 0;
}
