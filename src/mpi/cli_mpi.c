/* cli_mpi.c -- gigatet-mpi: `gigatet triangulate` over MPI ranks.
 *
 *   mpirun -np N gigatet-mpi triangulate INPUT [-o OUTPUT] [-t THREADS] [--check] [--stats] [-q]
 *
 * Exit codes as gigatet's, the same on every rank: 0 ok, 1 usage, 2 bad input file or data
 * (also: the output cannot be written), 3 degenerate input, 4 out of memory, 5 check failed.
 * Only rank 0 prints.  .bin input is read with MPI-IO, each rank a slice; the other formats
 * by rank 0 (src/io) and scattered.  -o FILE.ele/.msh/.vtu gathers the mesh to rank 0 and
 * writes one file; -o FILE.pvtu writes one piece FILE_<rank>.vtu per rank and the .pvtu
 * index (no partial output on failure: every piece is removed).
 *
 * Test hook: GTET_MPI_FAIL_ALLOC="RANK:K" makes the K-th allocation of the distributed layer
 * fail on rank RANK (the out-of-memory path of the tests).
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/io.h"
#include "mpi/mpi_internal.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

enum { XC_OK = 0, XC_USAGE = 1, XC_INPUT = 2, XC_DEGENERATE = 3, XC_NOMEM = 4, XC_CHECK = 5 };

static int g_rank, g_size;

static void say(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void say(const char *fmt, ...)
{
    if (g_rank != 0) return;
    va_list ap;
    va_start(ap, fmt);
    fputs("gigatet-mpi: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

static int exit_of(gtet_status s)
{
    switch (s) {
    case GTET_OK: return XC_OK;
    case GTET_ERR_ARGUMENT: return XC_USAGE;
    case GTET_ERR_NONFINITE:
    case GTET_ERR_TOO_LARGE: return XC_INPUT;
    case GTET_ERR_DEGENERATE_INPUT: return XC_DEGENERATE;
    case GTET_ERR_OUT_OF_MEMORY: return XC_NOMEM;
    default: return XC_CHECK;
    }
}

static int exit_of_io(io_status s)
{
    switch (s) {
    case IO_OK: return XC_OK;
    case IO_ERR_ARGUMENT: return XC_USAGE;
    case IO_ERR_NOMEM: return XC_NOMEM;
    default: return XC_INPUT;
    }
}

/* every rank: agree on an exit code and a message (the lowest failing rank's) */
static int agree(int code, char *msg, size_t msize)
{
    int me = code ? g_rank : g_size, low;
    MPI_Allreduce(&me, &low, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (low == g_size) return 0;
    int cm[1] = {code};
    MPI_Bcast(cm, 1, MPI_INT, low, MPI_COMM_WORLD);
    MPI_Bcast(msg, (int)msize, MPI_CHAR, low, MPI_COMM_WORLD);
    return cm[0];
}

static void usage_text(void)
{
    if (g_rank) return;
    fputs("usage: mpirun -np N gigatet-mpi triangulate INPUT [-o OUTPUT] [-t THREADS] [--check] "
          "[--stats] [-q]\n"
          "  INPUT   .xyz, .node, .ply or .bin (.bin is read with MPI-IO, a slice per rank)\n"
          "  -o      .ele, .msh or .vtu (the mesh gathered to rank 0), .pvtu (a piece per rank)\n"
          "  -t      OpenMP threads per rank (0 = all cores; default 1)\n"
          "  --check exact checker on each rank's triangulation and the cross-rank adjacency\n"
          "  --stats one JSON object: per-rank tile, ghost points, bytes sent, seconds\n"
          "  -q      print only errors\n",
          stderr);
}

/* ---- input ---------------------------------------------------------------------------- */

static int ends_with(const char *s, const char *e)
{
    size_t a = strlen(s), b = strlen(e);
    if (a < b) return 0;
    for (size_t i = 0; i < b; i++) {
        char x = s[a - b + i];
        if (x >= 'A' && x <= 'Z') x = (char)(x - 'A' + 'a');
        if (x != e[i]) return 0;
    }
    return 1;
}

/* .bin with MPI-IO: rank r reads points [N r / P, N (r+1) / P) */
static int read_bin(const char *path, double **xyz, size_t *n, uint64_t *first, char *msg,
                    size_t msize)
{
    MPI_File fh;
    int code = 0;
    *xyz = NULL;
    *n = 0;
    int rc = MPI_File_open(MPI_COMM_WORLD, path, MPI_MODE_RDONLY, MPI_INFO_NULL, &fh);
    if (rc != MPI_SUCCESS) {
        snprintf(msg, msize, "%s: cannot open the file", path);
        return XC_INPUT;   /* the open is collective: every rank saw the failure */
    }
    MPI_Offset size = 0;
    MPI_File_get_size(fh, &size);
    uint64_t count = 0;
    unsigned char hdr[8] = {0};
    if (g_rank == 0 && size >= 8) MPI_File_read_at(fh, 0, hdr, 8, MPI_BYTE, MPI_STATUS_IGNORE);
    MPI_Bcast(hdr, 8, MPI_BYTE, 0, MPI_COMM_WORLD);
    for (int i = 7; i >= 0; i--) count = count << 8 | hdr[i];
    if (size < 8) {
        snprintf(msg, msize, "%s: too short for a .bin header (%lld bytes)", path,
                 (long long)size);
        code = XC_INPUT;
    } else if (count == 0) {
        snprintf(msg, msize, "%s: the header says 0 points", path);
        code = XC_INPUT;
    } else if (count > (uint64_t)(size - 8) / 24 || (uint64_t)(size - 8) != 24 * count) {
        snprintf(msg, msize, "%s: the header says %" PRIu64 " points but the file holds %lld "
                 "bytes of coordinates (%" PRIu64 " expected)", path, count,
                 (long long)(size - 8), 24 * count);
        code = XC_INPUT;
    }
    if (code) {
        MPI_File_close(&fh);
        return code;
    }
    uint64_t a = count * (uint64_t)g_rank / (uint64_t)g_size;
    uint64_t b = count * (uint64_t)(g_rank + 1) / (uint64_t)g_size;
    *first = a;
    *n = (size_t)(b - a);
    *xyz = malloc(3 * *n * sizeof(double) + 8);
    if (!*xyz) {
        snprintf(msg, msize, "rank %d: out of memory for %zu points", g_rank, *n);
        code = XC_NOMEM;
    }
    code = agree(code, msg, msize);
    if (code) {
        free(*xyz);
        *xyz = NULL;
        MPI_File_close(&fh);
        return code;
    }
    /* collective read in chunks below 2^31 bytes */
    uint64_t done = 0, total = 3 * (uint64_t)*n;
    uint64_t maxall = 0, mine = total;
    MPI_Allreduce(&mine, &maxall, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
    const uint64_t chunk = (uint64_t)1 << 27;   /* doubles */
    int ioerr = 0;
    for (uint64_t at = 0; at < maxall; at += chunk) {
        uint64_t k = done < total ? (total - done < chunk ? total - done : chunk) : 0;
        MPI_Offset off = (MPI_Offset)(8 + 24 * a + 8 * done);
        if (MPI_File_read_at_all(fh, off, *xyz + done, (int)k, MPI_DOUBLE, MPI_STATUS_IGNORE) !=
            MPI_SUCCESS)
            ioerr = 1;
        done += k;
    }
    MPI_File_close(&fh);
    if (ioerr) {
        snprintf(msg, msize, "%s: read error on rank %d", path, g_rank);
        code = XC_INPUT;
    }
    return code;
}

/* other formats: rank 0 reads, then a slice to each rank */
static int read_root(const char *path, double **xyz, size_t *n, uint64_t *first, char *msg,
                     size_t msize)
{
    double *all = NULL;
    size_t na = 0;
    int code = 0;
    if (g_rank == 0) {
        io_error e;
        io_status s = io_read_points(path, &all, &na, &e);
        if (s != IO_OK) {
            snprintf(msg, msize, "%s", e.message);
            code = exit_of_io(s);
        } else if (3 * (uint64_t)na > (uint64_t)INT_MAX) {
            snprintf(msg, msize, "%s: %zu points: more than rank 0 can scatter (use .bin)", path,
                     na);
            code = XC_INPUT;
        }
    }
    code = agree(code, msg, msize);
    if (code) {
        free(all);
        return code;
    }
    uint64_t count = na;
    MPI_Bcast(&count, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    uint64_t a = count * (uint64_t)g_rank / (uint64_t)g_size;
    uint64_t b = count * (uint64_t)(g_rank + 1) / (uint64_t)g_size;
    *first = a;
    *n = (size_t)(b - a);
    *xyz = malloc(3 * *n * sizeof(double) + 8);
    int *cnt = malloc(2 * (size_t)g_size * sizeof *cnt);
    if (!*xyz || !cnt) {
        snprintf(msg, msize, "rank %d: out of memory", g_rank);
        code = XC_NOMEM;
    }
    code = agree(code, msg, msize);
    if (code) {
        free(all);
        free(cnt);
        free(*xyz);
        *xyz = NULL;
        return code;
    }
    for (int q = 0; q < g_size; q++) {
        uint64_t qa = count * (uint64_t)q / (uint64_t)g_size;
        uint64_t qb = count * (uint64_t)(q + 1) / (uint64_t)g_size;
        cnt[q] = (int)(3 * (qb - qa));
        cnt[g_size + q] = (int)(3 * qa);
    }
    MPI_Scatterv(all, cnt, cnt + g_size, MPI_DOUBLE, *xyz, (int)(3 * *n), MPI_DOUBLE, 0,
                 MPI_COMM_WORLD);
    free(cnt);
    free(all);
    return 0;
}

/* ---- output --------------------------------------------------------------------------- */

/* gather the mesh to rank 0: vertices by global id, tets with 32-bit ids (a 32-bit result's
 * rows as they are, a 64-bit one's narrowed: the vertex count was checked to fit) */
static int gather_mesh(const gtet_mpi_result *r, double **vout, uint32_t **tout, char *msg,
                       size_t msize)
{
    int code = 0;
    *vout = NULL;
    *tout = NULL;
    if (r->num_vertices > UINT32_MAX - 1 || 4 * r->num_tets_global > (uint64_t)INT_MAX ||
        3 * r->num_vertices > (uint64_t)INT_MAX) {
        snprintf(msg, msize, "the mesh (%llu vertices, %llu tets) is too large to gather in one "
                 "file: write .pvtu", (unsigned long long)r->num_vertices,
                 (unsigned long long)r->num_tets_global);
        return XC_INPUT;
    }
    int *cnt = malloc(4 * (size_t)g_size * sizeof *cnt);
    double *vx = NULL, *vtmp = NULL;
    uint64_t *ids = NULL, *tets = NULL;
    uint32_t *t32 = NULL;
    if (g_rank == 0) {
        vx = malloc((3 * r->num_vertices + 1) * sizeof *vx);
        vtmp = malloc((3 * r->num_vertices + 1) * sizeof *vtmp);
        ids = malloc((r->num_vertices + 1) * sizeof *ids);
        if (r->id_bits != 32) tets = malloc((4 * r->num_tets_global + 1) * sizeof *tets);
        t32 = malloc((4 * r->num_tets_global + 1) * sizeof *t32);
        if (!vx || !vtmp || !ids || (!tets && r->id_bits != 32) || !t32) code = XC_NOMEM;
    }
    if (!cnt) code = XC_NOMEM;
    if (code) snprintf(msg, msize, "rank %d: out of memory gathering the mesh", g_rank);
    if ((code = agree(code, msg, msize)) != 0) goto done;
    int mine = (int)r->num_tile_vertices;
    MPI_Gather(&mine, 1, MPI_INT, cnt, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (g_rank == 0) {
        int at = 0;
        for (int q = 0; q < g_size; q++) {
            cnt[2 * g_size + q] = at;
            at += cnt[q];
        }
    }
    MPI_Gatherv(r->tile_vertex_ids, mine, MPI_UINT64_T, ids, cnt, cnt + 2 * g_size,
                MPI_UINT64_T, 0, MPI_COMM_WORLD);
    if (g_rank == 0)
        for (int q = 0; q < g_size; q++) {
            cnt[q] *= 3;
            cnt[2 * g_size + q] *= 3;
        }
    MPI_Gatherv(r->tile_vertices, 3 * mine, MPI_DOUBLE, vtmp, cnt, cnt + 2 * g_size, MPI_DOUBLE,
                0, MPI_COMM_WORLD);
    int mt = (int)(4 * r->num_tets);
    MPI_Gather(&mt, 1, MPI_INT, cnt, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (g_rank == 0) {
        int at = 0;
        for (int q = 0; q < g_size; q++) {
            cnt[2 * g_size + q] = at;
            at += cnt[q];
        }
    }
    if (r->id_bits == 32)
        MPI_Gatherv(r->tets32, mt, MPI_UINT32_T, t32, cnt, cnt + 2 * g_size, MPI_UINT32_T, 0,
                    MPI_COMM_WORLD);
    else
        MPI_Gatherv(r->tets, mt, MPI_UINT64_T, tets, cnt, cnt + 2 * g_size, MPI_UINT64_T, 0,
                    MPI_COMM_WORLD);
    if (g_rank == 0) {
        for (uint64_t i = 0; i < r->num_vertices; i++)
            memcpy(vx + 3 * ids[i], vtmp + 3 * i, 3 * sizeof(double));
        if (r->id_bits != 32)
            for (uint64_t i = 0; i < 4 * r->num_tets_global; i++) t32[i] = (uint32_t)tets[i];
        *vout = vx;
        *tout = t32;
        vx = NULL;
        t32 = NULL;
    }
done:
    free(cnt);
    free(vx);
    free(vtmp);
    free(ids);
    free(tets);
    free(t32);
    return code;
}

static char *piece_path(const char *out, int rank)
{
    size_t len = strlen(out) - 5;   /* without ".pvtu" */
    char *p = malloc(len + 32);
    if (p) snprintf(p, len + 32, "%.*s_%d.vtu", (int)len, out, rank);
    return p;
}

static int write_pvtu(const char *out, const gtet_mpi_result *r, char *msg, size_t msize)
{
    int code = 0;
    char *piece = piece_path(out, g_rank);
    uint32_t *t32 = malloc((4 * r->num_tets + 1) * sizeof *t32);
    if (!piece || !t32) {
        snprintf(msg, msize, "rank %d: out of memory", g_rank);
        code = XC_NOMEM;
    }
    if (!code) {
        for (size_t i = 0; i < 4 * r->num_tets; i++) {
            /* used ids are sorted */
            uint64_t id = r->id_bits == 32 ? r->tets32[i] : r->tets[i];
            size_t lo = 0, hi = r->num_used_vertices;
            while (hi - lo > 1) {
                size_t mid = (lo + hi) / 2;
                if (r->used_vertex_ids[mid] <= id) lo = mid;
                else hi = mid;
            }
            t32[i] = (uint32_t)lo;
        }
        io_error e;
        io_status s = io_write_mesh(piece, r->used_vertices, r->num_used_vertices, t32,
                                    r->num_tets, &e);
        if (s != IO_OK) {
            snprintf(msg, msize, "%s", e.message);
            code = exit_of_io(s);
        }
    }
    free(t32);
    code = agree(code, msg, msize);
    if (!code && g_rank == 0) {
        /* the index: written to a temporary next to it, renamed when complete */
        size_t len = strlen(out);
        char *tmp = malloc(len + 16);
        FILE *f = NULL;
        if (tmp) {
            snprintf(tmp, len + 16, "%s.tmp%d", out, (int)getpid());
            f = fopen(tmp, "wx");
        }
        int ok = f != NULL;
        if (f) {
            const char *base = strrchr(out, '/');
            base = base ? base + 1 : out;
            size_t blen = strlen(base) - 5;
            fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" "
                    "version=\"0.1\" byte_order=\"LittleEndian\">\n<PUnstructuredGrid "
                    "GhostLevel=\"0\">\n<PPoints>\n<PDataArray type=\"Float64\" "
                    "NumberOfComponents=\"3\"/>\n</PPoints>\n");
            for (int q = 0; q < g_size; q++)
                fprintf(f, "<Piece Source=\"%.*s_%d.vtu\"/>\n", (int)blen, base, q);
            fprintf(f, "</PUnstructuredGrid>\n</VTKFile>\n");
            ok = !ferror(f);
            ok = (fclose(f) == 0) && ok;
            if (ok) ok = rename(tmp, out) == 0;
            if (!ok) remove(tmp);
        }
        if (!ok) {
            snprintf(msg, msize, "%s: cannot write the file (%s)", out, strerror(errno));
            code = XC_INPUT;
        }
        free(tmp);
    }
    code = agree(code, msg, msize);
    if (code && piece) remove(piece);   /* no partial output */
    free(piece);
    return code;
}

/* ---- main ----------------------------------------------------------------------------- */

typedef struct args {
    const char *input, *output;
    long threads;
    int check, stats, quiet;
} args;

static int parse(int argc, char **argv, args *a, char *msg, size_t msize)
{
    memset(a, 0, sizeof *a);
    a->threads = 1;
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage_text();
        return argc < 2 ? XC_USAGE : -1;
    }
    if (strcmp(argv[1], "triangulate")) {
        snprintf(msg, msize, "unknown command '%s' (gigatet-mpi has: triangulate)", argv[1]);
        return XC_USAGE;
    }
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "-o") || !strcmp(s, "--output") || !strcmp(s, "-t") ||
            !strcmp(s, "--threads")) {
            if (i + 1 >= argc) {
                snprintf(msg, msize, "%s needs a value", s);
                return XC_USAGE;
            }
            const char *v = argv[++i];
            if (s[1] == 'o' || s[2] == 'o') {
                a->output = v;
            } else {
                char *end;
                errno = 0;
                long t = strtol(v, &end, 10);
                if (!*v || *end || errno || t < 0 || t > 4096) {
                    snprintf(msg, msize, "-t needs a thread count in 0..4096, not '%s'", v);
                    return XC_USAGE;
                }
                a->threads = t;
            }
        } else if (!strcmp(s, "--check")) {
            a->check = 1;
        } else if (!strcmp(s, "--stats")) {
            a->stats = 1;
        } else if (!strcmp(s, "-q") || !strcmp(s, "--quiet")) {
            a->quiet = 1;
        } else if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            usage_text();
            return -1;
        } else if (s[0] == '-' && s[1]) {
            snprintf(msg, msize, "unknown option '%s'", s);
            return XC_USAGE;
        } else if (!a->input) {
            a->input = s;
        } else {
            snprintf(msg, msize, "unexpected argument '%s'", s);
            return XC_USAGE;
        }
    }
    if (!a->input) {
        snprintf(msg, msize, "triangulate needs an INPUT file");
        return XC_USAGE;
    }
    if (a->output && !ends_with(a->output, ".pvtu") && !ends_with(a->output, ".ele") &&
        !ends_with(a->output, ".msh") && !ends_with(a->output, ".vtu")) {
        snprintf(msg, msize, "%s: the output must be .ele, .msh, .vtu or .pvtu", a->output);
        return XC_USAGE;
    }
    return 0;
}

