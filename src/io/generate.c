/* generate.c -- point sets for research and tests, random and degenerate.
 *
 * Random kinds use splitmix64 seeded with the user's seed (no rand(), no global state), and
 * only correctly rounded IEEE operations plus log/sqrt/cos/sin from libm (Gaussians), so a
 * (kind, n, seed) triple gives the same points wherever libm is correctly rounded for those
 * calls (glibc's are).  The degenerate kinds are exact: integer coordinates (or integer
 * coordinates times a power of two), so every co-spherical / coplanar relation the kind
 * promises holds exactly in binary64, not just approximately.
 *
 *   uniform      n points uniform in [0,1)^3 (53 random bits per coordinate)
 *   ball         n points uniform in the unit ball (rejection sampling)
 *   sphere       n points on the unit sphere (points of the ball projected onto it; rounding
 *                leaves them within an ulp of it, so they are not exactly co-spherical)
 *   grid         k^3 integer points {0..k-1}^3, k^3 the cube nearest n: massively co-spherical
 *   jittered     the same grid, each coordinate moved by a uniform amount in [-2^-20, 2^-20]
 *                (near-degenerate: the filters' hard case)
 *   cospherical  all integer solutions of x^2+y^2+z^2 = r^2 for a prime r ~ n/6 (about 6r
 *                points, exactly on one sphere)
 *   paraboloid   (x, y, x^2+y^2) for the integer grid |x|,|y| <= k/2, k = round(sqrt(n)): the
 *                lifted grid, every co-circular set of grid points becomes coplanar
 *   fcc          face-centred cubic lattice: integer points of [0,2k]^3 with an even
 *                coordinate sum, k chosen so that there are about n
 *   bcc          body-centred cubic lattice: integer points of [0,2k]^3 whose coordinates are
 *                all even or all odd
 *   plane-apex   n-1 points uniform in the square [0,1)^2 of the plane z = 0, plus the apex
 *                (0.5, 0.5, 1)
 *   plane-apex-denormal   the same with the apex at height 2^-1074 (the smallest denormal)
 *   clustered    n points in 1 + n/1000 Gaussian clusters (sigma 0.01) with centres uniform
 *                in [0,1)^3
 *   far-point    n-1 points uniform in [0,1)^3 and one at (10^6, 10^6, 10^6): every other point
 *                in one Moore cell of the bounding box (the BRIO's refinement, src/sort/brio.c)
 *   cauchy       n points with Cauchy-distributed coordinates (a ratio of two Gaussians):
 *                heavy tails, a bounding box some 10^5 times the bulk's
 *   surface      n points uniform by area on the triangles of a mesh file: not made here
 *                but by io_sample_surface (sample_surface.c), which needs the mesh; listed
 *                so that the help and the CLI's list of kinds name it
 */
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const kinds[] = {"uniform", "ball", "sphere", "grid", "jittered",
                                    "cospherical", "paraboloid", "fcc", "bcc", "plane-apex",
                                    "plane-apex-denormal", "clustered", "far-point", "cauchy",
                                    "surface", NULL};
static const char *const helps[] = {
    "uniform in the unit cube [0,1)^3",
    "uniform in the unit ball",
    "on the unit sphere (within rounding)",
    "integer grid k^3, the cube nearest N",
    "integer grid k^3 with each coordinate jittered by at most 2^-20",
    "integer solutions of x^2+y^2+z^2 = r^2, r prime ~ N/6 (about N points)",
    "(x, y, x^2+y^2) on an integer grid of about N points",
    "face-centred cubic lattice, about N points",
    "body-centred cubic lattice, about N points",
    "N-1 points on the plane z = 0 plus the apex (0.5, 0.5, 1)",
    "N-1 points on the plane z = 0 plus an apex at height 2^-1074",
    "Gaussian clusters (sigma 0.01), 1 + N/1000 of them",
    "N-1 points uniform in [0,1)^3 plus one at (10^6, 10^6, 10^6)",
    "Cauchy-distributed coordinates (heavy tails)",
    "uniform by area on the triangles of --mesh FILE (.off or .ply)",
};

const char *const *io_generator_kinds(void) { return kinds; }

const char *io_generator_help(const char *kind)
{
    for (int i = 0; kinds[i]; i++)
        if (strcmp(kinds[i], kind) == 0) return helps[i];
    return NULL;
}

typedef struct rng { uint64_t s; } rng;

uint64_t io_splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static uint64_t next(rng *r) { return io_splitmix64(&r->s); }

static double uniform(rng *r) { return (double)(next(r) >> 11) * 0x1p-53; }

