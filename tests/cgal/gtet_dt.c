/* gtet_dt.c -- gigatet's mesh in the canonical form of tests/cgal/cgal_dt.cpp.
 *
 *   gtet_dt [-t THREADS] INPUT.{bin,xyz}
 *
 * Prints
 *   # gtet-canonical points N vertices V duplicates D tets T
 *   a b c d            (one line per finite tet, a < b < c < d, lines sorted)
 * where a vertex id is the input index of the first occurrence of the vertex's point.  Only
 * the public API is used (gtet_triangulate, gtet_mesh_tets, gtet_mesh_input_map): the input map
 * sends every input index to its vertex, so scanning it in increasing index order and keeping
 * the first index seen per vertex gives exactly that id, whatever numbering the kernel uses
 * internally.  CGAL's side computes the same ids by sorting coordinates, so the two lists agree
 * iff the two meshes have the same tets on the same distinct points.
 *
 * Reads the same two formats as pointfile.hpp: .bin (little-endian uint64 count, count*3
 * binary64) and .xyz (text "x y z" per line, '#' comments), the latter with strtod (correctly
 * rounded, so %.17g / %a text reads back bit-exact).  Exit 0 ok, 1 usage, 2 bad input,
 * 3 gigatet returned an error (its status and message are printed).
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../canon.h"
#include "gigatet.h"

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* Appends one double to a growing array; returns 0 on allocation failure. */
static int push(double **a, size_t *len, size_t *cap, double v)
{
    if (*len == *cap) {
        size_t nc = *cap ? 2 * *cap : 3 * 1024;
        double *na = realloc(*a, nc * sizeof *na);
        if (!na) return 0;
        *a = na;
        *cap = nc;
    }
    (*a)[(*len)++] = v;
    return 1;
}

/* Reads the file into *xyz (3 * *n doubles).  Prints the reason and returns 0 on failure. */
static int read_points(const char *path, double **xyz, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "gtet_dt: %s: cannot open: %s\n", path, strerror(errno));
        return 0;
    }
    double *a = NULL;
    size_t len = 0, cap = 0;
    int ok = 1;
    if (ends_with(path, ".bin")) {
        unsigned char head[8];
        uint64_t count = 0;
        if (fread(head, 1, 8, f) != 8) {
            fprintf(stderr, "gtet_dt: %s: truncated header\n", path);
            ok = 0;
        } else {
            for (int i = 7; i >= 0; i--) count = (count << 8) | head[i];
            if (count > ((uint64_t)1 << 34)) {
                fprintf(stderr, "gtet_dt: %s: absurd point count\n", path);
                ok = 0;
            }
        }
        if (ok) {
            len = (size_t)count * 3;
            a = malloc((len ? len : 1) * sizeof *a);
            if (!a) {
                fprintf(stderr, "gtet_dt: out of memory\n");
                ok = 0;
            } else if (fread(a, sizeof *a, len, f) != len) {
                fprintf(stderr, "gtet_dt: %s: truncated\n", path);
                ok = 0;
            }
        }
    } else {
        char line[4096];
        size_t lineno = 0;
        while (ok && fgets(line, sizeof line, f)) {
            lineno++;
            char *hash = strchr(line, '#');
            if (hash) *hash = '\0';
            char *p = line;
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
            if (*p == '\0') continue;
            for (int k = 0; k < 3 && ok; k++) {
                char *end = NULL;
                double v = strtod(p, &end);
                if (end == p) {
                    fprintf(stderr, "gtet_dt: %s:%zu: expected three numbers\n", path, lineno);
                    ok = 0;
                } else if (!push(&a, &len, &cap, v)) {
                    fprintf(stderr, "gtet_dt: out of memory\n");
                    ok = 0;
                }
                p = end;
            }
        }
    }
    fclose(f);
    if (!ok) {
        free(a);
        return 0;
    }
    *xyz = a;
    *n = len / 3;
    return 1;
}

/* Writes the canonical list of mesh m built from n input points; returns 0 on failure. */
static int print_canonical(const gtet_mesh *m, size_t n)
{
    size_t nv = gtet_mesh_num_vertices(m), nt = gtet_mesh_num_tets(m);
    char why[160];
    uint32_t *canon = canon_input_ids(m, NULL, n, why);
    if (!canon) {
        fprintf(stderr, "gtet_dt: %s\n", why);
        return 0;
    }
    printf("# gtet-canonical points %zu vertices %zu duplicates %zu tets %zu\n", n, nv, n - nv,
           nt);
    for (size_t t = 0; t < nt; t++)
        printf("%u %u %u %u\n", (unsigned)canon[4 * t], (unsigned)canon[4 * t + 1],
               (unsigned)canon[4 * t + 2], (unsigned)canon[4 * t + 3]);
    free(canon);
    return fflush(stdout) == 0;
}

int main(int argc, char **argv)
{
    const char *path = NULL;
    int threads = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-t") == 0 && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (argv[i][0] != '-' && !path) {
            path = argv[i];
        } else {
            path = NULL;
            break;
        }
    }
    if (!path || threads < 0) {
        fprintf(stderr, "usage: gtet_dt [-t THREADS] POINTS.{bin,xyz}\n");
        return 1;
    }
    double *xyz = NULL;
    size_t n = 0;
    if (!read_points(path, &xyz, &n)) return 2;

    gtet_options opts;
    gtet_options_init(&opts);
    opts.threads = threads;
    gtet_error err;
    memset(&err, 0, sizeof err);
    opts.error = &err;
    gtet_mesh *mesh = NULL;
    gtet_status st = gtet_triangulate(xyz, n, &opts, &mesh);
    if (st != GTET_OK) {
        fprintf(stderr, "gtet_dt: %s: %s: %s\n", path, gtet_status_str(st), err.message);
        free(xyz);
        return 3;
    }
    int ok = print_canonical(mesh, n);
    gtet_mesh_free(&mesh);
    free(xyz);
    return ok ? 0 : 2;
}
