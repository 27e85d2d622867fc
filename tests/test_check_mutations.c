/* test_check_mutations.c -- the checker is checked: valid meshes (brute-force perturbed
 * Delaunay of random and degenerate point sets) are corrupted in every way a kernel bug could
 * corrupt them, and each corruption must be reported with the message of the invariant it
 * breaks.
 *
 * Where the broken invariant is determined by the corruption, the test names it exactly (a
 * swapped tet is negatively oriented; a duplicated tet repeats four vertices; a dropped
 * interior tet leaves a cavity, V - E + F - T = 2; a 2-3 flip leaves a valid triangulation that
 * is not locally Delaunay; a broken link disagrees with the rebuilt adjacency).  Where several
 * invariants can break first (rewiring a tet, dropping a hull tet, moving a hull vertex), the
 * test requires a failure whose message is one of the invariants that can.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test_check_meshes.h"
#include "testutil.h"

static tmesh tm_copy(const tmesh *m)
{
    tmesh c = tm_make(m->v, m->nv, m->t, m->nt);
    return c;
}

/* The canonical check's verdict and message.  Every mutation is also judged in closed
 * Delaunay mode (GTET_CHECK_DELAUNAY), with and without GTET_CHECK_ANY_ORIENTATION: a mesh the
 * canonical check accepts must pass it, and a mesh it rejects must fail it too, unless the
 * canonical failure is only a co-spherical tie broken the other way (violation.tie), or (with
 * any orientation) only a negatively oriented tet.  Mismatches are counted in mode_mismatch. */
static int mode_mismatch, mode_runs;

static gtet_status run(const tmesh *m, const double *xyz, size_t n, int with_nb, char msg[512])
{
    gtet_check_report r, rd, ra;
    const uint32_t *nb = with_nb ? m->nb : NULL;
    gtet_status st = gtet_check_arrays(m->v, m->nv, m->t, m->nt, nb, xyz, n, 0, &r);
    gtet_status sd = gtet_check_arrays(m->v, m->nv, m->t, m->nt, nb, xyz, n, GTET_CHECK_DELAUNAY, &rd);
    gtet_status sa = gtet_check_arrays(m->v, m->nv, m->t, m->nt, nb, xyz, n,
                                       GTET_CHECK_DELAUNAY | GTET_CHECK_ANY_ORIENTATION, &ra);
    snprintf(msg, 512, "%s", r.message);
    if ((st == GTET_OK) != (r.ok == 1)) snprintf(msg, 512, "status and report.ok disagree");
    int tie = st != GTET_OK && r.violation.tie;
    int negative = st != GTET_OK && r.violation.stage && !strcmp(r.violation.stage, "orientation") &&
                   strstr(r.message, "negatively");
    mode_runs++;
    if ((sd == GTET_OK) != (st == GTET_OK || tie)) {
        mode_mismatch++;
        fprintf(stderr, "mode mismatch: canonical: %s; delaunay: %s\n", r.message, rd.message);
    }
    if (!negative && (sa == GTET_OK) != (sd == GTET_OK)) {
        mode_mismatch++;
        fprintf(stderr, "mode mismatch: delaunay: %s; any orientation: %s\n", rd.message, ra.message);
    }
    if (st != GTET_OK && !tie && (!r.violation.stage || !rd.violation.stage)) {
        mode_mismatch++;
        fprintf(stderr, "a failure without its stage: %s\n", r.message);
    }
    return st;
}

static int has_any(const char *msg, const char *const *keys)
{
    for (; *keys; keys++)
        if (strstr(msg, *keys)) return 1;
    return 0;
}

/* The brute-force mesh of n random points (seed), computed once per (seed, n) and copied:
 * brute force is the slow part of these tests. */
