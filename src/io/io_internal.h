/* io_internal.h -- helpers shared by the files of src/io (not for users of io.h).
 *
 * Text parsing works on a buffer that holds len bytes followed by a NUL (so strtod can
 * never run past the end); lines are cut at '\n' and at '#', tokens at blanks.  strtod is
 * called only on a token's first byte, which is never a blank, so it cannot skip a newline
 * and read the next line's number; a token is a number only when strtod consumes it whole.
 */
#ifndef GTET_IO_INTERNAL_H
#define GTET_IO_INTERNAL_H

#include <stdarg.h>
#include <stdio.h>

#include "io.h"

/* Fill err (when not NULL) and return status. */
io_status io_fail(io_error *err, io_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Read a whole file into a malloc'ed buffer with a NUL after its len bytes.  Rejects a
 * missing file, a directory, a read error. */
io_status io_load_file(const char *path, char **buf, size_t *len, io_error *err);
/* The same from a file already open (closed here): a named pipe must not be opened twice, its
 * writer's data would go to the first reader (NOTES.md E158). */
io_status io_load_fd(int fd, const char *path, char **buf, size_t *len, io_error *err);

/* ---- text lines and tokens --------------------------------------------------------------- */
typedef struct io_text {
    const char *name;        /* file name for messages */
    const char *p, *end;     /* unread bytes; *end == '\0' */
    size_t line;             /* number of the current line (1-based) */
    const char *lp, *le;     /* the current line without its comment and newline */
} io_text;

void io_text_init(io_text *t, const char *name, const char *buf, size_t len);
/* 3 when buf starts with a UTF-8 byte order mark (EF BB BF, which Windows editors write at the
 * start of a text file), else 0: the text readers start after it (NOTES.md E152). */
size_t io_bom_length(const char *buf, size_t len);
/* IO_OK, or IO_ERR_INPUT naming the encoding when buf starts with a UTF-16 or UTF-32 byte
 * order mark (Windows PowerShell's `>` writes UTF-16): no reader takes such text, and the
 * message says so rather than quoting its first token as '??0?'. */
io_status io_text_encoding(const char *name, const char *buf, size_t len, io_error *err);
/* Advance to the next line that has a token; 0 at the end of the data. */
int io_text_next_line(io_text *t);
/* Next token of the current line: 1 and [*ts, *te), or 0 at the end of the line. */
int io_text_token(io_text *t, const char **ts, const char **te);
/* Count the tokens of the current line. */
size_t io_text_count_tokens(const io_text *t);
/* Parse [ts, te) as a finite double; on failure fill err naming name:line and `what`. */
io_status io_text_double(const io_text *t, const char *ts, const char *te, const char *what,
                         double *v, io_error *err);
/* Parse [ts, te) as a decimal integer in [0, max]. */
io_status io_text_uint(const io_text *t, const char *ts, const char *te, const char *what,
                       uint64_t max, uint64_t *v, io_error *err);

/* ---- growing array of doubles ------------------------------------------------------------ */
typedef struct io_dvec { double *a; size_t n, cap; } io_dvec;
io_status io_dvec_push3(io_dvec *v, const double x[3], const char *name, io_error *err);

/* ---- parsers on a NUL-terminated buffer (buf[len] == '\0') -------------------------------- */
io_status io_parse_xyz(const char *name, const char *buf, size_t len, double **xyz, size_t *n,
                       io_error *err);
io_status io_parse_node(const char *name, const char *buf, size_t len, double **xyz,
                        size_t *n, long *first_id, io_error *err);
io_status io_parse_ply(const char *name, const char *buf, size_t len, double **xyz, size_t *n,
                       io_error *err);
io_status io_parse_bin(const char *name, const unsigned char *buf, size_t len, double **xyz,
                       size_t *n, io_error *err);

/* ---- mesh parsers (read_ele.c, read_msh.c, read_vtu.c), on NUL-terminated buffers --------
 * On failure they leave the mesh for the caller (io_parse_mesh) to free. */
io_status io_parse_ele(const char *name, const char *buf, size_t len, const char *node_name,
                       const char *nbuf, size_t nlen, io_mesh *m, io_error *err);
io_status io_parse_msh(const char *name, const char *buf, size_t len, io_mesh *m,
                       io_error *err);
io_status io_parse_vtu(const char *name, const char *buf, size_t len, io_mesh *m,
                       io_error *err);

/* ---- surface parsers (read_off.c, read_ply.c), on NUL-terminated buffers ----------------
 * On failure they leave the surface for the caller (io_parse_surface) to free. */
typedef struct io_tvec { uint32_t *a; size_t n, cap; } io_tvec;   /* n ids, n % 3 == 0 */
/* Append the triangle (a, b, c). */
io_status io_tvec_push3(io_tvec *v, uint32_t a, uint32_t b, uint32_t c, const char *name,
                        io_error *err);
io_status io_parse_off(const char *name, const char *buf, size_t len, io_surface *s,
                       io_error *err);
io_status io_parse_ply_surface(const char *name, const char *buf, size_t len, io_surface *s,
                               io_error *err);

/* The generators' random numbers (generate.c): splitmix64, the next 64 bits of state *s. */
uint64_t io_splitmix64(uint64_t *s);

/* ---- binary helpers (decode.c) ------------------------------------------------------------ */
/* Little-endian loads of 1, 2, 4 or 8 bytes, whatever the host's byte order. */
uint64_t io_load_le(const unsigned char *p, size_t width);
/* The 1-based line of position p in buf (for messages; linear in p - buf). */
size_t io_line_of(const char *buf, const char *p);

/* Base64 (RFC 4648 alphabet) read as a stream of 4-character groups, whitespace ignored.  A
 * group may end in '=' padding anywhere in the stream, not only at its end: VTK and meshio
 * encode an array's header and its data either as one stream or as two padded ones, and
 * decoding group by group gives the same bytes for both.  A last group of 2 or 3 characters
 * without padding is accepted (1 or 2 bytes). */
typedef struct io_b64 {
    const char *p, *e;          /* undecoded characters */
    unsigned char q[3];         /* decoded bytes of the current group not yet handed out */
    unsigned nq, qi;
    int bad;                    /* set when a character outside the alphabet was met */
} io_b64;
void io_b64_init(io_b64 *s, const char *p, const char *e);
/* Decode exactly n bytes into dst (dst may be NULL to skip them); 0 when the characters end
 * first or one is not base64 (then s->bad is set). */
int io_b64_read(io_b64 *s, unsigned char *dst, size_t n);
/* An upper bound on the bytes the remaining characters can decode to. */
size_t io_b64_bound(const io_b64 *s);

/* Inflate one zlib stream of slen bytes into exactly dlen bytes: 1 on success, 0 when the
 * stream is corrupt or decodes to another length.  zlib's deflate never expands data more
 * than IO_ZLIB_MAX_RATIO times, which bounds what a header may claim before allocating. */
#define IO_ZLIB_MAX_RATIO 1032u
int io_inflate(const unsigned char *src, size_t slen, unsigned char *dst, size_t dlen);

/* Read a .bin file straight into the point array (regular files; others via io_parse_bin). */
io_status io_read_bin_file(const char *path, double **xyz, size_t *n, io_error *err);

/* ---- atomic output ----------------------------------------------------------------------- */
typedef struct io_out {
    FILE *f;
    char *tmp;          /* temporary path, removed unless committed */
    const char *path;   /* final path */
} io_out;

/* Create the temporary file for path. */
io_status io_out_open(io_out *o, const char *path, io_error *err);
/* Flush and close the temporary; on any write error remove it and fail. */
io_status io_out_close(io_out *o, io_error *err);
/* Rename the closed temporary onto the final path. */
io_status io_out_commit(io_out *o, io_error *err);
/* Close (if open) and remove the temporary; safe to call after a failed step. */
void io_out_abort(io_out *o);

/* Format helpers for fast text output: write v in decimal at p, return the end. */
char *io_fmt_u64(char *p, uint64_t v);

#endif
