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

/* ---- text lines and tokens --------------------------------------------------------------- */
typedef struct io_text {
    const char *name;        /* file name for messages */
    const char *p, *end;     /* unread bytes; *end == '\0' */
    size_t line;             /* number of the current line (1-based) */
    const char *lp, *le;     /* the current line without its comment and newline */
} io_text;

void io_text_init(io_text *t, const char *name, const char *buf, size_t len);
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
