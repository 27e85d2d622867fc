/* _gigatet.c -- the CPython/numpy binding of gigatet (module gigatet._gigatet).
 *
 * One type, Mesh, owns a gtet_mesh and the float64 points it was built from.  The Python
 * class gigatet.Delaunay (python/gigatet/__init__.py) wraps it under scipy's names.
 *
 *   triangulate(points, threads, check) -> Mesh   the GIL is released while the kernel runs;
 *       SIGINT (KeyboardInterrupt) is polled through gtet_options.cancel before each pass
 *       and every 65536 points of a one-thread pass.
 *   Mesh.views() -> (vertices, tets, neighbors, input_map): read-only numpy arrays over the
 *       mesh's own memory (zero-copy; their base is the Mesh, which keeps the memory alive).
 *   Mesh.simplices(), neighbors(), vertex_to_simplex(), convex_hull(),
 *       vertex_neighbor_vertices(), vertex_input_index(), input_map(): new intp arrays, in
 *       input-point numbering (a vertex is named by the input index of its first occurrence).
 *   Mesh.find_simplex(xi): exact point location (gtet_orient3d) by a visibility walk.
 *   Mesh.check(flags), stats(), write(path).
 *   Mesh.__reduce__() / _restore(...): pickling and copying; the arrays themselves are saved
 *       and a Mesh is made from them by gtet_mesh_from_arrays (src/mesh/mesh.h), so the copy
 *       has the tets in the same order (a run with threads orders them as it goes).
 *
 * Errors become exceptions: ValueError (NaN/Inf, with the point's index), DegenerateInputError
 * (a ValueError, with .dimension), MemoryError, CheckError (a RuntimeError, with .report),
 * OSError for files that cannot be written.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <numpy/arrayobject.h>

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/base.h"
#include "gigatet.h"
#include "io/io.h"
#include "mesh/mesh.h"

static PyObject *DegenerateInputError;  /* gigatet.DegenerateInputError(ValueError) */
static PyObject *CheckError;            /* gigatet.CheckError(RuntimeError) */

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

static PyTypeObject MeshType;

/* ---------------------------------------------------------------------------------------- */
/* Errors                                                                                   */
/* ---------------------------------------------------------------------------------------- */

static PyObject *set_error(const gtet_error *err, gtet_status s)
{
    const char *msg = err->message[0] ? err->message : gtet_status_str(s);
    switch (s) {
    case GTET_ERR_NONFINITE: {
        PyObject *inst = PyObject_CallFunction(PyExc_ValueError, "s", msg);
        if (!inst) return NULL;
        PyObject *idx = err->index == SIZE_MAX ? (Py_INCREF(Py_None), Py_None)
                                               : PyLong_FromSize_t(err->index);
        if (idx && PyObject_SetAttrString(inst, "index", idx) == 0)
            PyErr_SetObject(PyExc_ValueError, inst);
        Py_XDECREF(idx);
        Py_DECREF(inst);
        return NULL;
    }
    case GTET_ERR_DEGENERATE_INPUT: {
        PyObject *inst = PyObject_CallFunction(DegenerateInputError, "s", msg);
        if (!inst) return NULL;
        PyObject *dim = PyLong_FromLong(err->dimension);
        if (dim && PyObject_SetAttrString(inst, "dimension", dim) == 0)
            PyErr_SetObject(DegenerateInputError, inst);
        Py_XDECREF(dim);
        Py_DECREF(inst);
        return NULL;
    }
    case GTET_ERR_OUT_OF_MEMORY:
        PyErr_SetString(PyExc_MemoryError, msg);
        return NULL;
    case GTET_ERR_ARGUMENT:
    case GTET_ERR_TOO_LARGE:
        PyErr_SetString(PyExc_ValueError, msg);
        return NULL;
    case GTET_ERR_CHECK_FAILED:
        PyErr_SetString(CheckError, msg);
        return NULL;
    default:
        PyErr_Format(PyExc_RuntimeError, "gigatet: %s (status %d)", msg, (int)s);
        return NULL;
    }
}

/* ---------------------------------------------------------------------------------------- */
/* triangulate                                                                              */
/* ---------------------------------------------------------------------------------------- */

#ifdef GTET_HAVE_CANCEL
/* Polled by the kernel on the calling thread between passes: take the GIL back for a moment
 * and let Python run its signal handlers (SIGINT raises KeyboardInterrupt). */
