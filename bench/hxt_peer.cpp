/* hxt_peer.cpp -- time HXT (the paper's own parallel Delaunay code) as Debian's libgmsh ships it.
 *
 *   hxt_peer [-t THREADS] [--algo A] POINTS.{bin,xyz}
 *
 * Calls gmsh::model::mesh::tetrahedralize(coord, tetra) with Mesh.Algorithm3D = 10 (HXT) and
 * General.NumThreads = THREADS: the public Gmsh API entry that triangulates a bare point cloud.
 * Only that call is timed, not reading the file or gmsh::initialize.  Prints
 *   hxt threads T points N tets M seconds S cpu C
 * with S wall (steady clock) and C the process CPU time (all threads) of the call.
 * --algo A sets another Mesh.Algorithm3D (1 = Gmsh's own Delaunay) to see that 10 is really a
 * different code path.  Gmsh's messages are silenced (General.Verbosity 0).
 */
#include <gmsh.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "../tests/cgal/pointfile.hpp"

int main(int argc, char **argv)
{
    int threads = 1, algo = 10;
    std::string path;
    for (int i = 1; i < argc; i++) {
        if (!std::strcmp(argv[i], "-t") && i + 1 < argc) {
            threads = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--algo") && i + 1 < argc) {
            algo = std::atoi(argv[++i]);
        } else if (argv[i][0] != '-' && path.empty()) {
            path = argv[i];
        } else {
            path.clear();
            break;
        }
    }
    if (path.empty() || threads < 1) {
        std::fprintf(stderr, "usage: hxt_peer [-t THREADS] [--algo A] POINTS.{bin,xyz}\n");
        return 1;
    }
    try {
        std::vector<double> xyz = gtet_ref::read_points(path);
        gmsh::initialize();
        gmsh::option::setNumber("General.Verbosity", 0);
        gmsh::option::setNumber("General.NumThreads", threads);
        gmsh::option::setNumber("Mesh.Algorithm3D", algo);
        std::vector<std::size_t> tetra;
        struct timespec c0, c1;
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
        auto t0 = std::chrono::steady_clock::now();
        gmsh::model::mesh::tetrahedralize(xyz, tetra);
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
        double c = (double)(c1.tv_sec - c0.tv_sec) + 1e-9 * (double)(c1.tv_nsec - c0.tv_nsec);
        std::printf("hxt threads %d points %zu tets %zu seconds %.6f cpu %.6f\n", threads,
                    xyz.size() / 3, tetra.size() / 4, s, c);
        gmsh::finalize();
    } catch (const std::exception &e) {
        std::fprintf(stderr, "hxt_peer: %s\n", e.what());
        return 2;
    } catch (...) {
        std::fprintf(stderr, "hxt_peer: gmsh raised an error\n");
        return 2;
    }
    return 0;
}
