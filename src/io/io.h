/* io.h -- file formats and point generators of gigatet (prefix io_), used by the CLI, the
 * tests and the fuzzers.  Not part of the public API (gigatet.h).
 *
 * The formats, their extensions and what each can do are listed once, in io_formats below;
 * this comment says what each reader accepts and what each writer writes.
 *
 * Readers (by extension, case-insensitive):
 *   .xyz   text, "x y z" per line; '#' starts a comment; blank lines are ignored.
 *   .node  TetGen: header "n [dim [attrs [markers]]]" (dim must be 3), then
 *          "id x y z [attrs...] [marker]"; ids consecutive from 0 or from 1; '#' comments.
 *   .ply   "ascii 1.0", "binary_little_endian 1.0" or "binary_big_endian 1.0"; a "vertex"
 *          element with scalar properties x, y, z among any others (lists included); other
 *          elements may come before or after it; faces are ignored.
 *   .bin   little-endian uint64 count, then count*3 little-endian doubles, nothing after.
 * Numbers are parsed with strtod in the "C" locale (correctly rounded; hex floats accepted).
 * Every malformed input is rejected with a message naming the file and the line (text) or
 * the point / vertex index and byte offset (binary): a token that is not a number or has
 * trailing garbage, a wrong number of columns, NaN or Inf (also decimal overflow), an empty
 * file, a header claiming more points than the file holds (checked against the file size
 * before anything is allocated, so a header claiming 2^60 points allocates nothing), extra
 * data after the declared points, a missing file, a directory, an unknown extension, text in
 * UTF-16 or UTF-32 (named from its byte order mark; a UTF-8 one is skipped).
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
 * Mesh readers (for `gigatet check`, which judges meshes written by other tools too):
 *   .ele   TetGen, with the .node beside it: 0- or 1-based (the .node's first id decides,
 *          as after TetGen's -z), attribute and boundary-marker columns in the .node and
 *          region-attribute columns in the .ele read and dropped, 4 or 10 nodes per tet (the
 *          first 4, the corners, are kept; the trailing run of .node entries that are only
 *          mid-edge nodes, where TetGen's -o2 puts them, is dropped, read_ele.c).
 *   .msh   Gmsh MSH 4.1 and 2.2 (2.0, 2.1 alike), ASCII or binary (little-endian; 4.1's
 *          size_t fields 4 or 8 bytes as its $MeshFormat says).  $MeshFormat, $Nodes and
 *          $Elements are read, $Entities and every other section skipped.  Node tags may be
 *          sparse and unordered; parametric nodes' extra coordinates are dropped.  Elements
 *          other than 4-node tetrahedra (type 4; 10-node ones, type 11, included) are
 *          skipped and counted; in a binary block that needs the type's node count, and a
 *          type without a known one is an error.
 *   .vtu   VTK XML UnstructuredGrid, one Piece: DataArrays format="ascii", "binary" (inline
 *          base64) or "appended" (<AppendedData encoding="raw" or "base64">), header_type
 *          UInt32 or UInt64, uncompressed or compressor="vtkZLibDataCompressor" (LZ4 and
 *          LZMA are refused by name), byte_order="LittleEndian" (BigEndian is refused).
 *          Points Float32, Float64 or any integer type (each within 2^53); connectivity and
 *          offsets any integer type (offsets as the NumberOfCells cell ends, or
 *          NumberOfCells+1 starts beginning with 0); types any integer type.  Attribute
 *          order inside a tag does not matter.  Cells other than VTK_TETRA (10) are skipped
 *          and counted; VTK_QUADRATIC_TETRA (24) is skipped too.
 *   What every reader returns: distinct vertex arrays as in the file (unused vertices are
 *   kept), tets as 4 vertex indices (range-checked, 0-based, in the file's orientation),
 *   and the count of skipped cells.  Every malformed file fails with IO_ERR_INPUT and a
 *   message naming the file and the line (text) or byte offset (binary); a claimed count is
 *   checked against the bytes present (and zlib's largest expansion ratio) before anything
 *   of its size is allocated.
 *
 * Surface readers (triangle meshes, for the `surface` generator; read_off.c, read_ply.c):
 *   .off   Geomview OFF: the keyword [ST][C][N]OFF (texture, colour and normal columns after
 *          x y z are read and dropped; 4OFF, nOFF and BINARY are refused by name), alone on
 *          its line or followed by the counts; "nv nf [ne]"; nv vertex lines, nf face lines
 *          "k i1 .. ik [colour]".  '#' comments.  Also a point format (its vertices).
 *   .ply   the point reader's header and vertices, and an element "face" with a list property
 *          "vertex_indices" (or "vertex_index"); other face properties are skipped.
 *   Polygons of k > 3 corners are fanned from their first corner into k - 2 triangles (the
 *   polygon itself when it is convex); faces of fewer than 3 corners and indices out of range
 *   are errors.  Vertices unused by any face are kept.
 *
 * Generators: io_generate(kind, n, seed) with the kinds listed by io_generator_kinds();
 * reproducible (splitmix64 seeded by `seed`), no global state.  The kind "surface" needs a
 * mesh: io_sample_surface.
 *
 * No function prints or exits; all report through io_status and io_error.
 */
