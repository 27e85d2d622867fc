/* test_oracle_cgal.cpp -- the GMP oracle's perturbation is CGAL's, and CGAL's meshes pass the
 * checker.
 *
 * 1. Predicates: on integer-grid tuples (exact zeros everywhere) orc_insphere_sos equals
 *    CGAL's Delaunay_triangulation_3::side_of_oriented_sphere(..., perturb = true) and the
 *    coplanar branch of orc_ghost_conflict equals coplanar_side_of_bounded_circle(..., true)
 *    (protected members, reached through a derived class).
 * 2. Triangulations: the brute-force perturbed Delaunay mesh built on the oracle equals CGAL's
 *    Delaunay_triangulation_3 (Epick) tet for tet, on small degenerate sets.
 * 3. The exact checker (with and without its interval filter) accepts CGAL's mesh of larger
 *    sets: random, a grid, co-spherical integer points, a plane plus an apex.
 * Any difference is a bug in one of the two; this test says which tuple.
 */
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

extern "C" {
#include "check/check_internal.h"
#include "gigatet.h"
#include "oracle/oracle.h"
}

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K> Vb;
typedef CGAL::Triangulation_data_structure_3<Vb> Tds;
typedef CGAL::Delaunay_triangulation_3<K, Tds> DT;
typedef K::Point_3 Pt;
typedef std::array<uint32_t, 4> Tet;

struct DTX : DT {
    using DT::coplanar_side_of_bounded_circle;
    using DT::side_of_oriented_sphere;
};

static int failures = 0;
#define EXPECT(cond, ...)                                                    \
    do {                                                                     \
        if (!(cond)) {                                                       \
            if (failures++ < 10) {                                           \
                std::fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);    \
                std::fprintf(stderr, __VA_ARGS__);                           \
                std::fprintf(stderr, "\n");                                  \
            }                                                                \
        }                                                                    \
    } while (0)

static Pt pt(const double *p) { return Pt(p[0], p[1], p[2]); }

static void predicates_match_cgal_on_grid_tuples()
{
    DTX dt;
    std::mt19937_64 g(7);
    int spheres = 0, circles = 0;
    for (int it = 0; it < 30000; it++) {
        double p[5][3];
        for (auto &q : p)
            for (double &x : q) x = (double)(g() % 3);
        bool distinct = true;
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < i; k++) distinct &= orc_lex_compare(p[i], p[k]) != 0;
        if (!distinct) continue;
        int o = orc_orient3d(p[0], p[1], p[2], p[3]);
        if (o > 0 && orc_insphere(p[0], p[1], p[2], p[3], p[4]) == 0) {
            spheres++;
            int c = (int)dt.side_of_oriented_sphere(pt(p[0]), pt(p[1]), pt(p[2]), pt(p[3]),
                                                    pt(p[4]), true);
            int s = orc_insphere_sos(p[0], p[1], p[2], p[3], p[4]);
            EXPECT(c == s, "insphere_sos %d, CGAL %d at iteration %d", s, c, it);
        }
        if (orc_orient3d(p[0], p[1], p[2], p[4]) == 0 &&
            orc_coplanar_orientation(p[0], p[1], p[2]) != 0) {
            circles++;
            int c = (int)dt.coplanar_side_of_bounded_circle(pt(p[0]), pt(p[1]), pt(p[2]), pt(p[4]),
                                                            true);
            int s = orc_ghost_conflict(p[0], p[1], p[2], p[4]);
            EXPECT(c == s, "ghost_conflict (coplanar) %d, CGAL %d at iteration %d", s, c, it);
        }
    }
    EXPECT(spheres > 500 && circles > 500, "only %d sphere and %d circle ties", spheres, circles);
}

static std::vector<Tet> cgal_tets(const std::vector<double> &xyz)
{
    std::vector<std::pair<Pt, uint32_t>> p;
    for (size_t i = 0; i < xyz.size() / 3; i++) p.push_back({pt(&xyz[3 * i]), (uint32_t)i});
    DT dt(p.begin(), p.end());
    std::vector<Tet> t;
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
        t.push_back({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(),
                     c->vertex(3)->info()});
    return t;
}

static std::vector<Tet> brute_tets(const std::vector<double> &xyz)
{
    uint32_t n = (uint32_t)(xyz.size() / 3);
    const double *v = xyz.data();
    std::vector<Tet> t;
    for (uint32_t a = 0; a < n; a++)
        for (uint32_t b = a + 1; b < n; b++)
            for (uint32_t c = b + 1; c < n; c++)
                for (uint32_t d = c + 1; d < n; d++) {
                    Tet q = {a, b, c, d};
                    int o = orc_orient3d(v + 3 * a, v + 3 * b, v + 3 * c, v + 3 * d);
                    if (o == 0) continue;
                    if (o < 0) std::swap(q[2], q[3]);
                    bool empty = true;
                    for (uint32_t e = 0; e < n && empty; e++)
                        if (e != a && e != b && e != c && e != d)
                            empty = orc_insphere_sos(v + 3 * q[0], v + 3 * q[1], v + 3 * q[2],
                                                     v + 3 * q[3], v + 3 * e) == -1;
                    if (empty) t.push_back(q);
                }
    return t;
}