typedef struct cancel_ctx {
    PyThreadState *ts;
    int interrupted;
} cancel_ctx;

static int poll_signals(void *user)
{
    cancel_ctx *c = user;
    if (c->interrupted) return 1;
    PyEval_RestoreThread(c->ts);
    if (PyErr_CheckSignals() < 0) c->interrupted = 1;
    c->ts = PyEval_SaveThread();
    return c->interrupted;
}
#endif

/* vertex id -> input index of its first occurrence (vertex ids are in first-occurrence
 * order, so vertex k is new exactly when input_map[i] == k). */
static npy_intp *first_occurrence(const gtet_mesh *mesh, size_t n, size_t nv)
{
    npy_intp *first = malloc((nv ? nv : 1) * sizeof *first);
    if (!first) return NULL;
    const uint32_t *map = gtet_mesh_input_map(mesh);
    size_t k = 0;
    for (size_t i = 0; i < n && k < nv; i++)
        if (map[i] == k) first[k++] = (npy_intp)i;
    if (k != nv) {  /* not in first-occurrence order: the header's promise is broken */
        free(first);
        return NULL;
    }
    return first;
}

/* A Mesh owning `mesh` (freed here when this fails) over the points array pts (a reference
 * taken): the one constructor of a run's result (triangulate) and of an unpickled one
 * (_restore, with the saved stats).  NULL with a Python error set. */
static MeshObject *mesh_object_new(gtet_mesh *mesh, PyArrayObject *pts, double seconds,
                                   int threads_asked, int threads, PyObject *saved_stats)
{
    MeshObject *m = PyObject_New(MeshObject, &MeshType);
    if (!m) {
        gtet_mesh_free(&mesh);
        return NULL;
    }
    m->mesh = mesh;
    Py_INCREF(pts);
    m->points = pts;
    m->n = PyArray_DIM(pts, 0);
    m->nv = (npy_intp)gtet_mesh_num_vertices(mesh);
    m->nt = (npy_intp)gtet_mesh_num_tets(mesh);
    m->first = NULL;
    m->seconds = seconds;
    m->threads_asked = threads_asked;
    m->threads = threads;
    Py_XINCREF(saved_stats);
    m->saved_stats = saved_stats;
    /* a restored map was checked to be in first-occurrence order: a failure is only memory */
    if (m->nv != m->n && !(m->first = first_occurrence(mesh, (size_t)m->n, (size_t)m->nv))) {
        Py_DECREF(m);
        PyErr_NoMemory();
        return NULL;
    }
    return m;
}

static PyObject *py_triangulate(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *names[] = {"points", "threads", "check", "memory_limit", NULL};
    PyObject *obj;
    int threads = 0, check = 0;
    Py_ssize_t memory_limit = 0;  /* gtet_options.memory_limit: 0 the machine, -1 off */
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|ipn", names, &obj, &threads, &check,
                                     &memory_limit))
        return NULL;
    if (memory_limit < -1) {
        PyErr_SetString(PyExc_ValueError, "memory_limit must be bytes > 0, 0 (auto) or -1 (off)");
        return NULL;
    }
    if (!PyArray_Check(obj) || PyArray_TYPE((PyArrayObject *)obj) != NPY_DOUBLE ||
        PyArray_NDIM((PyArrayObject *)obj) != 2 ||
        PyArray_DIM((PyArrayObject *)obj, 1) != 3 ||
        !PyArray_IS_C_CONTIGUOUS((PyArrayObject *)obj) ||
        !PyArray_ISALIGNED((PyArrayObject *)obj) || PyArray_ISBYTESWAPPED((PyArrayObject *)obj)) {
        PyErr_SetString(PyExc_TypeError,
                        "triangulate: points must be a C-contiguous float64 array of shape (n, 3)");
        return NULL;
    }
    if (threads < 0) {
        PyErr_SetString(PyExc_ValueError, "threads must be >= 0 (0: all cores)");
        return NULL;
    }
    PyArrayObject *pts = (PyArrayObject *)obj;
    const double *xyz = PyArray_DATA(pts);
    size_t n = (size_t)PyArray_DIM(pts, 0);

    gtet_options opt;
    gtet_error err;
    gtet_options_init(&opt);
    opt.threads = threads;
    opt.check = check;
    opt.memory_limit = memory_limit == -1 ? SIZE_MAX : (size_t)memory_limit;
    opt.error = &err;
    memset(&err, 0, sizeof err);
    gtet_mesh *mesh = NULL;
    gtet_status s;
    double t0, t1;
