/* test_degeneracies.c -- gtet_options.degeneracies / gtet_mesh_degeneracies: the record of
 * every decision the symbolic perturbation made during a run.
 *
 * What must hold (gigatet.h):
 *   - the record and the predicate counters count the same decisions: total == sos_calls,
 *     and without truncation the records with term k number sos_depth[k-1];
 *   - every record is a real degeneracy, re-evaluated here with the public predicates on the
 *     mesh coordinates: co-spherical -> gtet_insphere == 0 and gtet_orient3d(v0..v3) > 0;
 *     coplanar -> gtet_orient3d(v0,v1,v2,v3) == 0 and v3 on the circle of v0,v1,v2 (then
 *     gtet_insphere(v0,v1,v2,v3,x) == 0 for every x: tried with v0 + e_x, e_y, e_z, not all in
 *     the plane); and the sign recorded is the perturbed
 *     predicate's (gtet_insphere_sos(v0..v4), gtet_ghost_conflict(v0,v1,v2,v3));
 *   - generic points give no record; grids, integer points of one sphere and an FCC lattice
 *     give many (grids both kinds);
 *   - the limit keeps min(total, limit) records with the total still exact, and the list is
 *     sorted; with one thread two runs give the same list, and recording changes no tet;
 *   - with two threads (a round really split) the same consistency holds.
 */
#include <stdlib.h>
#include <string.h>

#include "gigatet.h"
#include "io/io.h"
#include "testutil.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || defined(GTET_TEST_SMALL)
enum { N_RANDOM = 20000, N_GRID_PAR = 13824 };
#else
enum { N_RANDOM = 100000, N_GRID_PAR = 27000 };
#endif

static double *gen(const char *kind, size_t n, size_t *m)
{
    double *xyz = NULL;
    io_error e;
    if (io_generate(kind, n, 7, &xyz, m, &e) != IO_OK) return NULL;
    return xyz;
}

static gtet_mesh *run(const double *xyz, size_t n, int threads, int record, size_t limit)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = threads;
    o.degeneracies = record;
    o.degeneracy_limit = limit;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(xyz, n, &o, &m);
    TEST_CHECK(s == GTET_OK, "gtet_triangulate: %s", gtet_status_str(s));
    return s == GTET_OK ? m : NULL;
}

static int cmp_rec(const gtet_degeneracy *a, const gtet_degeneracy *b)
{
    if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
    for (int i = 0; i < 5; i++)
        if (a->vertex[i] != b->vertex[i]) return a->vertex[i] < b->vertex[i] ? -1 : 1;
    if (a->term != b->term) return a->term < b->term ? -1 : 1;
    return (a->sign > b->sign) - (a->sign < b->sign);
}

/* Check every claim of gigatet.h about the record of m; returns the number of records per
 * kind in kinds[1], kinds[2]. */
static void verify(const gtet_mesh *m, const char *what, size_t limit, size_t kinds[3])
{
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    size_t stored = 7;
    uint64_t total = 7;
    const gtet_degeneracy *d = gtet_mesh_degeneracies(m, &stored, &total);
    const double *v = gtet_mesh_vertices(m);
    const size_t nv = gtet_mesh_num_vertices(m);
    kinds[0] = kinds[1] = kinds[2] = 0;
    TEST_CHECK(total == st.pred.sos_calls, "%s: total %llu != sos_calls %llu", what,
               (unsigned long long)total, (unsigned long long)st.pred.sos_calls);
    TEST_CHECK(stored == (total < limit ? total : limit), "%s: stored %zu of %llu, limit %zu",
               what, stored, (unsigned long long)total, limit);
    TEST_CHECK((d == NULL) == (stored == 0), "%s: array %p for %zu records", what,
               (const void *)d, stored);
    uint64_t per_term[4] = {0, 0, 0, 0};
    size_t bad = 0;
    for (size_t i = 0; i < stored; i++) {
        const gtet_degeneracy *r = &d[i];
        const double *p[5];
        int ok = (r->kind == GTET_DEGENERACY_COSPHERICAL && r->npoints == 5) ||
                 (r->kind == GTET_DEGENERACY_COPLANAR && r->npoints == 4 &&
                  r->vertex[4] == GTET_NO_VERTEX);
        ok &= r->term >= 1 && r->term <= 4 && (r->sign == 1 || r->sign == -1);
        for (int k = 0; ok && k < r->npoints; k++) {
            ok &= r->vertex[k] < nv;
            if (ok) p[k] = v + 3 * (size_t)r->vertex[k];
        }
        if (ok && r->kind == GTET_DEGENERACY_COSPHERICAL) {
            ok &= gtet_orient3d(p[0], p[1], p[2], p[3]) > 0;
            ok &= gtet_insphere(p[0], p[1], p[2], p[3], p[4]) == 0;
            ok &= gtet_insphere_sos(p[0], p[1], p[2], p[3], p[4]) == r->sign;
        } else if (ok) {
            ok &= gtet_orient3d(p[0], p[1], p[2], p[3]) == 0;
            for (int k = 0; k < 3; k++) {
                double x[3] = {p[0][0], p[0][1], p[0][2]};
                x[k] += 1.0;
                ok &= gtet_insphere(p[0], p[1], p[2], p[3], x) == 0;
            }
            ok &= gtet_ghost_conflict(p[0], p[1], p[2], p[3]) == r->sign;
        }
        if (ok && i > 0) ok &= cmp_rec(&d[i - 1], r) <= 0;
        if (!ok && bad++ < 3)
            TEST_CHECK(0, "%s: record %zu (kind %d, term %d, sign %d, vertices %u %u %u %u %u) "
                       "is not what gigatet.h says", what, i, r->kind, r->term, r->sign,
                       r->vertex[0], r->vertex[1], r->vertex[2], r->vertex[3], r->vertex[4]);
        if (ok) {
            per_term[r->term - 1]++;
            kinds[r->kind]++;
        }
    }
    if (stored == total)
        for (int k = 0; k < 4; k++)
            TEST_CHECK(per_term[k] == st.pred.sos_depth[k], "%s: %llu records of term %d, "
                       "sos_depth %llu", what, (unsigned long long)per_term[k], k + 1,
                       (unsigned long long)st.pred.sos_depth[k]);
}

