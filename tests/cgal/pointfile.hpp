/* pointfile.hpp -- read a point set for the CGAL reference programs (tests/cgal, bench).
 *
 * Two formats, the ones gigatet's CLI reads and the driver writes:
 *   .bin  little-endian uint64 count, then count*3 IEEE binary64 (x y z per point);
 *   .xyz  text, one "x y z" per line, '#' starts a comment, blank lines ignored.
 * Text is parsed with strtod, which rounds correctly (and reads C99 hex floats), so a file
 * printed with %.17g or %a reads back bit-exact.  Every error throws std::runtime_error
 * naming the file and the line or point, so a bad input never turns into a wrong mesh.
 */
#ifndef GTET_POINTFILE_HPP
#define GTET_POINTFILE_HPP

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace gtet_ref {

inline bool ends_with(const std::string &s, const char *suffix)
{
    size_t m = std::strlen(suffix);
    return s.size() >= m && s.compare(s.size() - m, m, suffix) == 0;
}

/* Returns 3*n doubles.  Rejects non-finite coordinates: neither peer defines a mesh for them. */
inline std::vector<double> read_points(const std::string &path)
{
    std::FILE *f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
    std::vector<double> xyz;
    if (ends_with(path, ".bin")) {
        unsigned char head[8];
        if (std::fread(head, 1, 8, f) != 8) {
            std::fclose(f);
            throw std::runtime_error(path + ": truncated header");
        }
        uint64_t n = 0;
        for (int i = 7; i >= 0; i--) n = (n << 8) | head[i];  /* little-endian on any host */
        if (n > (uint64_t)1 << 34) {
            std::fclose(f);
            throw std::runtime_error(path + ": absurd point count");
        }
        xyz.resize((size_t)n * 3);
        size_t got = std::fread(xyz.data(), sizeof(double), xyz.size(), f);
        std::fclose(f);
        if (got != xyz.size())
            throw std::runtime_error(path + ": truncated: " + std::to_string(got / 3) + " of " +
                                     std::to_string(n) + " points");
        /* The driver only runs on little-endian hosts (x86-64); a big-endian host would need
         * byte swaps here. */
        static_assert(sizeof(double) == 8, "binary64 expected");
    } else {
        char line[4096];
        size_t lineno = 0;
        while (std::fgets(line, sizeof line, f)) {
            lineno++;
            char *hash = std::strchr(line, '#');
            if (hash) *hash = '\0';
            char *p = line;
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
            if (*p == '\0') continue;
            for (int k = 0; k < 3; k++) {
                char *end = nullptr;
                double v = std::strtod(p, &end);
                if (end == p) {
                    std::fclose(f);
                    throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                             ": expected three numbers");
                }
                xyz.push_back(v);
                p = end;
            }
        }
        std::fclose(f);
    }
    for (size_t i = 0; i < xyz.size(); i++)
        if (!std::isfinite(xyz[i]))
            throw std::runtime_error(path + ": point " + std::to_string(i / 3) +
                                     " has a non-finite coordinate");
    return xyz;
}

}  // namespace gtet_ref

#endif