static std::vector<Tet> canonical(std::vector<Tet> t)
{
    for (auto &q : t) std::sort(q.begin(), q.end());
    std::sort(t.begin(), t.end());
    return t;
}

static void brute_force_meshes_equal_cgal_on_degenerate_sets()
{
    std::mt19937_64 g(11);
    int compared = 0;
    for (int it = 0; it < 120; it++) {
        int kind = it % 4;
        size_t n = 6 + g() % 8;
        std::vector<double> xyz;
        while (xyz.size() < 3 * n) {
            double p[3];
            if (kind == 0) for (double &x : p) x = (double)(g() % 3);
            else if (kind == 1) for (double &x : p) x = (double)((int)(g() % 3) - 1);
            else if (kind == 2) {  /* integer points with x^2 + y^2 + z^2 = 9 */
                static const double s[][3] = {{3, 0, 0}, {-3, 0, 0}, {0, 3, 0}, {0, -3, 0},
                                              {0, 0, 3}, {0, 0, -3}, {1, 2, 2}, {-1, 2, 2},
                                              {1, -2, 2}, {1, 2, -2}, {-1, -2, 2}, {2, 1, -2},
                                              {2, -2, 1}, {-2, 2, -1}, {-2, -1, -2}, {2, 2, 1}};
                const double *q = s[g() % 16];
                std::copy(q, q + 3, p);
            } else {  /* a plane with one or two apexes */
                p[0] = (double)(g() % 4);
                p[1] = (double)(g() % 4);
                p[2] = g() % 5 == 0 ? 1.0 : 0.0;
            }
            bool dup = false;
            for (size_t i = 0; i < xyz.size(); i += 3) dup |= orc_lex_compare(&xyz[i], p) == 0;
            if (!dup) xyz.insert(xyz.end(), p, p + 3);
        }
        std::vector<Tet> b = brute_tets(xyz);
        if (b.empty()) continue;  /* coplanar: no 3D mesh */
        compared++;
        std::vector<Tet> c = cgal_tets(xyz);
        EXPECT(canonical(b) == canonical(c), "set %d (kind %d, %zu points): brute force %zu tets, "
               "CGAL %zu", it, kind, n, b.size(), c.size());
        gtet_check_report r;
        EXPECT(gtet_check_arrays(xyz.data(), n, &c[0][0], c.size(), nullptr, xyz.data(), n,
                                 GTET_CHECK_FULL, &r) == GTET_OK,
               "set %d: CGAL's mesh fails the full check: %s", it, r.message);
    }
    EXPECT(compared > 75, "only %d sets compared", compared);
}

static void checker_accepts_cgal_meshes_of_larger_sets()
{
    std::mt19937_64 g(5);
    std::uniform_real_distribution<double> u(0, 1);
    for (int kind = 0; kind < 4; kind++) {
        std::vector<double> xyz;
        if (kind == 0) {
            for (int i = 0; i < 3 * 1500; i++) xyz.push_back(u(g));
        } else if (kind == 1) {
            for (int i = 0; i < 8 * 8 * 8; i++) {
                double p[3] = {(double)(i % 8), (double)(i / 8 % 8), (double)(i / 64)};
                xyz.insert(xyz.end(), p, p + 3);
            }
        } else if (kind == 2) {
            for (int x = -12; x <= 12; x++)
                for (int y = -12; y <= 12; y++)
                    for (int z = -12; z <= 12; z++)
                        if (x * x + y * y + z * z == 169) {
                            double p[3] = {(double)x, (double)y, (double)z};
                            xyz.insert(xyz.end(), p, p + 3);
                        }
        } else {
            for (int i = 0; i < 400; i++) {
                double p[3] = {(double)(g() % 20), (double)(g() % 20), 0.0};
                bool dup = false;
                for (size_t k = 0; k < xyz.size(); k += 3) dup |= orc_lex_compare(&xyz[k], p) == 0;
                if (!dup) xyz.insert(xyz.end(), p, p + 3);
            }
            double apex[3] = {9.5, 9.5, 0x1p-1074};  /* a denormal apex */
            xyz.insert(xyz.end(), apex, apex + 3);
        }
        size_t n = xyz.size() / 3;
        std::vector<Tet> c = cgal_tets(xyz);
        for (unsigned flags : {0u, (unsigned)GTET_CHECK_NO_FILTER}) {
            gtet_check_report r;
            EXPECT(gtet_check_arrays(xyz.data(), n, &c[0][0], c.size(), nullptr, xyz.data(), n,
                                     flags, &r) == GTET_OK,
                   "kind %d (%zu points, %zu tets), flags %u: %s", kind, n, c.size(), flags,
                   r.message);
        }
    }
}

int main()
{
    predicates_match_cgal_on_grid_tuples();
    brute_force_meshes_equal_cgal_on_degenerate_sets();
    checker_accepts_cgal_meshes_of_larger_sets();
    std::printf("%s (%d failures)\n", failures ? "FAILED" : "passed", failures);
    return failures != 0;
}