#ifdef GTET_HAVE_CANCEL
    cancel_ctx cc = {NULL, 0};
    opt.cancel = poll_signals;
    opt.cancel_user = &cc;
    cc.ts = PyEval_SaveThread();
    t0 = omp_get_wtime();
    s = gtet_triangulate(xyz, n, &opt, &mesh);
    t1 = omp_get_wtime();
    PyEval_RestoreThread(cc.ts);
    if (s == GTET_ERR_CANCELLED) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_KeyboardInterrupt, "gigatet: cancelled");
        return NULL;
    }
    if (cc.interrupted && s == GTET_OK) {  /* the run ended before it looked again */
        gtet_mesh_free(&mesh);
        return NULL;
    }
#else
    Py_BEGIN_ALLOW_THREADS
    t0 = omp_get_wtime();
    s = gtet_triangulate(xyz, n, &opt, &mesh);
    t1 = omp_get_wtime();
    Py_END_ALLOW_THREADS
#endif
    if (s != GTET_OK) return set_error(&err, s);

    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    return (PyObject *)mesh_object_new(mesh, pts, t1 - t0, threads,
                                       st.threads > 0 ? st.threads : 1, NULL);
}

static void mesh_dealloc(MeshObject *m)
{
    gtet_mesh_free(&m->mesh);
    free(m->first);
    Py_XDECREF(m->points);
    Py_XDECREF(m->saved_stats);
    PyObject_Free(m);
}

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