static tmesh base_mesh(uint64_t seed, size_t n, double **pts)
{
    static struct { uint64_t seed; size_t n; tmesh m; } cache[4];
    static int used;
    *pts = tm_random_points(seed, n);
    for (int i = 0; i < used; i++)
        if (cache[i].seed == seed && cache[i].n == n) return tm_copy(&cache[i].m);
    tmesh m = tm_brute_delaunay(*pts, n);
    if (used < 4) {
        cache[used].seed = seed;
        cache[used].n = n;
        cache[used++].m = tm_copy(&m);
    }
    return m;
}

/* A vertex on no hull facet, or UINT32_MAX. */
static uint32_t interior_vertex(const tmesh *m)
{
    uint8_t *hull = calloc(m->nv, 1);
    for (size_t t = 0; t < m->nt; t++)
        for (int f = 0; f < 4; f++)
            if (m->nb[4 * t + f] == GTET_NO_TET)
                for (int i = 0; i < 4; i++)
                    if (i != f) hull[m->t[4 * t + i]] = 1;
    uint32_t v = UINT32_MAX;
    for (uint32_t i = 0; i < m->nv && v == UINT32_MAX; i++)
        if (!hull[i]) v = i;
    free(hull);
    return v;
}

static void test_base_meshes_pass(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512];
    TEST_CHECK(run(&m, p, 18, 1, msg) == GTET_OK, "base mesh fails: %s", msg);
    TEST_CHECK(interior_vertex(&m) != UINT32_MAX, "base mesh has no interior vertex");
    tm_free(&m);
    free(p);
}

