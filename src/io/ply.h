/* ply.h -- the PLY header, shared by the PLY readers (internal to src/io).
 *
 * ply_header.c parses a header up to "end_header": the elements with their counts and
 * properties (scalars of the eight PLY types under both their names, or lists), the vertex
 * element with its x, y, z, and a "face" element's vertex_indices list when there is one.
 * read_ply.c reads the data after it: the vertices (io_parse_ply) or the faces of a surface
 * (io_parse_ply_surface). */
#ifndef GTET_IO_PLY_H
#define GTET_IO_PLY_H

#include <stddef.h>
#include <stdint.h>

#include "io_internal.h"

enum { PLY_MAX_ELEMENTS = 32, PLY_MAX_PROPS = 256 };

typedef struct ply_prop {
    int type;       /* scalar type, or the item type of a list */
    int count_type; /* list: type of the count; -1 for a scalar */
    int coord;      /* 0, 1, 2 for x, y, z; -1 otherwise */
} ply_prop;

typedef struct ply_element {
    char name[32];
    uint64_t count;
    int nprops;
    ply_prop props[PLY_MAX_PROPS];
} ply_element;

typedef struct ply_header {
    int binary;             /* 0 ascii, 1 binary_little_endian, 2 binary_big_endian */
    int nel, vertex;        /* element count, index of the vertex element */
    int face, face_prop;    /* the "face" element and its vertex_indices list, or -1 */
    size_t data;            /* offset of the first data byte */
    size_t lines;           /* header lines */
    ply_element el[PLY_MAX_ELEMENTS];
} ply_header;

/* Bytes of a PLY scalar type (a type index of ply_header.c's table: 1, 2, 4 or 8). */
int ply_type_size(int ty);

/* Whether a PLY scalar type is a floating-point one (float, double). */
int ply_type_float(int ty);

/* Value of a binary scalar of type ty at p, little-endian or (big != 0) big-endian, as a
 * double (exact for every type: the integers have at most 32 bits, floats widen exactly). */
double ply_bin_value(int ty, const unsigned char *p, int big);

/* Parse the header at the start of buf[0, len) into *h: h->data is the offset of the first
 * data byte.  Fails with a message naming the file and line on anything it does not
 * understand, and when there is no vertex element with x, y, z or it declares 0 vertices. */
io_status ply_parse_header(const char *name, const char *buf, size_t len, ply_header *h,
                           io_error *err);

#endif