static PyObject *mesh_views(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_simplices(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_neighbors(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_vertex_to_simplex(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_convex_hull(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_vertex_neighbor_vertices(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_vertex_input_index(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_input_map(MeshObject *m, PyObject *noargs)
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
static PyObject *mesh_find_simplex(MeshObject *m, PyObject *arg)
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

/* ---------------------------------------------------------------------------------------- */
/* Checker, statistics, files                                                               */
/* ---------------------------------------------------------------------------------------- */

static int dict_set(PyObject *d, const char *key, PyObject *v)
{
    if (!v) return -1;
    int r = PyDict_SetItemString(d, key, v);
    Py_DECREF(v);
    return r;
}

static PyObject *u64(uint64_t x) { return PyLong_FromUnsignedLongLong((unsigned long long)x); }

static PyObject *violation_dict(const gtet_check_violation *v)
{
    if (!v->stage) Py_RETURN_NONE;
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    PyObject *tets = PyList_New(0), *verts = PyList_New(0);
    int bad = !tets || !verts;
    for (int i = 0; i < 2 && !bad; i++)
        if (v->tet[i] != GTET_CHECK_NONE) {
            PyObject *x = u64(v->tet[i]);
            bad = !x || PyList_Append(tets, x) < 0;
            Py_XDECREF(x);
        }
    for (int i = 0; i < v->nvertices && i < 5 && !bad; i++) {
        PyObject *x = Py_BuildValue("{s:I,s:(ddd)}", "id", (unsigned)v->vertex[i], "point",
                                    v->point[i][0], v->point[i][1], v->point[i][2]);
        bad = !x || PyList_Append(verts, x) < 0;
        Py_XDECREF(x);
    }
    if (bad || dict_set(d, "stage", PyUnicode_FromString(v->stage)) < 0 ||
        dict_set(d, "tie", PyBool_FromLong(v->tie)) < 0 ||
        dict_set(d, "group_size", u64(v->group_size)) < 0 ||
        PyDict_SetItemString(d, "tets", tets) < 0 || PyDict_SetItemString(d, "vertices", verts) < 0) {
        Py_XDECREF(tets);
        Py_XDECREF(verts);
        Py_DECREF(d);
        return NULL;
    }
    Py_DECREF(tets);
    Py_DECREF(verts);
    return d;
}

static PyObject *report_dict(const gtet_check_report *r)
{
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    if (dict_set(d, "ok", PyBool_FromLong(r->ok)) < 0 ||
        dict_set(d, "mode", PyUnicode_FromString(r->mode & GTET_CHECK_DELAUNAY ? "delaunay"
                                                                               : "canonical")) < 0 ||
        dict_set(d, "tets", u64(r->tets)) < 0 ||
        dict_set(d, "facets_checked", u64(r->facets_checked)) < 0 ||
        dict_set(d, "hull_facets", u64(r->hull_facets)) < 0 ||
        dict_set(d, "duplicates", u64(r->duplicates)) < 0 ||
        dict_set(d, "negative_tets", u64(r->negative_tets)) < 0 ||
        dict_set(d, "unused_vertices", u64(r->unused_vertices)) < 0 ||
        dict_set(d, "cospherical_facets", u64(r->cospherical_facets)) < 0 ||
        dict_set(d, "coplanar_hull_edges", u64(r->coplanar_hull_edges)) < 0 ||
        dict_set(d, "euler", PyLong_FromLong(r->euler)) < 0 ||
        dict_set(d, "message", PyUnicode_FromString(r->message)) < 0 ||
        dict_set(d, "violation", violation_dict(&r->violation)) < 0) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

/* check(flags) -> report dict; raises CheckError (with .report) when the mesh fails. */
static PyObject *mesh_check(MeshObject *m, PyObject *args)
{
    unsigned flags = 0;
    if (!PyArg_ParseTuple(args, "I", &flags)) return NULL;
    gtet_check_report rep;
    memset(&rep, 0, sizeof rep);
    gtet_status s;
    Py_BEGIN_ALLOW_THREADS
    s = gtet_check(m->mesh, PyArray_DATA(m->points), (size_t)m->n, flags, &rep);
    Py_END_ALLOW_THREADS
    if (s != GTET_OK && s != GTET_ERR_CHECK_FAILED) {
        gtet_error e;
        memset(&e, 0, sizeof e);
        e.index = SIZE_MAX;
        snprintf(e.message, sizeof e.message, "check: %s", gtet_status_str(s));
        return set_error(&e, s);
    }
    PyObject *d = report_dict(&rep);
    if (!d) return NULL;
    if (s == GTET_OK) return d;
    PyObject *inst = PyObject_CallFunction(CheckError, "s", rep.message);
    if (inst && PyObject_SetAttrString(inst, "report", d) == 0) PyErr_SetObject(CheckError, inst);
    Py_XDECREF(inst);
    Py_DECREF(d);
    return NULL;
}

static PyObject *pred_dict(const gtet_pred_counters *p)
{
    return Py_BuildValue(
        "{s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:K,s:[K,K,K,K]}", "orient_calls",
        (unsigned long long)p->orient_calls, "orient_exact", (unsigned long long)p->orient_exact,
        "orient_int", (unsigned long long)p->orient_int, "orient_gmp",
        (unsigned long long)p->orient_gmp, "orient_zero", (unsigned long long)p->orient_zero,
        "insphere_calls", (unsigned long long)p->insphere_calls, "insphere_exact",
        (unsigned long long)p->insphere_exact, "insphere_int", (unsigned long long)p->insphere_int,
        "insphere_int122", (unsigned long long)p->insphere_int122, "insphere_gmp", (unsigned long long)p->insphere_gmp, "insphere_zero",
        (unsigned long long)p->insphere_zero, "sos_calls", (unsigned long long)p->sos_calls,
        "sos_depth", (unsigned long long)p->sos_depth[0], (unsigned long long)p->sos_depth[1],
        (unsigned long long)p->sos_depth[2], (unsigned long long)p->sos_depth[3]);
}

/* stats() -> dict with the fields of the CLI's --stats (file-related ones aside). */
static PyObject *mesh_stats(MeshObject *m, PyObject *noargs)
{
    (void)noargs;
    if (m->saved_stats) {  /* a restored mesh: a copy of the pickled mesh's figures */
        PyObject *copy = PyImport_ImportModule("copy");
        PyObject *r = copy ? PyObject_CallMethod(copy, "deepcopy", "O", m->saved_stats) : NULL;
        Py_XDECREF(copy);
        return r;
    }
    gtet_stats st;
    gtet_mesh_stats(m->mesh, &st);
    const size_t nt = (size_t)m->nt;
    PyObject *rounds = PyList_New(0);
    if (!rounds) return NULL;
    for (int r = 0; r < st.num_rounds && st.rounds; r++) {
        const gtet_round_stats *rs = &st.rounds[r];
        PyObject *x = Py_BuildValue(
            "{s:K,s:K,s:K,s:K,s:i,s:i,s:d,s:d,s:i}", "points", (unsigned long long)rs->points,
            "tried", (unsigned long long)rs->tried, "inserted", (unsigned long long)rs->inserted,
            "deferred", (unsigned long long)rs->deferred, "threads", rs->threads, "passes",
            rs->passes, "alpha", rs->tried ? (double)rs->inserted / (double)rs->tried : 1.0,
            "alpha_first_pass", rs->alpha_first, "ownership", rs->ownership);
        if (!x || PyList_Append(rounds, x) < 0) {
            Py_XDECREF(x);
            Py_DECREF(rounds);
            return NULL;
        }
        Py_DECREF(x);
    }
    PyObject *pred = pred_dict(&st.pred);
    if (!pred) {
        Py_DECREF(rounds);
        return NULL;
    }
    return Py_BuildValue(
        "{s:n,s:n,s:n,s:n,s:n,s:i,s:d,s:{s:d,s:d,s:d,s:d,s:d,s:d},s:n,s:n,s:K,s:K,s:K,s:N,"
        "s:i,s:N}",
        "points", (Py_ssize_t)m->n, "vertices", (Py_ssize_t)m->nv, "duplicates",
        (Py_ssize_t)gtet_mesh_num_duplicates(m->mesh), "tets", (Py_ssize_t)nt, "hull_facets",
        (Py_ssize_t)gtet_mesh_num_hull_facets(m->mesh), "threads", st.threads,
        "tets_per_second", m->seconds > 0 ? (double)nt / m->seconds : 0.0, "seconds",
        "validate", st.seconds_validate, "sort", st.seconds_sort, "insert", st.seconds_insert,
        "finalize", st.seconds_finalize, "kernel", m->seconds, "kernel_reported",
        st.seconds_total, "bytes_per_tet", (Py_ssize_t)st.bytes_per_tet, "kernel_peak_bytes",
        (Py_ssize_t)st.peak_bytes, "tets_created", (unsigned long long)st.tets_created,
        "walk_steps", (unsigned long long)st.walk_steps, "walk_fallbacks",
        (unsigned long long)st.walk_fallbacks, "predicates", pred, "num_rounds", st.num_rounds,
        "rounds", rounds);
}

/* write(path): the CLI's mesh writers, by extension (.ele with its .node, .msh, .vtu). */
static PyObject *mesh_write(MeshObject *m, PyObject *arg)
{
    PyObject *bytes = NULL;
    if (!PyUnicode_FSConverter(arg, &bytes)) return NULL;
    const char *path = PyBytes_AS_STRING(bytes);
    io_error err;
    memset(&err, 0, sizeof err);
    io_status s;
    Py_BEGIN_ALLOW_THREADS
    s = io_write_mesh(path, gtet_mesh_vertices(m->mesh), (size_t)m->nv, gtet_mesh_tets(m->mesh),
                      (size_t)m->nt, &err);
    Py_END_ALLOW_THREADS
    Py_DECREF(bytes);
    switch (s) {
    case IO_OK:
        Py_RETURN_NONE;
    case IO_ERR_NOMEM:
        PyErr_SetString(PyExc_MemoryError, err.message);
        return NULL;
    case IO_ERR_ARGUMENT:
        PyErr_SetString(PyExc_ValueError, err.message);
        return NULL;
    default:
        PyErr_SetString(PyExc_OSError, err.message);
        return NULL;
    }
}

/* ---------------------------------------------------------------------------------------- */
/* Pickling and copying                                                                     */
/* ---------------------------------------------------------------------------------------- */

/* The layout of the tuple Mesh.__reduce__ hands to _restore; a pickle of another layout is
 * refused by name rather than misread. */
#define PICKLE_FORMAT 1

static PyObject *restore_fn;  /* gigatet._gigatet._restore, looked up once at import */

/* Mesh.__reduce__: (_restore, (format, points, vertices, tets, neighbors, input_map, stats,
 * threads_asked, threads)).  The arrays themselves are saved, so the copy has the tets in
 * their order here: a new run with threads may number them otherwise (ARCHITECTURE.md, the
 * slot order; NOTES.md E180).  The four arrays are the zero-copy views, which pickle as their
 * data (out of band with protocol 5) and deep-copy as copies. */
static PyObject *mesh_reduce(MeshObject *m, PyObject *noargs)
{
    PyObject *views = mesh_views(m, noargs);
    if (!views) return NULL;
    PyObject *stats = mesh_stats(m, noargs);
    if (!stats) {
        Py_DECREF(views);
        return NULL;
    }
    PyObject *r = Py_BuildValue("(O(iOOOOONii))", restore_fn, PICKLE_FORMAT, (PyObject *)m->points,
                                PyTuple_GET_ITEM(views, 0), PyTuple_GET_ITEM(views, 1),
                                PyTuple_GET_ITEM(views, 2), PyTuple_GET_ITEM(views, 3), stats,
                                m->threads_asked, m->threads);
    Py_DECREF(views);
    return r;
}

/* obj as a C-contiguous, aligned, native array of `type` with `nd` dimensions, the last of
 * `last` (when > 0) entries, or NULL with a ValueError naming `what`.  No casts: the pickle
 * saved exactly these types. */
static PyArrayObject *saved_array(PyObject *obj, int type, int nd, npy_intp last, const char *what)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_OTF(obj, type, NPY_ARRAY_IN_ARRAY);
    if (!a) return NULL;
    if (PyArray_NDIM(a) != nd || (last > 0 && PyArray_DIM(a, nd - 1) != last)) {
        PyErr_Format(PyExc_ValueError, "gigatet: a saved mesh's %s has shape of %d dimensions, "
                     "not the one pickled", what, PyArray_NDIM(a));
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

/* _restore(format, points, vertices, tets, neighbors, input_map, stats, threads_asked,
 * threads) -> Mesh: Mesh.__reduce__'s inverse, through gtet_mesh_from_arrays (which copies the
 * arrays and refuses any that would take an accessor out of bounds). */
static PyObject *py_restore(PyObject *self, PyObject *args)
{
    (void)self;
    int format, threads_asked, threads;
    PyObject *o[5], *stats;
    if (!PyArg_ParseTuple(args, "iOOOOOO!ii", &format, &o[0], &o[1], &o[2], &o[3], &o[4],
                          &PyDict_Type, &stats, &threads_asked, &threads))
        return NULL;
    if (format != PICKLE_FORMAT) {
        PyErr_Format(PyExc_ValueError, "gigatet: a mesh pickled in format %d; this version "
                     "reads format %d", format, PICKLE_FORMAT);
        return NULL;
    }
    PyArrayObject *pts = saved_array(o[0], NPY_DOUBLE, 2, 3, "points");
    PyArrayObject *v = pts ? saved_array(o[1], NPY_DOUBLE, 2, 3, "vertices") : NULL;
    PyArrayObject *t = v ? saved_array(o[2], NPY_UINT32, 2, 4, "tets") : NULL;
    PyArrayObject *nb = t ? saved_array(o[3], NPY_UINT32, 2, 4, "neighbors") : NULL;
    PyArrayObject *map = nb ? saved_array(o[4], NPY_UINT32, 1, 0, "input map") : NULL;
    MeshObject *m = NULL;
    if (!map) goto done;
    const size_t n = (size_t)PyArray_DIM(pts, 0), nt = (size_t)PyArray_DIM(t, 0);
    if ((size_t)PyArray_DIM(map, 0) != n || (size_t)PyArray_DIM(nb, 0) != nt) {
        PyErr_SetString(PyExc_ValueError, "gigatet: a saved mesh's arrays disagree in length");
        goto done;
    }
    gtet_mesh *mesh = NULL;
    char msg[160] = "";
    gtet_status s;
    Py_BEGIN_ALLOW_THREADS
    s = gtet_mesh_from_arrays(PyArray_DATA(v), (size_t)PyArray_DIM(v, 0), PyArray_DATA(map), n,
                              PyArray_DATA(t), PyArray_DATA(nb), nt, &mesh, msg, sizeof msg);
    Py_END_ALLOW_THREADS
    if (s == GTET_ERR_OUT_OF_MEMORY) {
        PyErr_NoMemory();
        goto done;
    }
    if (s != GTET_OK) {
        PyErr_Format(PyExc_ValueError, "gigatet: not a saved gigatet mesh: %s", msg);
        goto done;
    }
    PyObject *secs = PyDict_GetItemString(stats, "seconds");  /* borrowed */
    PyObject *kernel = secs && PyDict_Check(secs) ? PyDict_GetItemString(secs, "kernel") : NULL;
    m = mesh_object_new(mesh, pts, kernel && PyFloat_Check(kernel) ? PyFloat_AS_DOUBLE(kernel) : 0.0,
                        threads_asked, threads > 0 && threads <= BASE_MAX_THREADS ? threads : 1, stats);
done:
    Py_XDECREF(pts);
    Py_XDECREF(v);
    Py_XDECREF(t);
    Py_XDECREF(nb);
    Py_XDECREF(map);
    return (PyObject *)m;
}

static PyObject *mesh_get_int(MeshObject *m, void *which)
{
    switch ((int)(intptr_t)which) {
    case 0: return PyLong_FromSsize_t(m->n);
    case 1: return PyLong_FromSsize_t(m->nv);
    case 2: return PyLong_FromSsize_t(m->nt);
    case 3: return PyLong_FromSize_t(gtet_mesh_num_hull_facets(m->mesh));
    case 5: return PyLong_FromLong(m->threads);
    default: return PyLong_FromSize_t(gtet_mesh_num_duplicates(m->mesh));
    }
}

static PyObject *mesh_get_points(MeshObject *m, void *unused)
{
    (void)unused;
    Py_INCREF(m->points);
    return (PyObject *)m->points;
}

static PyGetSetDef mesh_getset[] = {
    {"npoints", (getter)mesh_get_int, NULL, "input points", (void *)0},
    {"nvertices", (getter)mesh_get_int, NULL, "distinct points", (void *)1},
    {"ntets", (getter)mesh_get_int, NULL, "tetrahedra", (void *)2},
    {"nhull", (getter)mesh_get_int, NULL, "hull facets", (void *)3},
    {"nduplicates", (getter)mesh_get_int, NULL, "duplicate input points", (void *)4},
    {"threads", (getter)mesh_get_int, NULL,
     "threads the run used (fewer than asked when the system would not start them)", (void *)5},
    {"points", (getter)mesh_get_points, NULL, "the float64 points triangulated", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyMethodDef mesh_methods[] = {
    {"views", (PyCFunction)mesh_views, METH_NOARGS,
     "(vertices, tets, neighbors, input_map): read-only arrays over the mesh's memory"},
    {"simplices", (PyCFunction)mesh_simplices, METH_NOARGS, "tets as input indices (intp)"},
    {"neighbors", (PyCFunction)mesh_neighbors, METH_NOARGS, "neighbours, -1 on the hull"},
    {"vertex_to_simplex", (PyCFunction)mesh_vertex_to_simplex, METH_NOARGS, NULL},
    {"convex_hull", (PyCFunction)mesh_convex_hull, METH_NOARGS, NULL},
    {"vertex_neighbor_vertices", (PyCFunction)mesh_vertex_neighbor_vertices, METH_NOARGS, NULL},
    {"vertex_input_index", (PyCFunction)mesh_vertex_input_index, METH_NOARGS, NULL},
    {"input_map", (PyCFunction)mesh_input_map, METH_NOARGS, NULL},
    {"find_simplex", (PyCFunction)mesh_find_simplex, METH_O, NULL},
    {"check", (PyCFunction)mesh_check, METH_VARARGS, NULL},
    {"stats", (PyCFunction)mesh_stats, METH_NOARGS, NULL},
    {"write", (PyCFunction)mesh_write, METH_O, NULL},
    {"__reduce__", (PyCFunction)mesh_reduce, METH_NOARGS,
     "pickle and copy support: the arrays themselves are saved, never recomputed"},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject MeshType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "gigatet._gigatet.Mesh",
    .tp_doc = "A gigatet mesh (made by gigatet._gigatet.triangulate)",
    .tp_basicsize = sizeof(MeshObject),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_dealloc = (destructor)mesh_dealloc,
    .tp_methods = mesh_methods,
    .tp_getset = mesh_getset,
};

/* ---------------------------------------------------------------------------------------- */
/* Module                                                                                   */
/* ---------------------------------------------------------------------------------------- */

/* NaN and infinite coordinates have no sign, and the exact stage's GMP (mpz_set_d) raises
 * SIGFPE on them: the interpreter died (NOTES.md E159b).  Refused here with a ValueError. */
static int finite_points(const char *what, const double (*p)[3], int k)
{
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++)
            if (!isfinite(p[i][j])) {
                PyErr_Format(PyExc_ValueError, "%s: point %d has %s %c coordinate (the "
                             "predicates take finite numbers)", what, i,
                             isnan(p[i][j]) ? "a NaN" : "an infinite", "xyz"[j]);
                return 0;
            }
    return 1;
}

static PyObject *py_orient3d(PyObject *self, PyObject *args)
{
    (void)self;
    double p[4][3];
    if (!PyArg_ParseTuple(args, "(ddd)(ddd)(ddd)(ddd)", &p[0][0], &p[0][1], &p[0][2], &p[1][0],
                          &p[1][1], &p[1][2], &p[2][0], &p[2][1], &p[2][2], &p[3][0], &p[3][1],
                          &p[3][2]))
        return NULL;
    if (!finite_points("orient3d", (const double (*)[3])p, 4)) return NULL;
    return PyLong_FromLong(gtet_orient3d(p[0], p[1], p[2], p[3]));
}

static PyObject *py_insphere(PyObject *self, PyObject *args)
{
    (void)self;
    double p[5][3];
    if (!PyArg_ParseTuple(args, "(ddd)(ddd)(ddd)(ddd)(ddd)", &p[0][0], &p[0][1], &p[0][2],
                          &p[1][0], &p[1][1], &p[1][2], &p[2][0], &p[2][1], &p[2][2], &p[3][0],
                          &p[3][1], &p[3][2], &p[4][0], &p[4][1], &p[4][2]))
        return NULL;
    if (!finite_points("insphere", (const double (*)[3])p, 5)) return NULL;
    return PyLong_FromLong(gtet_insphere(p[0], p[1], p[2], p[3], p[4]));
}

static PyMethodDef module_methods[] = {
    {"triangulate", (PyCFunction)(void (*)(void))py_triangulate, METH_VARARGS | METH_KEYWORDS,
     "triangulate(points, threads=0, check=False) -> Mesh; points: (n, 3) C-contiguous float64"},
    {"orient3d", py_orient3d, METH_VARARGS, "exact sign of orient3d(a, b, c, d)"},
    {"insphere", py_insphere, METH_VARARGS, "exact sign of insphere(a, b, c, d, e)"},
    {"_restore", py_restore, METH_VARARGS, "a Mesh from Mesh.__reduce__'s tuple (unpickling)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "gigatet._gigatet", "gigatet's C binding", -1, module_methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__gigatet(void);
PyMODINIT_FUNC PyInit__gigatet(void)
{
    import_array();
    if (PyType_Ready(&MeshType) < 0) return NULL;
    PyObject *mod = PyModule_Create(&module_def);
    if (!mod) return NULL;
    DegenerateInputError = PyErr_NewExceptionWithDoc(
        "gigatet.DegenerateInputError",
        "The distinct input points span fewer than 3 dimensions (fewer than 4 distinct points, "
        "collinear or coplanar): .dimension is their affine dimension (-1 for no points).",
        PyExc_ValueError, NULL);
    CheckError = PyErr_NewExceptionWithDoc(
        "gigatet.CheckError",
        "The exact checker found a violated invariant: .report holds the checker's report.",
        PyExc_RuntimeError, NULL);
    restore_fn = PyObject_GetAttrString(mod, "_restore");
    if (!DegenerateInputError || !CheckError || !restore_fn) goto fail;
    Py_INCREF(&MeshType);
    if (PyModule_AddObject(mod, "Mesh", (PyObject *)&MeshType) < 0) {
        Py_DECREF(&MeshType);
        goto fail;
    }
    Py_INCREF(DegenerateInputError);
    if (PyModule_AddObject(mod, "DegenerateInputError", DegenerateInputError) < 0) {
        Py_DECREF(DegenerateInputError);
        goto fail;
    }
    Py_INCREF(CheckError);
    if (PyModule_AddObject(mod, "CheckError", CheckError) < 0) {
        Py_DECREF(CheckError);
        goto fail;
    }
    if (PyModule_AddIntConstant(mod, "NO_TET", (long)GTET_NO_TET) < 0 ||
        PyModule_AddIntConstant(mod, "CHECK_FULL", GTET_CHECK_FULL) < 0 ||
        PyModule_AddIntConstant(mod, "CHECK_DELAUNAY", GTET_CHECK_DELAUNAY) < 0 ||
#ifdef GTET_HAVE_CANCEL
        PyModule_AddIntConstant(mod, "HAVE_CANCEL", 1) < 0 ||
#else
        PyModule_AddIntConstant(mod, "HAVE_CANCEL", 0) < 0 ||
#endif
        PyModule_AddStringConstant(mod, "__version__", "0.1.0") < 0)
        goto fail;
    return mod;
fail:
    Py_DECREF(mod);
    return NULL;
}