static void test_off_by_default(void)
{
    gtet_options o;
    gtet_options_init(&o);
    TEST_CHECK(o.degeneracies == 0 && o.degeneracy_limit == 100000, "defaults %d %zu",
               o.degeneracies, o.degeneracy_limit);
    size_t n;
    double *xyz = gen("grid", 1000, &n);
    TEST_REQUIRE(xyz, "generate");
    gtet_mesh *m = run(xyz, n, 1, 0, 0);
    if (m) {
        size_t stored = 7;
        uint64_t total = 7;
        gtet_stats st;
        gtet_mesh_stats(m, &st);
        TEST_CHECK(st.pred.sos_calls > 0, "a grid needs the perturbation");
        TEST_CHECK(gtet_mesh_degeneracies(m, &stored, &total) == NULL && stored == 0 &&
                   total == 0, "not recorded: NULL, 0, 0");
    }
    TEST_CHECK(gtet_mesh_degeneracies(NULL, NULL, NULL) == NULL, "NULL mesh");
    gtet_mesh_free(&m);
    free(xyz);
}

static void test_random_is_empty(void)
{
    size_t n;
    double *xyz = gen("uniform", N_RANDOM, &n);
    TEST_REQUIRE(xyz, "generate");
    for (int threads = 1; threads <= 2; threads++) {
        gtet_mesh *m = run(xyz, n, threads, 1, 100000);
        if (!m) continue;
        size_t kinds[3];
        verify(m, "uniform", 100000, kinds);
        size_t stored;
        uint64_t total;
        TEST_CHECK(gtet_mesh_degeneracies(m, &stored, &total) == NULL && stored == 0 &&
                   total == 0, "uniform points, %d threads: %zu records", threads, stored);
        gtet_mesh_free(&m);
    }
    free(xyz);
}

/* Full records of a degenerate set; they are deterministic with one thread and recording
 * does not change the mesh. */
static void degenerate_set(const char *kind, size_t want, int need_cospherical,
                           int need_coplanar)
{
    size_t n;
    double *xyz = gen(kind, want, &n);
    TEST_REQUIRE(xyz, "generate %s", kind);
    gtet_mesh *plain = run(xyz, n, 1, 0, 0);
    gtet_mesh *a = run(xyz, n, 1, 1, SIZE_MAX);
    gtet_mesh *b = run(xyz, n, 1, 1, SIZE_MAX);
    if (plain && a && b) {
        size_t kinds[3];
        verify(a, kind, SIZE_MAX, kinds);
        TEST_CHECK(!need_cospherical || kinds[1] > 0, "%s: no co-spherical record", kind);
        TEST_CHECK(!need_coplanar || kinds[2] > 0, "%s: no coplanar record", kind);
        size_t sa, sb;
        uint64_t ta, tb;
        const gtet_degeneracy *da = gtet_mesh_degeneracies(a, &sa, &ta);
        const gtet_degeneracy *db = gtet_mesh_degeneracies(b, &sb, &tb);
        TEST_CHECK(sa > 0, "%s: empty record", kind);
        TEST_CHECK(sa == sb && ta == tb && (sa == 0 || !memcmp(da, db, sa * sizeof *da)),
                   "%s: one thread, two runs, different records", kind);
        const size_t nt = gtet_mesh_num_tets(plain);
        TEST_CHECK(nt == gtet_mesh_num_tets(a) &&
                   !memcmp(gtet_mesh_tets(plain), gtet_mesh_tets(a), 4 * nt * sizeof(uint32_t)),
                   "%s: recording changed the mesh", kind);
    }
    gtet_mesh_free(&plain);
    gtet_mesh_free(&a);
    gtet_mesh_free(&b);
    free(xyz);
}

