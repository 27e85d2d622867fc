/* mpi_patch.h -- what the later rounds' patch (mpi_patch.c) shares with its cavity search
 * (mpi_cavity.c); private to those two files. */
#ifndef GTET_MPI_PATCH_H
#define GTET_MPI_PATCH_H

#include "mpi/mpi_internal.h"

#define NONE UINT32_MAX

/* one patch: DT(S) (the local mesh), the cavity's marks, W and its triangulation */
typedef struct patch {
    run *R;
    size_t n_old, nt;
    const uint32_t *tv, *nb;
    uint8_t *cf;        /* per tet: bit 4 in conflict, bit f: hull facet f in conflict */
    uint32_t *wid;      /* per S vertex: its index in W, or NONE */
    uint32_t *ws;       /* per W vertex: its S index */
    size_t nw;
    gtet_mesh *wm;
} patch;

/* mark C and H in X->cf: the tets and the hull facets some new point conflicts with (exact
 * predicates), by locating the new points (D10) or, should that fail, by testing every tet;
 * 0, -1 out of memory, or 1 when the growth would make more than 2 exact tests per
 * point of S (then the caller triangulates from scratch) */
int mx_find_cavity(patch *X);

#endif
