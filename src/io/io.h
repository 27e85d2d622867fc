/* io.h -- file formats and point generators of gigatet (prefix io_), used by the CLI, the
 * tests and the fuzzers.  Not part of the public API (gigatet.h).
 *
 * Readers (by extension, case-insensitive):
 *   .xyz   text, "x y z" per line; '#' starts a comment; blank lines are ignored.
 *   .node  TetGen: header "n [dim [attrs [markers]]]" (dim must be 3), then
 *          "id x y z [attrs...] [marker]"; ids consecutive from 0 or from 1; '#' comments.
 *   .ply   "ascii 1.0" or "binary_little_endian 1.0"; a "vertex" element with scalar
 *          properties x, y, z among any others (lists included); other elements may come
 *          before or after it; faces are ignored.
 *   .bin   little-endian uint64 count, then count*3 little-endian doubles, nothing after.
 * Numbers are parsed with strtod in the "C" locale (correctly rounded; hex floats accepted).
 * Every malformed input is rejected with a message naming the file and the line (text) or
 * the point / vertex index and byte offset (binary): a token that is not a number or has
 * trailing garbage, a wrong number of columns, NaN or Inf (also decimal overflow), an empty
 * file, a header claiming more points than the file holds (checked against the file size
 * before anything is allocated, so a header claiming 2^60 points allocates nothing), extra
 * data after the declared points, a missing file, a directory, an unknown extension.
 *
 * Writers are atomic: the data goes to a temporary file created next to the destination
 * (O_EXCL, so the umask applies as for any new file) and is renamed over it only after
 * every byte was written and the file closed without error; on any failure the temporary is
 * removed.  A failed run therefore leaves no partial output.  Coordinates are printed with
 * %.17g, which reads back bit-exact with any correctly rounded strtod.
 *   points: .xyz, .node (1-based), .ply (binary_little_endian, double x y z), .bin
 *   meshes: .ele (TetGen: NAME.node + NAME.ele, 1-based like TetGen's own output; TetGen
 *           and meshio read 0- and 1-based files alike), .msh (Gmsh 4.1 ASCII, one volume
 *           entity, tetrahedra of type 4), .vtu (VTK XML UnstructuredGrid, ASCII, cell type 10).
 *   Tets are written in the order of their vertices as given (gigatet's tets are positively
 *   oriented, which is the orientation TetGen, Gmsh and VTK use).
 *
 * Mesh reader (for `gigatet check`): .ele (+ the .node beside it), .msh (Gmsh 4.1 ASCII;
 * elements other than tetrahedra are skipped), .vtu (ASCII DataArrays, tetrahedra only).
 *
 * Generators: io_generate(kind, n, seed) with the kinds listed by io_generator_kinds();
 * reproducible (splitmix64 seeded by `seed`), no global state.
 *
 * No function prints or exits; all report through io_status and io_error.
 */
#ifndef GTET_IO_H
#define GTET_IO_H

#include <stddef.h>
#include <stdint.h>

/* The values are the CLI's exit codes for the kinds of failure (see src/cli/main.c). */
typedef enum io_status {
    IO_OK = 0,
    IO_ERR_ARGUMENT = 1,  /* unknown extension / generator kind, bad parameter */
    IO_ERR_INPUT = 2,     /* missing, unreadable or malformed input file */
    IO_ERR_NOMEM = 4,     /* an allocation failed */
    IO_ERR_WRITE = 6      /* the output could not be created or written */
} io_status;

typedef struct io_error {
    io_status status;
    char message[1024];   /* "FILE:LINE: what is wrong", NUL-terminated */
} io_error;

typedef enum io_format {
    IO_FMT_UNKNOWN = 0,
    IO_FMT_XYZ, IO_FMT_NODE, IO_FMT_PLY, IO_FMT_BIN,   /* point sets */
    IO_FMT_ELE, IO_FMT_MSH, IO_FMT_VTU                 /* meshes */
} io_format;

/* The format a file name's extension names, or IO_FMT_UNKNOWN. */
io_format io_format_of(const char *path);

/* ---- point sets -------------------------------------------------------------------------- */

/* Read the points of a file, by extension.  On success *xyz (3*n doubles, malloc'ed; the
 * caller frees it) and *n >= 1.  On failure *xyz is NULL, *n is 0, err (if not NULL) says why. */
io_status io_read_points(const char *path, double **xyz, size_t *n, io_error *err);

/* The same parsers on bytes in memory (any bytes: this is the fuzzers' entry point); `name`
 * is only used in messages.  fmt must be a point format. */
io_status io_parse_points(io_format fmt, const char *name, const void *data, size_t len,
                          double **xyz, size_t *n, io_error *err);

/* Write n points to path (.xyz, .node, .ply, .bin), atomically. */
io_status io_write_points(const char *path, const double *xyz, size_t n, io_error *err);

/* ---- meshes ------------------------------------------------------------------------------ */

typedef struct io_mesh {
    double *vertices;   /* 3*nv */
    size_t nv;
    uint32_t *tets;     /* 4*nt vertex ids, 0-based */
    size_t nt;
} io_mesh;

/* Write a tet mesh (.ele, .msh, .vtu), atomically (for .ele both files or neither). */
io_status io_write_mesh(const char *path, const double *vertices, size_t nv,
                        const uint32_t *tets, size_t nt, io_error *err);

/* Read a tet mesh (.ele with its .node, .msh, .vtu).  Vertex ids are range-checked. */
io_status io_read_mesh(const char *path, io_mesh *mesh, io_error *err);
void io_mesh_free(io_mesh *mesh);

/* Fail early (IO_ERR_WRITE) when path cannot be created: creates and removes the temporary
 * file a writer would use, so a long run does not end in an unwritable destination. */
io_status io_check_writable(const char *path, io_error *err);

/* For .ele: the .node path written / read beside it (malloc'ed), else NULL. */
char *io_ele_node_path(const char *path);

/* ---- generators -------------------------------------------------------------------------- */

/* NULL-terminated list of generator kinds, and a one-line description of each. */
const char *const *io_generator_kinds(void);
const char *io_generator_help(const char *kind);

/* Generate about n points of the given kind (exactly n for the random kinds; the lattices
 * round n to their natural sizes).  Same (kind, n, seed) -> same bits on every machine. */
io_status io_generate(const char *kind, size_t n, uint64_t seed, double **xyz, size_t *n_out,
                      io_error *err);

#endif