static void test_grid(void) { degenerate_set("grid", 1000, 1, 1); }
static void test_cospherical(void) { degenerate_set("cospherical", 600, 1, 0); }
static void test_fcc(void) { degenerate_set("fcc", 2000, 1, 0); }

/* 4x4x4 integer points written out here (no generator involved). */
static void test_small_lattice(void)
{
    double xyz[64 * 3];
    size_t k = 0;
    for (int x = 0; x < 4; x++)
        for (int y = 0; y < 4; y++)
            for (int z = 0; z < 4; z++) {
                xyz[k++] = x;
                xyz[k++] = y;
                xyz[k++] = z;
            }
    gtet_mesh *m = run(xyz, 64, 1, 1, 100000);
    if (m) {
        size_t kinds[3];
        verify(m, "4x4x4", 100000, kinds);
        TEST_CHECK(kinds[1] > 0 && kinds[2] > 0, "4x4x4: %zu co-spherical, %zu coplanar",
                   kinds[1], kinds[2]);
    }
    gtet_mesh_free(&m);
}

static void test_limit(void)
{
    size_t n;
    double *xyz = gen("grid", 1000, &n);
    TEST_REQUIRE(xyz, "generate");
    gtet_mesh *full = run(xyz, n, 1, 1, SIZE_MAX);
    const size_t limits[] = {0, 1, 10, 1000};
    for (size_t i = 0; full && i < sizeof limits / sizeof *limits; i++) {
        gtet_mesh *m = run(xyz, n, 1, 1, limits[i]);
        if (!m) continue;
        size_t kinds[3], stored, fstored;
        uint64_t total, ftotal;
        char what[64];
        snprintf(what, sizeof what, "grid, limit %zu", limits[i]);
        verify(m, what, limits[i], kinds);
        const gtet_degeneracy *d = gtet_mesh_degeneracies(m, &stored, &total);
        const gtet_degeneracy *fd = gtet_mesh_degeneracies(full, &fstored, &ftotal);
        TEST_CHECK(total == ftotal && total > limits[i] && stored == limits[i],
                   "%s: %zu stored of %llu (unlimited: %llu)", what, stored,
                   (unsigned long long)total, (unsigned long long)ftotal);
        /* with one thread: the first `limit` decisions of the same run, each one in the
         * full record */
        for (size_t j = 0; j < stored; j++) {
            size_t lo = 0, hi = fstored;
            while (lo < hi) {
                size_t mid = lo + (hi - lo) / 2;
                if (cmp_rec(&fd[mid], &d[j]) < 0) lo = mid + 1;
                else hi = mid;
            }
            if (lo == fstored || cmp_rec(&fd[lo], &d[j]) != 0) {
                TEST_CHECK(0, "%s: record %zu not in the full record", what, j);
                break;
            }
        }
        gtet_mesh_free(&m);
    }
    gtet_mesh_free(&full);
    free(xyz);
}

static void test_two_threads(void)
{
    size_t n;
    double *xyz = gen("grid", N_GRID_PAR, &n);
    TEST_REQUIRE(xyz, "generate");
    for (int threads = 1; threads <= 2; threads++) {
        gtet_mesh *m = run(xyz, n, threads, 1, SIZE_MAX);
        if (!m) continue;
        char what[64];
        snprintf(what, sizeof what, "grid %zu, %d threads", n, threads);
        size_t kinds[3];
        verify(m, what, SIZE_MAX, kinds);
        TEST_CHECK(kinds[1] > 0 && kinds[2] > 0, "%s: %zu co-spherical, %zu coplanar", what,
                   kinds[1], kinds[2]);
        gtet_stats st;
        gtet_mesh_stats(m, &st);
        int most = 0;
        for (int r = 0; r < st.num_rounds; r++)
            if (st.rounds[r].threads > most) most = st.rounds[r].threads;
        TEST_CHECK(most == threads, "%s: rounds used at most %d threads", what, most);
        /* truncated with two threads: still exact totals */
        gtet_mesh *t = run(xyz, n, threads, 1, 100);
        if (t) {
            verify(t, what, 100, kinds);
            gtet_mesh_free(&t);
        }
        gtet_mesh_free(&m);
    }
    free(xyz);
}

int main(void)
{
    TU_RUN(test_off_by_default);
    TU_RUN(test_random_is_empty);
    TU_RUN(test_grid);
    TU_RUN(test_cospherical);
    TU_RUN(test_fcc);
    TU_RUN(test_small_lattice);
    TU_RUN(test_limit);
    TU_RUN(test_two_threads);
    return tu_finish();
}