static void print_stats(const args *a, const gtet_mpi_result *r, double seconds_read)
{
    gtet_mpi_stats *all = g_rank == 0 ? malloc((size_t)g_size * sizeof *all) : NULL;
    int ok = g_rank != 0 || all != NULL;
    int allok = 0;
    MPI_Allreduce(&ok, &allok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!allok) {
        free(all);
        return;
    }
    MPI_Gather(&r->stats, (int)sizeof r->stats, MPI_BYTE, all, (int)sizeof r->stats, MPI_BYTE, 0,
               MPI_COMM_WORLD);
    if (g_rank) return;
    printf("{\"input\":\"%s\",\"ranks\":%d,\"threads_per_rank\":%ld,\"points\":%llu,"
           "\"vertices\":%llu,\"duplicates\":%llu,\"tets\":%llu,\"hull_facets\":%llu,"
           "\"rounds\":%d,\"id_bits\":%d,\"seconds_read\":%.6f,\"per_rank\":[",
           a->input, g_size, a->threads, (unsigned long long)r->num_points_global,
           (unsigned long long)r->num_vertices, (unsigned long long)r->num_duplicates,
           (unsigned long long)r->num_tets_global, (unsigned long long)r->num_hull_facets,
           r->stats.rounds, r->id_bits, seconds_read);
    for (int q = 0; q < g_size; q++) {
        const gtet_mpi_stats *s = &all[q];
        printf("%s{\"rank\":%d,\"tile_points\":%llu,\"ghost_points\":%llu,\"ghost_seeded\":%llu,"
               "\"rebuilds\":%d,\"scans\":%d,\"queries_sent\":%llu,\"bytes_sent\":%llu,"
               "\"bytes_sent_ghost\":%llu,\"answer_tests\":%llu,\"answer_lifts\":%d,"
               "\"answers_near\":%llu,"
               "\"tets\":%llu,\"seconds\":{\"validate\":%.6f,\"partition\":%.6f,"
               "\"triangulate\":%.6f,\"exchange\":%.6f,\"output\":%.6f,\"total\":%.6f}}",
               q ? "," : "", q, (unsigned long long)s->tile_points,
               (unsigned long long)s->ghost_points, (unsigned long long)s->ghost_seeded,
               s->rebuilds, s->scans, (unsigned long long)s->queries_sent,
               (unsigned long long)s->bytes_sent,
               (unsigned long long)s->bytes_sent_ghost,
               (unsigned long long)s->answer_tests, s->answer_lifts,
               (unsigned long long)s->answers_near,
               (unsigned long long)(r->tet_offsets[q + 1] - r->tet_offsets[q]),
               s->seconds_validate, s->seconds_partition, s->seconds_triangulate,
               s->seconds_exchange, s->seconds_output, s->seconds_total);
    }
    printf("]}\n");
    free(all);
}

