/* cgal_dt.cpp -- CGAL's Delaunay tetrahedrization as the reference gigatet is compared with.
 *
 *   cgal_dt [--parallel T] [--time] INPUT.{bin,xyz}
 *
 * Canonical mode (default) prints the mesh in the form tests/cgal/gtet_dt.c prints gigatet's:
 *   # gtet-canonical points N vertices V duplicates D tets T
 *   a b c d            (one line per finite tet, a < b < c < d, lines sorted)
 * where a vertex id is the input index of the FIRST occurrence of its point.  Exact duplicates
 * (with -0.0 == +0.0, which is what double comparison does) are found here by sorting, and only
 * the first occurrence is inserted, carrying its index as vertex info; so the ids never depend
 * on which duplicate CGAL happens to keep.  CGAL's Delaunay_triangulation_3 with Epick
 * evaluates orient3d / insphere exactly (filtered, then exact) and breaks co-sphericity with
 * the symbolic perturbation of Devillers & Teillaud, so its output is a function of the point
 * SET alone: any correct implementation of the same rule -- gigatet -- must print the very
 * same lines, and so must CGAL itself on a shuffled input or with the parallel (TBB) insertion.
 *
 * --parallel T  builds with Parallel_tag, a Spatial_lock_grid_3 and T TBB threads.
 * --time        timing-only mode for bench/: inserts the plain point range (which spatially
 *               sorts, as a user's `Delaunay dt(begin, end)` does; duplicates are left to
 *               CGAL) and prints one line:  cgal seq|par threads T points N vertices V tets T
 *               seconds S  -- S covers the construction only, not reading or destruction.
 */
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "pointfile.hpp"

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K> Vb;
typedef CGAL::Delaunay_triangulation_cell_base_3<K> Cb;
typedef CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Sequential_tag> Tds_seq;
typedef CGAL::Delaunay_triangulation_3<K, Tds_seq> Dt_seq;
#ifdef CGAL_LINKED_WITH_TBB
typedef CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Parallel_tag> Tds_par;
typedef CGAL::Delaunay_triangulation_3<K, Tds_par, CGAL::Default,
                                       CGAL::Spatial_lock_grid_3<CGAL::Tag_priority_blocking>>
    Dt_par;
#endif

typedef std::array<uint32_t, 4> Tet;

struct Canon {
    size_t points = 0, vertices = 0;
    std::vector<Tet> tets;
};

/* first[i] = smallest j with point j == point i (coordinate-wise ==, so -0.0 == +0.0). */
std::vector<uint32_t> first_occurrence(const std::vector<double> &xyz)
{
    size_t n = xyz.size() / 3;
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    const double *p = xyz.data();
    std::sort(order.begin(), order.end(), [p](uint32_t a, uint32_t b) {
        for (int k = 0; k < 3; k++) {
            if (p[3 * a + k] < p[3 * b + k]) return true;
            if (p[3 * b + k] < p[3 * a + k]) return false;
        }
        return a < b;  /* ties: the earliest index leads its run */
    });
    std::vector<uint32_t> first(n);
    size_t run = 0;
    for (size_t i = 0; i < n; i++) {
        bool same = i > 0;
        for (int k = 0; k < 3 && same; k++) same = p[3 * order[i] + k] == p[3 * order[run] + k];
        if (!same) run = i;
        first[order[i]] = order[run];
    }
    return first;
}

template <class Dt>
Canon canonical(const Dt &dt, size_t npoints)
{
    Canon c;
    c.points = npoints;
    c.vertices = dt.number_of_vertices();
    c.tets.reserve(dt.number_of_finite_cells());
    for (auto cell = dt.finite_cells_begin(); cell != dt.finite_cells_end(); ++cell) {
        Tet t;
        for (int k = 0; k < 4; k++) t[k] = cell->vertex(k)->info();
        std::sort(t.begin(), t.end());
        c.tets.push_back(t);
    }
    std::sort(c.tets.begin(), c.tets.end());
    return c;
}

std::vector<std::pair<Point, uint32_t>> distinct_points(const std::vector<double> &xyz)
{
    std::vector<uint32_t> first = first_occurrence(xyz);
    std::vector<std::pair<Point, uint32_t>> pts;
    for (size_t i = 0; i < first.size(); i++)
        if (first[i] == i) pts.emplace_back(Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]),
                                            (uint32_t)i);
    return pts;
}