/* A standard normal deviate (Box-Muller; 1 - u keeps the log's argument in (0, 1]). */
static double gauss(rng *r)
{
    double u = 1.0 - uniform(r), v = uniform(r);
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

static size_t icbrt_round(size_t n)
{
    size_t k = (size_t)cbrt((double)n);
    while ((k + 1) * (k + 1) * (k + 1) <= n) k++;
    /* round: pick k or k+1, whichever cube is closer */
    if (n - k * k * k > (k + 1) * (k + 1) * (k + 1) - n) k++;
    return k ? k : 1;
}

static uint64_t isqrt64(uint64_t x)
{
    uint64_t r = (uint64_t)sqrt((double)x);
    while (r * r > x) r--;
    while ((r + 1) * (r + 1) <= x) r++;
    return r;
}

static int is_prime(uint64_t p)
{
    if (p < 2) return 0;
    for (uint64_t d = 2; d * d <= p; d++)
        if (p % d == 0) return 0;
    return 1;
}

/* Emit every sign variant of (x, y, z) >= 0 (zero coordinates only once). */
static size_t emit_signs(double *a, size_t k, int64_t x, int64_t y, int64_t z)
{
    for (int sx = 0; sx < (x ? 2 : 1); sx++)
        for (int sy = 0; sy < (y ? 2 : 1); sy++)
            for (int sz = 0; sz < (z ? 2 : 1); sz++) {
                if (a) {
                    a[3 * k] = (double)(sx ? -x : x);
                    a[3 * k + 1] = (double)(sy ? -y : y);
                    a[3 * k + 2] = (double)(sz ? -z : z);
                }
                k++;
            }
    return k;
}

/* Integer points on the sphere of radius r: two passes, count then fill. */
static size_t cospherical(double *a, int64_t r)
{
    size_t k = 0;
    for (int64_t x = 0; x <= r; x++)
        for (int64_t y = 0; x * x + y * y <= r * r; y++) {
            uint64_t zz = (uint64_t)(r * r - x * x - y * y);
            uint64_t z = isqrt64(zz);
            if (z * z == zz) k = emit_signs(a, k, x, y, (int64_t)z);
        }
    return k;
}

/* Integer points of [0,2k]^3: fcc keeps an even coordinate sum ((2k+1)^3+1)/2 points),
 * bcc all-even or all-odd coordinates ((k+1)^3 + k^3 points). */
static size_t lattice_size(int64_t k, int bcc)
{
    size_t s = (size_t)(2 * k + 1);
    return bcc ? (size_t)((k + 1) * (k + 1) * (k + 1) + k * k * k) : (s * s * s + 1) / 2;
}

static void lattice(double *a, int64_t k, int bcc)
{
    size_t c = 0;
    for (int64_t i = 0; i <= 2 * k; i++)
        for (int64_t j = 0; j <= 2 * k; j++)
            for (int64_t l = 0; l <= 2 * k; l++) {
                int keep = bcc ? ((i & 1) == (j & 1) && (j & 1) == (l & 1)) : ((i + j + l) % 2 == 0);
                if (!keep) continue;
                a[3 * c] = (double)i;
                a[3 * c + 1] = (double)j;
                a[3 * c + 2] = (double)l;
                c++;
            }
}

static size_t absdiff(size_t a, size_t b) { return a > b ? a - b : b - a; }

/* How many points kind `name` makes for a request of n, and its size parameter *k (the side
 * of a grid, the radius of the sphere, the lattice's half side). */
static size_t gen_size(const char *name, size_t n, int64_t *k)
{
    *k = 0;
    if (!strcmp(name, "grid") || !strcmp(name, "jittered")) {
        *k = (int64_t)icbrt_round(n);
        return (size_t)(*k * *k * *k);
    }
    if (!strcmp(name, "paraboloid")) {
        *k = (int64_t)llround(sqrt((double)n));
        if (*k < 2) *k = 2;
        return (size_t)((*k / 2 * 2 + 1) * (*k / 2 * 2 + 1));
    }
    if (!strcmp(name, "cospherical")) {
        *k = (int64_t)(n / 6 > 3 ? n / 6 : 3);
        while (!is_prime((uint64_t)*k)) (*k)++;
        return cospherical(NULL, *k);
    }
    if (!strcmp(name, "fcc") || !strcmp(name, "bcc")) {
        int bcc = name[0] == 'b';
        *k = 1;
        while (absdiff(lattice_size(*k + 1, bcc), n) < absdiff(lattice_size(*k, bcc), n)) (*k)++;
        return lattice_size(*k, bcc);
    }
    return n;
}

/* The exact kinds (no randomness but the jitter): 1 when `name` is one of them. */
static int gen_exact(const char *name, double *a, size_t m, int64_t k, rng *r)
{
    size_t c = 0;
    if (!strcmp(name, "grid") || !strcmp(name, "jittered")) {
        for (int64_t i = 0; i < k; i++)
            for (int64_t j = 0; j < k; j++)
                for (int64_t l = 0; l < k; l++, c++) {
                    a[3 * c] = (double)i;
                    a[3 * c + 1] = (double)j;
                    a[3 * c + 2] = (double)l;
                    if (name[0] == 'j')
                        for (int d = 0; d < 3; d++)
                            a[3 * c + (size_t)d] += (2.0 * uniform(r) - 1.0) * 0x1p-20;
                }
    } else if (!strcmp(name, "paraboloid")) {
        for (int64_t i = -k / 2; i <= k / 2; i++)
            for (int64_t j = -k / 2; j <= k / 2; j++, c++) {
                a[3 * c] = (double)i;
                a[3 * c + 1] = (double)j;
                a[3 * c + 2] = (double)(i * i + j * j);
            }
    } else if (!strcmp(name, "cospherical")) {
        cospherical(a, k);
    } else if (!strcmp(name, "fcc") || !strcmp(name, "bcc")) {
        lattice(a, k, name[0] == 'b');
    } else if (!strcmp(name, "plane-apex") || !strcmp(name, "plane-apex-denormal")) {
        for (size_t i = 0; i + 1 < m; i++) {
            a[3 * i] = uniform(r);
            a[3 * i + 1] = uniform(r);
            a[3 * i + 2] = 0.0;
        }
        a[3 * (m - 1)] = 0.5;
        a[3 * (m - 1) + 1] = 0.5;
        a[3 * (m - 1) + 2] = strlen(name) > 10 ? 0x1p-1074 : 1.0;
    } else {
        return 0;
    }
    return 1;
}

/* Points of the unit ball by rejection from the cube (not too near the centre, so that
 * `sphere` can project them onto the unit sphere). */
static void ball(double *a, size_t m, rng *r, int on_sphere)
{
    for (size_t i = 0; i < m; i++) {
        double p[3], q;
        do {
            for (int c = 0; c < 3; c++) p[c] = 2.0 * uniform(r) - 1.0;
            q = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        } while (q > 1.0 || q < 1e-6);
        if (on_sphere) {
            double s = 1.0 / sqrt(q);
            for (int c = 0; c < 3; c++) p[c] *= s;
        }
        memcpy(a + 3 * i, p, sizeof p);
    }
}

/* The random kinds. */
static io_status gen_random(const char *name, double *a, size_t m, rng *r, io_error *err)
{
    if (!strcmp(name, "uniform")) {
        for (size_t i = 0; i < 3 * m; i++) a[i] = uniform(r);
    } else if (!strcmp(name, "ball") || !strcmp(name, "sphere")) {
        ball(a, m, r, name[0] == 's');
    } else if (!strcmp(name, "far-point")) {
        for (size_t i = 0; i < 3 * (m - 1); i++) a[i] = uniform(r);
        for (int d = 0; d < 3; d++) a[3 * (m - 1) + (size_t)d] = 1e6;
    } else if (!strcmp(name, "cauchy")) {
        for (size_t i = 0; i < 3 * m; i++) {
            double den;
            do den = gauss(r); while (den == 0.0);
            a[i] = gauss(r) / den;
        }
    } else { /* clustered */
        size_t nc = 1 + m / 1000;
        double *ctr = malloc(nc * 3 * sizeof(double));
        if (!ctr) return io_fail(err, IO_ERR_NOMEM, "out of memory for %zu cluster centres", nc);
        for (size_t i = 0; i < 3 * nc; i++) ctr[i] = uniform(r);
        for (size_t i = 0; i < m; i++) {
            size_t c = (size_t)(next(r) % nc);
            for (int d = 0; d < 3; d++) a[3 * i + (size_t)d] = ctr[3 * c + (size_t)d] + 0.01 * gauss(r);
        }
        free(ctr);
    }
    return IO_OK;
}

io_status io_generate(const char *kind, size_t n, uint64_t seed, double **xyz, size_t *n_out,
                      io_error *err)
{
    *xyz = NULL;
    *n_out = 0;
    int which = -1;
    for (int i = 0; kinds[i]; i++)
        if (strcmp(kinds[i], kind) == 0) which = i;
    if (which < 0) return io_fail(err, IO_ERR_ARGUMENT, "unknown generator kind '%s'", kind);
    if (!strcmp(kind, "surface"))
        return io_fail(err, IO_ERR_ARGUMENT, "the kind 'surface' samples a mesh: "
                       "io_sample_surface (generate surface N --mesh FILE)");
    if (n < 1 || n > (size_t)UINT32_MAX)
        return io_fail(err, IO_ERR_ARGUMENT, "the number of points must be in 1..%u", UINT32_MAX);
    rng r = {seed};
    const char *name = kinds[which];
    int64_t k;
    size_t m = gen_size(name, n, &k);
    double *a = malloc(m * 3 * sizeof(double));
    if (!a) return io_fail(err, IO_ERR_NOMEM, "out of memory for %zu points", m);
    if (!gen_exact(name, a, m, k, &r)) {
        io_status s = gen_random(name, a, m, &r, err);
        if (s != IO_OK) {
            free(a);
            return s;
        }
    }
    *xyz = a;
    *n_out = m;
    return IO_OK;
}