/* A rank allocates and frees arrays of tens to hundreds of MB in turn (the local mesh, the
 * patched copy, the result); glibc serves each from a fresh mmap whose every page faults on
 * first touch (the output step's and the patch's largest cost).  From the heap, with freed
 * memory kept, later arrays reuse pages already mapped (1M points, np 2: 210k -> 127k page
 * faults a rank, the output step 2x faster); the peak resident size stays the same (515 MB a
 * rank either way).  The single-process tool keeps glibc's defaults: there one mesh is built
 * once and the kernel hands memory back on purpose (NOTES.md E14). */
static void keep_freed_memory(void)
{
#if defined(__GLIBC__)
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

int main(int argc, char **argv)
{
    keep_freed_memory();
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    io_out_catch_signals();  /* after MPI_Init: a rank killed while writing leaves no temporary */
    char msg[1024] = "";
    args a;
    int code = parse(argc, argv, &a, msg, sizeof msg);   /* the same on every rank */
    if (code) {
        if (code > 0 && msg[0]) say("%s (run gigatet-mpi --help)", msg);
        MPI_Finalize();
        return code < 0 ? 0 : code;
    }
    const char *fi = getenv("GTET_MPI_FAIL_ALLOC");
    if (fi) {
        int r = -1;
        long k = -1;
        if (sscanf(fi, "%d:%ld", &r, &k) == 2 && r == g_rank) gtet_mpi_debug_fail_alloc(k);
    }
    double t0 = mx_now();
    /* the destination first, so a long run does not end in an unwritable file */
    if (a.output && g_rank == 0) {
        io_error e;
        const char *probe = a.output;
        char *tmpname = NULL;
        if (ends_with(a.output, ".pvtu")) {
            tmpname = piece_path(a.output, 0);
            probe = tmpname;
        }
        io_status s = probe ? io_check_writable(probe, &e) : IO_ERR_NOMEM;
        if (s != IO_OK) {
            snprintf(msg, sizeof msg, "%s", probe ? e.message : "out of memory");
            code = exit_of_io(s);
        }
        free(tmpname);
    }
    if ((code = agree(code, msg, sizeof msg)) != 0) {
        say("%s", msg);
        MPI_Finalize();
        return code;
    }
    double *xyz = NULL;
    size_t n = 0;
    uint64_t first = 0;
    code = ends_with(a.input, ".bin") ? read_bin(a.input, &xyz, &n, &first, msg, sizeof msg)
                                      : read_root(a.input, &xyz, &n, &first, msg, sizeof msg);
    code = agree(code, msg, sizeof msg);
    if (code) {
        say("%s", msg);
        free(xyz);
        MPI_Finalize();
        return code;
    }
    double t_read = mx_now() - t0;
    gtet_options opt;
    gtet_options_init(&opt);
    gtet_error err;
    memset(&err, 0, sizeof err);
    opt.threads = (int)a.threads;
    opt.check = a.check;
    opt.error = &err;
    /* the points read are freed as soon as the library has copied them (after its duplicate
     * step): 24 B a point the later steps reuse instead of fresh memory (NOTES.md E122) */
    opt.input_done = mx_free_input;
    opt.input_done_user = &xyz;
    gtet_mpi_result res;
    double t1 = mx_now();
    /* 32-bit ids, as gigatet triangulate's: the rows translated where they lie, no 64-bit
     * copy (a mesh whose counts do not fit comes back with 64-bit ids; the writers and the
     * checks take either) */
    gtet_mpi_options mo;
    gtet_mpi_options_init(&mo);
    mo.id_bits = 32;
    gtet_status s = gtet_triangulate_mpi_opt(MPI_COMM_WORLD, xyz, n, first, &opt, &mo, &res);
    double secs = mx_now() - t1;
    free(xyz);
    if (s != GTET_OK) {
        code = exit_of(s);
        if (s == GTET_ERR_NONFINITE)
            say("%s: %s", a.input, err.message);
        else
            say("%s", err.message);
        MPI_Finalize();
        return code;
    }
    if (a.output) {
        if (ends_with(a.output, ".pvtu")) {
            code = write_pvtu(a.output, &res, msg, sizeof msg);
        } else {
            double *v = NULL;
            uint32_t *t = NULL;
            code = gather_mesh(&res, &v, &t, msg, sizeof msg);
            if (!code && g_rank == 0) {
                if (a.check) {
                    /* the whole mesh is here: run the exact checker on it too */
                    gtet_check_report rep;
                    gtet_status cs = gtet_check_arrays(v, (size_t)res.num_vertices, t,
                                                       (size_t)res.num_tets_global, NULL, NULL, 0,
                                                       0, &rep);
                    if (cs != GTET_OK) {
                        snprintf(msg, sizeof msg, "check of the gathered mesh failed: %s",
                                 rep.message);
                        code = cs == GTET_ERR_OUT_OF_MEMORY ? XC_NOMEM : XC_CHECK;
                    }
                }
                if (!code) {
                    io_error e;
                    io_status ws = io_write_mesh(a.output, v, (size_t)res.num_vertices, t,
                                                 (size_t)res.num_tets_global, &e);
                    if (ws != IO_OK) {
                        snprintf(msg, sizeof msg, "%s", e.message);
                        code = exit_of_io(ws);
                    }
                }
            }
            free(v);
            free(t);
            code = agree(code, msg, sizeof msg);
        }
        if (code) {
            say("%s", msg);
            gtet_mpi_result_free(&res);
            MPI_Finalize();
            return code;
        }
    }
    if (a.stats) {
        print_stats(&a, &res, t_read);
    } else if (!a.quiet && g_rank == 0) {
        printf("points=%llu duplicates=%llu tets=%llu seconds=%.3f tets/s=%.0f ranks=%d "
               "rounds=%d%s\n",
               (unsigned long long)res.num_points_global, (unsigned long long)res.num_duplicates,
               (unsigned long long)res.num_tets_global, secs,
               secs > 0 ? (double)res.num_tets_global / secs : 0.0, g_size, res.stats.rounds,
               a.check ? " check=ok" : "");
    }
    gtet_mpi_result_free(&res);
    MPI_Finalize();
    return 0;
}