CGAL::Bbox_3 bbox_of(const std::vector<double> &xyz)
{
    CGAL::Bbox_3 b;
    for (size_t i = 0; i + 2 < xyz.size(); i += 3)
        b += CGAL::Bbox_3(xyz[i], xyz[i + 1], xyz[i + 2], xyz[i], xyz[i + 1], xyz[i + 2]);
    return b;
}

void print_canon(const Canon &c)
{
    std::printf("# gtet-canonical points %zu vertices %zu duplicates %zu tets %zu\n", c.points,
                c.vertices, c.points - c.vertices, c.tets.size());
    for (const Tet &t : c.tets)
        std::printf("%u %u %u %u\n", (unsigned)t[0], (unsigned)t[1], (unsigned)t[2],
                    (unsigned)t[3]);
}

double seconds_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/* CPU seconds of the whole process (all threads): on a loaded shared machine the fair
 * measure for a one-thread run, and the one TetGen itself reports (clock()). */
double cpu_seconds()
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int run(const std::string &path, int parallel, bool timing)
{
    std::vector<double> xyz = gtet_ref::read_points(path);
    size_t n = xyz.size() / 3;
    if (n > UINT32_MAX) {
        std::fprintf(stderr, "cgal_dt: %s: too many points for 32-bit ids\n", path.c_str());
        return 2;
    }
    if (timing) {
        std::vector<Point> pts;
        pts.reserve(n);
        for (size_t i = 0; i < n; i++) pts.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        std::vector<double>().swap(xyz);  /* as a user would: only CGAL's copy stays */
        size_t nv = 0, nt = 0;
        double s = 0.0, c0 = cpu_seconds(), c = 0.0;
        if (parallel == 0) {
            auto t0 = std::chrono::steady_clock::now();
            std::unique_ptr<Dt_seq> dt(new Dt_seq(pts.begin(), pts.end()));
            s = seconds_since(t0);
            c = cpu_seconds() - c0;
            nv = dt->number_of_vertices();
            nt = dt->number_of_finite_cells();
        } else {
#ifdef CGAL_LINKED_WITH_TBB
            CGAL::Bbox_3 box;
            for (const Point &p : pts) box += p.bbox();
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      (size_t)parallel);
            c0 = cpu_seconds();
            auto t0 = std::chrono::steady_clock::now();
            Dt_par::Lock_data_structure locks(box, 50);
            std::unique_ptr<Dt_par> dt(new Dt_par(pts.begin(), pts.end(), &locks));
            s = seconds_since(t0);
            c = cpu_seconds() - c0;
            nv = dt->number_of_vertices();
            nt = dt->number_of_finite_cells();
#endif
        }
        std::printf("cgal %s threads %d points %zu vertices %zu tets %zu seconds %.6f cpu %.6f\n",
                    parallel ? "par" : "seq", parallel ? parallel : 1, n, nv, nt, s, c);
        return 0;
    }
    std::vector<std::pair<Point, uint32_t>> pts = distinct_points(xyz);
    Canon c;
    if (parallel == 0) {
        Dt_seq dt(pts.begin(), pts.end());
        c = canonical(dt, n);
    } else {
#ifdef CGAL_LINKED_WITH_TBB
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, (size_t)parallel);
        Dt_par::Lock_data_structure locks(bbox_of(xyz), 50);
        Dt_par dt(pts.begin(), pts.end(), &locks);
        c = canonical(dt, n);
#endif
    }
    print_canon(c);
    return std::fflush(stdout) == 0 ? 0 : 2;
}

}  // namespace

int main(int argc, char **argv)
{
    int parallel = 0;
    bool timing = false;
    std::string path;
    for (int i = 1; i < argc; i++) {
        if (!std::strcmp(argv[i], "--parallel") && i + 1 < argc) {
            parallel = std::atoi(argv[++i]);
            if (parallel < 1) parallel = 1;
        } else if (!std::strcmp(argv[i], "--time")) {
            timing = true;
        } else if (argv[i][0] != '-' && path.empty()) {
            path = argv[i];
        } else {
            path.clear();
            break;
        }
    }
    if (path.empty()) {
        std::fprintf(stderr, "usage: cgal_dt [--parallel THREADS] [--time] POINTS.{bin,xyz}\n");
        return 1;
    }
#ifndef CGAL_LINKED_WITH_TBB
    if (parallel) {
        std::fprintf(stderr, "cgal_dt: built without TBB; --parallel is unavailable\n");
        return 1;
    }
#endif
    try {
        return run(path, parallel, timing);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "cgal_dt: %s\n", e.what());
        return 2;
    }
}
