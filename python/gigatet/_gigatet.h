/* _gigatet.h -- what the binding's two files share (python/gigatet/_gigatet.c: the module, the
 * Mesh type, triangulation, the checker, pickling; _gigatet_arrays.c: Mesh's array accessors in
 * input numbering and its point location).  Included after Python.h and numpy/arrayobject.h;
 * the numpy API table is gigatet_ARRAY_API, imported once by the module's init. */
#ifndef GIGATET_PY_GIGATET_H
#define GIGATET_PY_GIGATET_H
#include <stdint.h>

#include "gigatet.h"

typedef struct {
    PyObject_HEAD
    gtet_mesh *mesh;
    PyArrayObject *points;  /* (n, 3) float64, C-contiguous: what was triangulated */
    npy_intp n, nv, nt;
    npy_intp *first;        /* vertex id -> input index of its first occurrence; NULL when
                               there are no duplicates (then the identity) */
    double seconds;         /* wall time of gtet_triangulate */
    int threads_asked;
    int threads;            /* threads the kernel used: the array conversions use as many */
    PyObject *saved_stats;  /* a restored (unpickled) mesh: stats() of the mesh pickled, which
                               gtet_mesh_from_arrays cannot give back; NULL after a run */
} MeshObject;

/* _gigatet_arrays.c: Mesh's methods over its arrays (see _gigatet.c's header for each) */
PyObject *mesh_views(MeshObject *m, PyObject *noargs);
PyObject *mesh_simplices(MeshObject *m, PyObject *noargs);
PyObject *mesh_neighbors(MeshObject *m, PyObject *noargs);
PyObject *mesh_vertex_to_simplex(MeshObject *m, PyObject *noargs);
PyObject *mesh_convex_hull(MeshObject *m, PyObject *noargs);
PyObject *mesh_vertex_neighbor_vertices(MeshObject *m, PyObject *noargs);
PyObject *mesh_vertex_input_index(MeshObject *m, PyObject *noargs);
PyObject *mesh_input_map(MeshObject *m, PyObject *noargs);
PyObject *mesh_find_simplex(MeshObject *m, PyObject *arg);

#endif