static void test_swapping_two_vertices_of_any_tet_is_a_negative_tet(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512], want[64];
    for (size_t t = 0; t < m.nt; t++) {
        tmesh c = tm_copy(&m);
        uint32_t x = c.t[4 * t + 1];
        c.t[4 * t + 1] = c.t[4 * t + 3];
        c.t[4 * t + 3] = x;
        TEST_CHECK(run(&c, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "swap in tet %zu passes", t);
        snprintf(want, sizeof want, "tet %zu (", t);
        TEST_CHECK(strstr(msg, want) && strstr(msg, "negatively oriented"), "swap in tet %zu: %s", t, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

static void drop_tet(tmesh *c, size_t t)
{
    if (t >= c->nt || c->nt < 2) return;
    memmove(c->t + 4 * t, c->t + 4 * (t + 1), 4 * (c->nt - t - 1) * sizeof *c->t);
    c->nt--;
    tm_neighbors(c);
}

/* 8 hull points (a jittered box) around 12 random inside points: many tets with no vertex on
 * the hull. */
static double *boxed_points(void)
{
    double *p = tm_random_points(21, 20);
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = ((i >> j) & 1 ? 4.0 : -3.0) + 0.1 * p[3 * i + j];
    return p;
}

/* Dropping a tet whose four vertices are interior leaves a closed cavity: every link and the
 * hull stay manifold, only V - E + F - T becomes 2.  A tet touching the hull breaks the hull
 * surface, a link, or the hull's convexity. */
static void test_dropping_any_tet_is_caught(void)
{
    double *p = boxed_points();
    tmesh m = tm_brute_delaunay(p, 20);
    char msg[512];
    static const char *const hull_keys[] = {"hull is not convex", "is in no tet", "link of",
                                            "V - E + F - T", "ray from the centroid", "hull edge",
                                            "centroid of tet 0", NULL};
    int deep = 0;
    for (size_t t = 0; t < m.nt; t++) {
        int touches = 0;
        for (int i = 0; i < 4; i++) touches |= m.t[4 * t + i] < 8;
        tmesh c = tm_copy(&m);
        drop_tet(&c, t);
        TEST_CHECK(run(&c, p, 20, 1, msg) == GTET_ERR_CHECK_FAILED, "dropping tet %zu passes", t);
        if (!touches) {
            deep++;
            TEST_CHECK(strstr(msg, "V - E + F - T") && strstr(msg, "= 2, not 1"),
                       "dropping interior tet %zu: %s", t, msg);
        } else {
            TEST_CHECK(has_any(msg, hull_keys), "dropping tet %zu: %s", t, msg);
        }
        tm_free(&c);
    }
    TEST_CHECK(deep > 5, "only %d tets with four interior vertices were dropped", deep);
    tm_free(&m);
    free(p);
}

static void test_duplicating_a_tet_is_reported_as_a_repeated_tet(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512], want[64];
    for (size_t t = 0; t < m.nt; t += 3) {
        tmesh c = tm_copy(&m);
        c.t = realloc(c.t, 4 * (c.nt + 1) * sizeof *c.t);
        /* the copy in an even permutation of the same vertices */
        c.t[4 * c.nt] = c.t[4 * t + 1];
        c.t[4 * c.nt + 1] = c.t[4 * t + 2];
        c.t[4 * c.nt + 2] = c.t[4 * t];
        c.t[4 * c.nt + 3] = c.t[4 * t + 3];
        c.nt++;
        tm_neighbors(&c);
        TEST_CHECK(run(&c, p, 18, 0, msg) == GTET_ERR_CHECK_FAILED, "duplicate of %zu passes", t);
        snprintf(want, sizeof want, "tets %zu and %zu have the same four vertices", t, c.nt - 1);
        TEST_CHECK(strstr(msg, want) != NULL, "duplicate of tet %zu: %s", t, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

static void test_moving_a_vertex_slightly_is_caught_against_the_input(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512], want[64];
    for (uint32_t v = 0; v < m.nv; v++) {
        tmesh c = tm_copy(&m);
        c.v[3 * v + v % 3] = nextafter(c.v[3 * v + v % 3], 2.0);  /* one ulp */
        TEST_CHECK(run(&c, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "1-ulp move of %u passes", v);
        snprintf(want, sizeof want, "input point %u (", v);
        TEST_CHECK(strstr(msg, want) && strstr(msg, "is not a vertex"), "move of %u: %s", v, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

/* Without the input, a small move is an error exactly when the mesh stops being the perturbed
 * Delaunay mesh of the moved points: the verdict must equal the brute-force definition.  On a
 * grid nearly every small move breaks a co-spherical tie the wrong way; on random points most
 * small moves change nothing: both outcomes occur. */
static void test_small_moves_are_judged_exactly_like_brute_force(void)
{
    double g[3 * 12];
    size_t n = 0;
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 2; y++)
            for (int x = 0; x < 3; x++) {
                g[3 * n] = x;
                g[3 * n + 1] = y;
                g[3 * n + 2] = z;
                n++;
            }
    double *rp = tm_random_points(3, 12);
    tmesh base[2] = {tm_brute_delaunay(g, n), tm_brute_delaunay(rp, 12)};
    tu_rng r = {99};
    int rejected = 0, accepted = 0;
    char msg[512];
    for (int it = 0; it < 24; it++) {
        tmesh c = tm_copy(&base[it % 2]);
        uint32_t v = (uint32_t)tu_below(&r, c.nv);
        double step = it % 4 == 3 ? 0.05 : 1e-6;
        for (int j = 0; j < 3; j++) c.v[3 * v + j] += (tu_uniform(&r) - 0.5) * step;
        tmesh truth = tm_brute_delaunay(c.v, c.nv);
        int is_delaunay = tm_same_tets(&c, &truth);
        /* a move can also invert a tet; that mesh is not Delaunay either */
        gtet_status st = run(&c, c.v, c.nv, 1, msg);
        TEST_CHECK((st == GTET_OK) == is_delaunay, "move %d of vertex %u: checker %s (%s), brute "
                   "force %s", it, v, st == GTET_OK ? "accepts" : "rejects", msg,
                   is_delaunay ? "Delaunay" : "not Delaunay");
        if (st != GTET_OK) {
            rejected++;
            static const char *const keys[] = {"not locally Delaunay", "hull is not convex",
                                               "negatively oriented", "flat", NULL};
            TEST_CHECK(has_any(msg, keys), "move %d: unexpected message %s", it, msg);
        } else {
            accepted++;
        }
        tm_free(&c);
        tm_free(&truth);
    }
    TEST_CHECK(rejected > 5 && accepted > 5, "moves rejected %d, accepted %d", rejected, accepted);
    tm_free(&base[0]);
    tm_free(&base[1]);
    free(rp);
}

static void test_moving_an_interior_vertex_far_inverts_a_tet(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    uint32_t v = interior_vertex(&m);
    TEST_REQUIRE(v != UINT32_MAX, "no interior vertex");
    char msg[512];
    static const double far[3][3] = {{10, 10, 10}, {-3, 0.5, 0.5}, {0.5, 0.5, 1e6}};
    for (int k = 0; k < 3; k++) {
        tmesh c = tm_copy(&m);
        memcpy(c.v + 3 * v, far[k], sizeof far[k]);
        TEST_CHECK(run(&c, NULL, 0, 1, msg) == GTET_ERR_CHECK_FAILED, "far move %d passes", k);
        TEST_CHECK(strstr(msg, "negatively oriented") != NULL, "far move %d: %s", k, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

static void test_moving_vertices_outward_is_rejected_exactly_when_the_delaunay_mesh_changes(void)
{
    double *p;
    tmesh m = base_mesh(11, 12, &p);
    char msg[512];
    int tried = 0;
    for (uint32_t v = 0; v < m.nv; v++) {
        tmesh c = tm_copy(&m);
        /* push v away from the centre by a factor 3: it leaves the hull or changes it */
        for (int j = 0; j < 3; j++) c.v[3 * v + j] = 0.5 + 3 * (c.v[3 * v + j] - 0.5);
        tmesh truth = tm_brute_delaunay(c.v, c.nv);
        int same = tm_same_tets(&c, &truth);
        tried += !same;
        gtet_status st = run(&c, NULL, 0, 1, msg);
        TEST_CHECK((st == GTET_OK) == same, "move of %u: checker %s (%s), brute force %s", v,
                   st == GTET_OK ? "accepts" : "rejects", msg, same ? "Delaunay" : "not Delaunay");
        tm_free(&truth);
        tm_free(&c);
    }
    TEST_CHECK(tried > 3, "only %d of %zu moves changed the Delaunay mesh", tried,
               m.nv);
    tm_free(&m);
    free(p);
}

static void test_rewiring_a_tet_to_another_tets_vertex_is_caught(void)
{
    double *p;
    tmesh m = base_mesh(12, 16, &p);
    tu_rng r = {5};
    char msg[512];
    static const char *const keys[] = {"negatively oriented", "flat", "is in ", "same side",
                                       "hull edge", "traverse", "link of", "V - E + F - T",
                                       "not locally Delaunay", "hull is not convex", NULL};
    for (int it = 0; it < 60; it++) {
        size_t t = tu_below(&r, m.nt), u = tu_below(&r, m.nt);
        uint32_t w = m.t[4 * u + tu_below(&r, 4)];
        int i = (int)tu_below(&r, 4);
        int in = 0;
        for (int j = 0; j < 4; j++) in |= m.t[4 * t + j] == w;
        if (in) continue;
        tmesh c = tm_copy(&m);
        c.t[4 * t + i] = w;          /* no re-orientation: as a buggy kernel would leave it */
        TEST_CHECK(run(&c, p, 16, 0, msg) == GTET_ERR_CHECK_FAILED, "rewire %d passes", it);
        TEST_CHECK(has_any(msg, keys), "rewire %d (tet %zu vertex %d -> %u): %s", it, t, i, w, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

static void test_breaking_a_neighbor_link_names_the_link(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512], want[96];
    for (size_t tf = 0; tf < 4 * m.nt; tf += 5) {
        tmesh c = tm_copy(&m);
        uint32_t old = c.nb[tf], t = (uint32_t)(tf / 4);
        uint32_t nw = old == GTET_NO_TET ? (t == 0 ? 1 : 0) : (old + 1) % (uint32_t)c.nt;
        c.nb[tf] = nw == t ? GTET_NO_TET : nw;
        TEST_CHECK(run(&c, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "broken link %zu passes", tf);
        snprintf(want, sizeof want, "neighbor[4*%zu+%zu] ", tf / 4, tf % 4);
        TEST_CHECK(strstr(msg, want) != NULL, "broken link %zu: %s", tf, msg);
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

/* Replace the two tets on facet (a,b,c) with apexes d, e by (a,b,d,e), (b,c,d,e), (c,a,d,e)
 * when segment de crosses the triangle: a valid triangulation of the same points. */
static int flip23(const tmesh *m, size_t t1, int f, tmesh *out)
{
    uint32_t t2 = m->nb[4 * t1 + f];
    if (t2 == GTET_NO_TET) return 0;
    uint32_t d = m->t[4 * t1 + f], e = UINT32_MAX, abc[3], k = 0;
    for (int i = 0; i < 4; i++)
        if (i != f) abc[k++] = m->t[4 * t1 + i];
    for (int i = 0; i < 4; i++) {
        uint32_t w = m->t[4 * (size_t)t2 + i];
        if (w != abc[0] && w != abc[1] && w != abc[2]) e = w;
    }
    const double *V = m->v;
#define PT(x) (V + 3 * (size_t)(x))
    int s0 = orc_orient3d(PT(d), PT(e), PT(abc[0]), PT(abc[1]));
    int s1 = orc_orient3d(PT(d), PT(e), PT(abc[1]), PT(abc[2]));
    int s2 = orc_orient3d(PT(d), PT(e), PT(abc[2]), PT(abc[0]));
#undef PT
    if (s0 == 0 || s0 != s1 || s1 != s2) return 0;
    *out = tm_copy(m);
    uint32_t lo = t1 < t2 ? (uint32_t)t1 : t2, hi = t1 < t2 ? t2 : (uint32_t)t1;
    tmesh *c = out;
    drop_tet(c, hi);
    drop_tet(c, lo);
    c->t = realloc(c->t, 4 * (c->nt + 3) * sizeof *c->t);
    for (int i = 0; i < 3; i++) {
        uint32_t *q = c->t + 4 * (c->nt + (size_t)i);
        q[0] = abc[i];
        q[1] = abc[(i + 1) % 3];
        q[2] = d;
        q[3] = e;
        tm_orient(c->v, q);
    }
    c->nt += 3;
    tm_neighbors(c);
    return 1;
}

static void test_a_2_3_flip_is_a_valid_triangulation_but_not_locally_delaunay(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512];
    int flips = 0;
    for (size_t t = 0; t < m.nt; t++)
        for (int f = 0; f < 4; f++) {
            tmesh c;
            if (!flip23(&m, t, f, &c)) continue;
            flips++;
            TEST_CHECK(run(&c, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "flip %zu/%d passes", t, f);
            TEST_CHECK(strstr(msg, "is not locally Delaunay") != NULL, "flip %zu/%d: %s", t, f, msg);
            tm_free(&c);
        }
    TEST_CHECK(flips > 5, "only %d 2-3 flips were possible", flips);
    tm_free(&m);
    free(p);
}

static void test_missing_and_extra_input_points_are_named(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512];
    /* the mesh of the first 17 points, checked against all 18 */
    tmesh m17 = tm_brute_delaunay(p, 17);
    TEST_CHECK(run(&m17, p, 17, 1, msg) == GTET_OK, "17-point mesh: %s", msg);
    TEST_CHECK(run(&m17, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "missing point passes");
    TEST_CHECK(strstr(msg, "input point 17 (") && strstr(msg, "is not a vertex"), "missing: %s", msg);
    /* the 18-point mesh against only 17 input points: vertex 17 is not an input point */
    TEST_CHECK(run(&m, p, 17, 1, msg) == GTET_ERR_CHECK_FAILED, "extra vertex passes");
    TEST_CHECK(strstr(msg, "vertex 17 (") && strstr(msg, "is not an input point"), "extra: %s", msg);
    /* a vertex no tet uses */
    tmesh c = tm_copy(&m17);
    c.v = realloc(c.v, 3 * 18 * sizeof *c.v);
    memcpy(c.v + 3 * 17, p + 3 * 17, 3 * sizeof *c.v);
    c.nv = 18;
    TEST_CHECK(run(&c, p, 18, 1, msg) == GTET_ERR_CHECK_FAILED, "unused vertex passes");
    TEST_CHECK(strstr(msg, "vertex 17 (") && strstr(msg, "is in no tet"), "unused: %s", msg);
    tm_free(&c);
    tm_free(&m17);
    tm_free(&m);
    free(p);
}

static void test_malformed_arrays_are_named(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    char msg[512];
    tmesh c = tm_copy(&m);
    c.t[4 * 2 + 1] = 18;
    TEST_CHECK(run(&c, NULL, 0, 0, msg) == GTET_ERR_CHECK_FAILED && strstr(msg, "tet 2 has vertex id 18, out of range"),
               "out of range: %s", msg);
    c.t[4 * 2 + 1] = c.t[4 * 2 + 3];
    TEST_CHECK(run(&c, NULL, 0, 0, msg) == GTET_ERR_CHECK_FAILED && strstr(msg, "repeats vertex"),
               "repeated: %s", msg);
    tm_free(&c);
    c = tm_copy(&m);
    c.v[3 * 4 + 1] = NAN;
    TEST_CHECK(run(&c, NULL, 0, 0, msg) == GTET_ERR_CHECK_FAILED && strstr(msg, "vertex 4 has a non-finite"),
               "NaN: %s", msg);
    memcpy(c.v + 3 * 4, c.v + 3 * 9, 3 * sizeof *c.v);
    TEST_CHECK(run(&c, NULL, 0, 0, msg) == GTET_ERR_CHECK_FAILED && strstr(msg, "vertices 4 and 9 are the same point"),
               "same point: %s", msg);
    tm_free(&c);
    TEST_CHECK(gtet_check_arrays(m.v, m.nv, m.t, 0, NULL, NULL, 0, 0, NULL) == GTET_ERR_CHECK_FAILED,
               "no tets passes");
    TEST_CHECK(gtet_check_arrays(NULL, 5, m.t, m.nt, NULL, NULL, 0, 0, NULL) == GTET_ERR_ARGUMENT,
               "NULL vertices accepted");
    TEST_CHECK(gtet_check_arrays(m.v, m.nv, m.t, m.nt, NULL, NULL, 0, 0x80, NULL) == GTET_ERR_ARGUMENT,
               "unknown flag accepted");
    tm_free(&m);
    free(p);
}

/* Swapping vertices 1 and 3 of any subset of the tets (with their neighbors, as a tool that
 * orients nothing would write them) passes GTET_CHECK_ANY_ORIENTATION in both modes, with the
 * count of negative tets; renumbering the vertices does not matter either. */
static void test_any_orientation_accepts_unoriented_renumbered_meshes(void)
{
    double *p;
    tmesh m = base_mesh(11, 18, &p);
    tu_rng r = {5};
    for (int it = 0; it < 6; it++) {
        tmesh c = tm_copy(&m);
        uint64_t swapped = 0;
        for (size_t t = 0; t < c.nt; t++)
            if (it == 5 || tu_below(&r, 2)) {
                uint32_t x = c.t[4 * t + 1];
                c.t[4 * t + 1] = c.t[4 * t + 3];
                c.t[4 * t + 3] = x;
                x = c.nb[4 * t + 1];
                c.nb[4 * t + 1] = c.nb[4 * t + 3];
                c.nb[4 * t + 3] = x;
                swapped++;
            }
        /* renumber: vertex v becomes perm[v] */
        uint32_t perm[18];
        for (uint32_t v = 0; v < 18; v++) perm[v] = v;
        for (uint32_t v = 17; v > 0; v--) {
            uint32_t k = (uint32_t)tu_below(&r, v + 1), x = perm[v];
            perm[v] = perm[k];
            perm[k] = x;
        }
        double *nv = malloc(18 * 3 * sizeof *nv);
        for (uint32_t v = 0; v < 18; v++) memcpy(nv + 3 * perm[v], c.v + 3 * v, 3 * sizeof *nv);
        for (size_t i = 0; i < 4 * c.nt; i++) c.t[i] = perm[c.t[i]];
        memcpy(c.v, nv, 18 * 3 * sizeof *nv);
        free(nv);
        for (int mode = 0; mode < 2; mode++) {
            unsigned fl = GTET_CHECK_ANY_ORIENTATION | GTET_CHECK_FULL | (mode ? GTET_CHECK_DELAUNAY : 0u);
            gtet_check_report rep;
            gtet_status st = gtet_check_arrays(c.v, c.nv, c.t, c.nt, c.nb, p, 18, fl, &rep);
            TEST_CHECK(st == GTET_OK && rep.negative_tets == swapped,
                       "round %d mode %d: %s (negative %llu of %llu)", it, mode, rep.message,
                       (unsigned long long)rep.negative_tets, (unsigned long long)swapped);
            st = gtet_check_arrays(c.v, c.nv, c.t, c.nt, NULL, p, 18, fl & ~(unsigned)GTET_CHECK_ANY_ORIENTATION, &rep);
            TEST_CHECK((st == GTET_OK) == (swapped == 0) && (swapped == 0 || (rep.violation.stage &&
                       !strcmp(rep.violation.stage, "orientation"))),
                       "round %d mode %d without the flag: %s", it, mode, rep.message);
        }
        tm_free(&c);
    }
    tm_free(&m);
    free(p);
}

/* Every mutation above, judged again by run() in closed Delaunay mode and with any
 * orientation, got the verdict the canonical one implies. */
static void test_every_mutation_fails_in_delaunay_mode_too(void)
{
    TEST_CHECK(mode_runs > 100, "only %d mutations were judged in both modes", mode_runs);
    TEST_CHECK(mode_mismatch == 0, "%d mutations judged inconsistently by the modes (see above)",
               mode_mismatch);
}

int main(void)
{
    TU_RUN(test_base_meshes_pass);
    TU_RUN(test_swapping_two_vertices_of_any_tet_is_a_negative_tet);
    TU_RUN(test_dropping_any_tet_is_caught);
    TU_RUN(test_duplicating_a_tet_is_reported_as_a_repeated_tet);
    TU_RUN(test_moving_a_vertex_slightly_is_caught_against_the_input);
    TU_RUN(test_small_moves_are_judged_exactly_like_brute_force);
    TU_RUN(test_moving_an_interior_vertex_far_inverts_a_tet);
    TU_RUN(test_moving_vertices_outward_is_rejected_exactly_when_the_delaunay_mesh_changes);
    TU_RUN(test_rewiring_a_tet_to_another_tets_vertex_is_caught);
    TU_RUN(test_breaking_a_neighbor_link_names_the_link);
    TU_RUN(test_a_2_3_flip_is_a_valid_triangulation_but_not_locally_delaunay);
    TU_RUN(test_missing_and_extra_input_points_are_named);
    TU_RUN(test_malformed_arrays_are_named);
    TU_RUN(test_any_orientation_accepts_unoriented_renumbered_meshes);
    TU_RUN(test_every_mutation_fails_in_delaunay_mode_too);
    return tu_finish();
}