#ifndef GTET_IO_H
#define GTET_IO_H

#include <stddef.h>
#include <stdint.h>

/* Kinds of failure.  The CLI maps them to its exit codes (cli_exit_of_io in src/cli/main.c:
 * IO_ERR_ARGUMENT -> 1 usage, IO_ERR_INPUT and IO_ERR_WRITE -> 2, IO_ERR_NOMEM -> 4). */
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
    IO_FMT_ELE, IO_FMT_MSH, IO_FMT_VTU,                /* meshes */
    IO_FMT_OFF                                         /* surface meshes (and their vertices) */
} io_format;
#define IO_FMT_COUNT 8

/* What a format's reader and writer handle (io_format_info.can). */
enum {
    IO_READ_POINTS = 1u,
    IO_WRITE_POINTS = 2u,
    IO_READ_MESH = 4u,
    IO_WRITE_MESH = 8u,
    IO_READ_SURFACE = 16u   /* triangles: io_read_surface */
};

/* The one list of file formats: every extension check, error message and help text is drawn
 * from it.  io_formats[k].fmt == k + 1. */
typedef struct io_format_info {
    io_format fmt;
    const char *ext;          /* ".xyz": lower case, matched case-insensitively */
    unsigned can;             /* IO_READ_POINTS | IO_WRITE_POINTS | IO_READ_MESH | IO_WRITE_MESH */
    const char *companion;    /* the file read and written beside it (".node" for .ele), or NULL */
    const char *description;  /* one line for --help */
} io_format_info;
extern const io_format_info io_formats[IO_FMT_COUNT];

/* The format a file name's extension names, or IO_FMT_UNKNOWN. */
io_format io_format_of(const char *path);
/* 1 when fmt has every capability of `can`, 0 otherwise (IO_FMT_UNKNOWN has none). */
int io_format_can(io_format fmt, unsigned can);
/* The extensions of the formats with every capability of `can`, as ".a, .b or .c" (with
 * `companions`: ".ele (with its .node)"), NUL-terminated in buf (cut to size); returns buf. */
const char *io_format_list(unsigned can, int companions, char *buf, size_t size);

/* ---- point sets -------------------------------------------------------------------------- */

/* Read the points of a file, by extension.  On success *xyz (3*n doubles, malloc'ed; the
 * caller frees it) and *n >= 1.  On failure *xyz is NULL, *n is 0, err (if not NULL) says why. */
io_status io_read_points(const char *path, double **xyz, size_t *n, io_error *err);

/* The same parsers on bytes in memory (any bytes: this is the fuzzers' entry point); `name`
 * is only used in messages.  fmt must be a point format. */
io_status io_parse_points(io_format fmt, const char *name, const void *data, size_t len,
                          double **xyz, size_t *n, io_error *err);

/* Write n points to path (a format with IO_WRITE_POINTS), atomically. */
io_status io_write_points(const char *path, const double *xyz, size_t n, io_error *err);

/* ---- meshes ------------------------------------------------------------------------------ */

