/* _gigatet_arrays.c -- Mesh's array accessors and point location (module gigatet._gigatet;
 * _gigatet.c's header says what each method returns).  The arrays are new intp arrays in
 * input-point numbering, filled in parallel on the threads the kernel ran with (m->threads: a
 * count the process could start), except views(), which are read-only arrays over the mesh's
 * own memory. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define PY_ARRAY_UNIQUE_SYMBOL gigatet_ARRAY_API
#define NO_IMPORT_ARRAY
#include <numpy/arrayobject.h>

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "_gigatet.h"

/* ---------------------------------------------------------------------------------------- */
/* Arrays                                                                                   */
/* ---------------------------------------------------------------------------------------- */

/* A read-only array over the mesh's memory; it holds a reference to the Mesh. */
static PyObject *view(MeshObject *m, const void *data, int nd, npy_intp *dims, int type)
{
    PyObject *a = PyArray_New(&PyArray_Type, nd, dims, type, NULL, (void *)(uintptr_t)data, 0,
                              NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED, NULL);
    if (!a) return NULL;
    Py_INCREF(m);
    if (PyArray_SetBaseObject((PyArrayObject *)a, (PyObject *)m) < 0) {
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

PyObject *mesh_views(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp dv[2] = {m->nv, 3}, dt[2] = {m->nt, 4}, dn[1] = {m->n};
    PyObject *v = view(m, gtet_mesh_vertices(m->mesh), 2, dv, NPY_DOUBLE);
    PyObject *t = view(m, gtet_mesh_tets(m->mesh), 2, dt, NPY_UINT32);
    PyObject *nb = view(m, gtet_mesh_neighbors(m->mesh), 2, dt, NPY_UINT32);
    PyObject *map = view(m, gtet_mesh_input_map(m->mesh), 1, dn, NPY_UINT32);
    if (!v || !t || !nb || !map) {
        Py_XDECREF(v);
        Py_XDECREF(t);
        Py_XDECREF(nb);
        Py_XDECREF(map);
        return NULL;
    }
    return Py_BuildValue("(NNNN)", v, t, nb, map);
}

static inline npy_intp input_id(const MeshObject *m, uint32_t v)
{
    return m->first ? m->first[v] : (npy_intp)v;
}

static PyObject *new_intp(int nd, npy_intp *dims)
{
    return PyArray_SimpleNew(nd, dims, NPY_INTP);
}

/* (nt, 4): the tets' vertices as input-point indices. */
PyObject *mesh_simplices(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[2] = {m->nt, 4};
    PyObject *a = new_intp(2, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const uint32_t *t = gtet_mesh_tets(m->mesh);
    const size_t n4 = 4 * (size_t)m->nt;
    const int nth = m->threads;
    const npy_intp *first = m->first;
    Py_BEGIN_ALLOW_THREADS
    if (first) {
#pragma omp parallel for num_threads(nth) schedule(static) if (nth > 1 && n4 > 262144)
        for (size_t i = 0; i < n4; i++) out[i] = first[t[i]];
    } else {
#pragma omp parallel for num_threads(nth) schedule(static) if (nth > 1 && n4 > 262144)
        for (size_t i = 0; i < n4; i++) out[i] = (npy_intp)t[i];
    }
    Py_END_ALLOW_THREADS
    return a;
}

/* (nt, 4): neighbours, -1 on the hull. */
PyObject *mesh_neighbors(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[2] = {m->nt, 4};
    PyObject *a = new_intp(2, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const uint32_t *nb = gtet_mesh_neighbors(m->mesh);
    const size_t n4 = 4 * (size_t)m->nt;
    const int nth = m->threads;
    Py_BEGIN_ALLOW_THREADS
#pragma omp parallel for num_threads(nth) schedule(static) if (nth > 1 && n4 > 262144)
    for (size_t i = 0; i < n4; i++) out[i] = nb[i] == GTET_NO_TET ? -1 : (npy_intp)nb[i];
    Py_END_ALLOW_THREADS
    return a;
}

/* (n,): the smallest tet of each input point's vertex; -1 for duplicates (they are not
 * vertices of the triangulation, as scipy's coplanar points). */
PyObject *mesh_vertex_to_simplex(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[1] = {m->n};
    PyObject *a = new_intp(1, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const uint32_t *t = gtet_mesh_tets(m->mesh);
    Py_BEGIN_ALLOW_THREADS
    for (npy_intp i = 0; i < m->n; i++) out[i] = -1;
    for (npy_intp k = m->nt; k-- > 0;)
        for (int j = 0; j < 4; j++) out[input_id(m, t[4 * k + j])] = k;
    Py_END_ALLOW_THREADS
    return a;
}

/* The facet opposite vertex f of a positively oriented tet, ordered so that it is
 * counter-clockwise seen from outside the tet (its normal points away from vertex f). */
static const int FACE[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/* (nh, 3): hull facets, outward (counter-clockwise seen from outside), in tet order. */
PyObject *mesh_convex_hull(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[2] = {(npy_intp)gtet_mesh_num_hull_facets(m->mesh), 3};
    PyObject *a = new_intp(2, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const uint32_t *t = gtet_mesh_tets(m->mesh);
    const uint32_t *nb = gtet_mesh_neighbors(m->mesh);
    npy_intp k = 0;
    Py_BEGIN_ALLOW_THREADS
    for (npy_intp i = 0; i < m->nt; i++)
        for (int f = 0; f < 4; f++)
            if (nb[4 * i + f] == GTET_NO_TET && k < d[0]) {
                for (int j = 0; j < 3; j++) out[3 * k + j] = input_id(m, t[4 * i + FACE[f][j]]);
                k++;
            }
    Py_END_ALLOW_THREADS
    if (k != d[0]) {
        Py_DECREF(a);
        PyErr_SetString(PyExc_RuntimeError, "gigatet: hull facet count mismatch");
        return NULL;
    }
    return a;
}

/* (indptr (n+1,), indices): the neighbours of input point i (as input indices, ascending)
 * are indices[indptr[i]:indptr[i+1]]; duplicates have none.  Through the vertex -> tets
 * incidence, each neighbour taken once with a per-vertex mark. */
PyObject *mesh_vertex_neighbor_vertices(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    const size_t nv = (size_t)m->nv, nt = (size_t)m->nt, n = (size_t)m->n;
    const uint32_t *t = gtet_mesh_tets(m->mesh);
    size_t *start = calloc(nv + 1, sizeof *start);
    size_t *pos = malloc((nv ? nv : 1) * sizeof *pos);
    uint32_t *inc = malloc((nt ? 4 * nt : 1) * sizeof *inc);
    uint32_t *mark = malloc((nv ? nv : 1) * sizeof *mark);
    size_t *deg = calloc(nv + 1, sizeof *deg);
    size_t cap = nt ? 2 * nt : 1;  /* grows if needed; ~14 neighbours a vertex, 6.5 tets */
    uint32_t *nbr = malloc(cap * sizeof *nbr);
    int nomem = !start || !pos || !inc || !mark || !deg || !nbr;
    size_t total = 0;
    Py_BEGIN_ALLOW_THREADS
    if (!nomem) {
        for (size_t i = 0; i < 4 * nt; i++) start[t[i] + 1]++;
        for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
        for (size_t v = 0; v < nv; v++) pos[v] = start[v];
        for (size_t k = 0; k < nt; k++)
            for (int j = 0; j < 4; j++) inc[pos[t[4 * k + j]]++] = (uint32_t)k;
        for (size_t v = 0; v < nv; v++) mark[v] = UINT32_MAX;
        for (size_t v = 0; v < nv && !nomem; v++) {
            const size_t begin = total;
            for (size_t q = start[v]; q < start[v + 1]; q++) {
                const uint32_t *tv = t + 4 * (size_t)inc[q];
                for (int j = 0; j < 4; j++) {
                    const uint32_t u = tv[j];
                    if (u == v || mark[u] == (uint32_t)v) continue;
                    mark[u] = (uint32_t)v;
                    if (total == cap) {
                        uint32_t *grown = realloc(nbr, 2 * cap * sizeof *nbr);
                        if (!grown) {
                            nomem = 1;
                            break;
                        }
                        nbr = grown;
                        cap *= 2;
                    }
                    /* insertion into the sorted list of v's neighbours */
                    size_t w = total++;
                    while (w > begin && nbr[w - 1] > u) {
                        nbr[w] = nbr[w - 1];
                        w--;
                    }
                    nbr[w] = u;
                }
            }
            deg[v] = total - begin;
        }
    }
    Py_END_ALLOW_THREADS
    free(start);
    free(pos);
    free(inc);
    free(mark);
    if (nomem) {
        free(deg);
        free(nbr);
        return PyErr_NoMemory();
    }
    npy_intp dp[1] = {(npy_intp)n + 1}, di[1] = {(npy_intp)total};
    PyObject *indptr = new_intp(1, dp), *indices = new_intp(1, di);
    if (!indptr || !indices) {
        Py_XDECREF(indptr);
        Py_XDECREF(indices);
        free(deg);
        free(nbr);
        return NULL;
    }
    npy_intp *ip = PyArray_DATA((PyArrayObject *)indptr);
    npy_intp *ix = PyArray_DATA((PyArrayObject *)indices);
    const uint32_t *map = gtet_mesh_input_map(m->mesh);
    Py_BEGIN_ALLOW_THREADS
    size_t w = 0;         /* lists are in vertex order, and vertex ids in first-occurrence
                             order: input point i starts vertex map[i]'s list when it is new */
    size_t vdone = 0;
    ip[0] = 0;
    for (size_t i = 0; i < n; i++) {
        if (map[i] == vdone) {
            for (size_t q = 0; q < deg[vdone]; q++) ix[w + q] = input_id(m, nbr[w + q]);
            w += deg[vdone];
            vdone++;
        }
        ip[i + 1] = (npy_intp)w;
    }
    Py_END_ALLOW_THREADS
    free(deg);
    free(nbr);
    return Py_BuildValue("(NN)", indptr, indices);
}

/* (nv,): the input index of each mesh vertex (its first occurrence). */
PyObject *mesh_vertex_input_index(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[1] = {m->nv};
    PyObject *a = new_intp(1, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    for (npy_intp v = 0; v < m->nv; v++) out[v] = m->first ? m->first[v] : v;
    return a;
}

/* (n,): gtet's input map (input point -> mesh vertex id) as intp. */
PyObject *mesh_input_map(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    npy_intp d[1] = {m->n};
    PyObject *a = new_intp(1, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const uint32_t *map = gtet_mesh_input_map(m->mesh);
    for (npy_intp i = 0; i < m->n; i++) out[i] = (npy_intp)map[i];
    return a;
}

/* ---------------------------------------------------------------------------------------- */
/* Point location                                                                           */
/* ---------------------------------------------------------------------------------------- */

typedef struct locator {
    const double *V;
    const uint32_t *T, *N;
    size_t nt;
    uint8_t *mark;      /* per tet, 0 outside the current query's search */
    uint32_t *list;     /* tets marked for the current query */
    size_t cap;
} locator;

/* Sign of the orientation of tet t with q in place of its vertex f: > 0 when q is on the
 * same side of facet f as vertex f. */
static int side(const locator *L, uint32_t t, int f, const double q[3])
{
    const uint32_t *tv = L->T + 4 * (size_t)t;
    const double *p[4];
    for (int j = 0; j < 4; j++) p[j] = L->V + 3 * (size_t)tv[j];
    p[f] = q;
    return gtet_orient3d(p[0], p[1], p[2], p[3]);
}

static int push(locator *L, size_t *len, uint32_t t)
{
    if (*len == L->cap) {
        size_t cap = L->cap ? 2 * L->cap : 64;
        uint32_t *l = realloc(L->list, cap * sizeof *l);
        if (!l) return -1;
        L->list = l;
        L->cap = cap;
    }
    L->list[(*len)++] = t;
    L->mark[t] = 1;
    return 0;
}

/* The tet containing q: the smallest tet index whose closed tet contains q, or -1 outside
 * the hull; -2 when out of memory.  *hint: where the walk starts, and where it ended.
 *
 * The visibility walk crosses the first facet (in facet order) that separates the tet from
 * q; on a Delaunay triangulation it terminates whatever the choice (Edelsbrunner's
 * acyclicity of the in-front relation), and reaching a hull facet that separates means q is
 * outside (the facet's plane supports the hull).  When q lies on the boundary of the tet
 * found, every tet containing it is reached from it across facets through q: the smallest
 * is the answer, so it does not depend on the walk. */
static npy_intp locate(locator *L, const double q[3], uint32_t *hint)
{
    uint32_t t = *hint;
    size_t steps = 0;
    const size_t limit = 4 * L->nt + 64;
    for (;;) {
        int moved = 0;
        for (int f = 0; f < 4; f++)
            if (side(L, t, f, q) < 0) {
                uint32_t u = L->N[4 * (size_t)t + f];
                if (u == GTET_NO_TET) {
                    *hint = t;
                    return -1;
                }
                t = u;
                moved = 1;
                break;
            }
        if (!moved) break;
        if (++steps > limit) {  /* never expected; a scan is still exact */
            for (t = 0; t < L->nt; t++) {
                int in = 1;
                for (int f = 0; f < 4 && in; f++) in = side(L, t, f, q) >= 0;
                if (in) break;
            }
            if (t == L->nt) return -1;
            break;
        }
    }
    *hint = t;
    int zero = 0;
    for (int f = 0; f < 4; f++) zero |= side(L, t, f, q) == 0;
    if (!zero) return (npy_intp)t;
    size_t len = 0, head = 0;
    if (push(L, &len, t) < 0) return -2;
    uint32_t best = t;
    while (head < len) {
        uint32_t s = L->list[head++];
        if (s < best) best = s;
        for (int f = 0; f < 4; f++) {
            uint32_t u = L->N[4 * (size_t)s + f];
            if (u == GTET_NO_TET || L->mark[u] || side(L, s, f, q) != 0) continue;
            if (push(L, &len, u) < 0) {
                for (size_t k = 0; k < len; k++) L->mark[L->list[k]] = 0;
                return -2;
            }
        }
    }
    for (size_t k = 0; k < len; k++) L->mark[L->list[k]] = 0;
    return (npy_intp)best;
}

/* find_simplex(xi (m, 3) float64 C-contiguous) -> (m,) intp */
PyObject *mesh_find_simplex(MeshObject *m, PyObject *arg)
{
    if (!PyArray_Check(arg) || PyArray_TYPE((PyArrayObject *)arg) != NPY_DOUBLE ||
        PyArray_NDIM((PyArrayObject *)arg) != 2 || PyArray_DIM((PyArrayObject *)arg, 1) != 3 ||
        !PyArray_IS_C_CONTIGUOUS((PyArrayObject *)arg) ||
        !PyArray_ISALIGNED((PyArrayObject *)arg) || PyArray_ISBYTESWAPPED((PyArrayObject *)arg)) {
        PyErr_SetString(PyExc_TypeError,
                        "find_simplex: a C-contiguous float64 array of shape (m, 3) expected");
        return NULL;
    }
    PyArrayObject *xa = (PyArrayObject *)arg;
    npy_intp d[1] = {PyArray_DIM(xa, 0)};
    PyObject *a = new_intp(1, d);
    if (!a) return NULL;
    npy_intp *out = PyArray_DATA((PyArrayObject *)a);
    const double *x = PyArray_DATA(xa);
    locator L = {gtet_mesh_vertices(m->mesh), gtet_mesh_tets(m->mesh),
                 gtet_mesh_neighbors(m->mesh), (size_t)m->nt, NULL, NULL, 0};
    L.mark = calloc(L.nt ? L.nt : 1, 1);
    if (!L.mark) {
        Py_DECREF(a);
        return PyErr_NoMemory();
    }
    int nomem = 0;
    Py_INCREF(xa);
    Py_BEGIN_ALLOW_THREADS
    uint32_t hint = 0;
    for (npy_intp i = 0; i < d[0]; i++) {
        const double *q = x + 3 * i;
        if (!isfinite(q[0]) || !isfinite(q[1]) || !isfinite(q[2]) || L.nt == 0) {
            out[i] = -1;
            continue;
        }
        npy_intp r = locate(&L, q, &hint);
        if (r == -2) {
            nomem = 1;
            break;
        }
        out[i] = r;
    }
    Py_END_ALLOW_THREADS
    Py_DECREF(xa);
    free(L.mark);
    free(L.list);
    if (nomem) {
        Py_DECREF(a);
        return PyErr_NoMemory();
    }
    return a;
}