typedef struct io_mesh {
    double *vertices;   /* 3*nv */
    size_t nv;
    uint32_t *tets;     /* 4*nt vertex ids, 0-based */
    size_t nt;
    size_t skipped_cells;   /* cells that are not linear tetrahedra (.msh, .vtu), not read */
} io_mesh;

/* Remove every temporary the writers have open now (each output is written to a temporary
 * beside it and renamed into place when complete): for a program's handler of a fatal signal
 * (Ctrl-C while a mesh is written), which then re-raises it.  Async-signal-safe: it only
 * reads a fixed table of atomic pointers and calls unlink (NOTES.md E156). */
void io_out_unlink_all(void);

/* Install a handler of SIGINT, SIGTERM and SIGHUP (each not ignored at the call) that calls
 * io_out_unlink_all and re-raises the signal with its default action: Ctrl-C, a kill or a
 * closed terminal while a mesh is written leaves no temporary, and the process still dies of
 * the signal.  For a program's main (gigatet, gigatet-mpi after MPI_Init); NOTES.md E156. */
void io_out_catch_signals(void);

/* Write a tet mesh (a format with IO_WRITE_MESH), atomically (for .ele both files or neither). */
io_status io_write_mesh(const char *path, const double *vertices, size_t nv,
                        const uint32_t *tets, size_t nt, io_error *err);

/* Read a tet mesh (a format with IO_READ_MESH; see the top of this file).  Vertex ids
 * are range-checked.  On failure *mesh is zeroed. */
io_status io_read_mesh(const char *path, io_mesh *mesh, io_error *err);
/* The same readers on bytes in memory (any bytes: the fuzzers' entry point); `name` is only
 * used in messages.  node_data / node_len are the .node file's bytes for IO_FMT_ELE and are
 * ignored for the other formats. */
io_status io_parse_mesh(io_format fmt, const char *name, const void *data, size_t len,
                        const void *node_data, size_t node_len, io_mesh *mesh, io_error *err);
void io_mesh_free(io_mesh *mesh);

/* Fail early (IO_ERR_WRITE) when path cannot be created or names a directory: creates and
 * removes the temporary file a writer would use, so a long run does not end in an unwritable
 * destination. */
io_status io_check_writable(const char *path, io_error *err);

/* For .ele: the .node path written / read beside it (malloc'ed), else NULL; .NODE beside an
 * upper-case .ELE. */
char *io_ele_node_path(const char *path);

/* ---- surface meshes (triangles) ---------------------------------------------------------- */

typedef struct io_surface {
    double *vertices;   /* 3*nv */
    size_t nv;
    uint32_t *tris;     /* 3*nt vertex ids, 0-based, range-checked */
    size_t nt;          /* >= 1 */
} io_surface;

/* Read a triangle mesh (a format with IO_READ_SURFACE).  On failure *s is zeroed. */
io_status io_read_surface(const char *path, io_surface *s, io_error *err);
/* The same readers on bytes in memory (any bytes: the fuzzers' entry point). */
io_status io_parse_surface(io_format fmt, const char *name, const void *data, size_t len,
                           io_surface *s, io_error *err);
void io_surface_free(io_surface *s);

/* n points uniform by area on the triangles of s (a triangle with probability proportional
 * to its area, then uniform in it); the same (s, n, seed) gives the same bits everywhere.
 * `name` is only used in messages.  Fails (IO_ERR_INPUT) when every triangle has zero area
 * or the total area is not finite. */
io_status io_sample_surface(const io_surface *s, const char *name, size_t n, uint64_t seed,
                            double **xyz, io_error *err);

/* ---- generators -------------------------------------------------------------------------- */

/* NULL-terminated list of generator kinds, and a one-line description of each. */
const char *const *io_generator_kinds(void);
const char *io_generator_help(const char *kind);

/* Generate about n points of the given kind (exactly n for the random kinds; the lattices
 * round n to their natural sizes).  Same (kind, n, seed) -> same bits on every machine. */
io_status io_generate(const char *kind, size_t n, uint64_t seed, double **xyz, size_t *n_out,
                      io_error *err);

#endif
