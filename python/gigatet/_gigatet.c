/* _gigatet.c -- the CPython/numpy binding of gigatet (module gigatet._gigatet): the module, the
 * Mesh type, triangulation, the checker, statistics, files and pickling; the array accessors
 * and find_simplex are in _gigatet_arrays.c, the shared struct in _gigatet.h.
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
 *   Mesh.check(flags), stats(), write(path).  check releases the GIL and polls SIGINT
 *       through gtet_check_options.cancel (KeyboardInterrupt within milliseconds).
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
#define PY_ARRAY_UNIQUE_SYMBOL gigatet_ARRAY_API
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

#include "_gigatet.h"

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
#ifdef GTET_HAVE_CANCEL
    /* Ctrl-C: the checker polls SIGINT through gtet_check_options.cancel on this thread */
    gtet_check_options opt;
    gtet_check_options_init(&opt);
    opt.flags = flags;
    cancel_ctx cc = {NULL, 0};
    opt.cancel = poll_signals;
    opt.cancel_user = &cc;
    cc.ts = PyEval_SaveThread();
    s = gtet_check_opt(m->mesh, PyArray_DATA(m->points), (size_t)m->n, &opt, &rep);
    PyEval_RestoreThread(cc.ts);
    if (s == GTET_ERR_CANCELLED || cc.interrupted) {  /* the exception the handler raised */
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_KeyboardInterrupt, "gigatet: cancelled");
        return NULL;
    }
#else
    Py_BEGIN_ALLOW_THREADS
    s = gtet_check(m->mesh, PyArray_DATA(m->points), (size_t)m->n, flags, &rep);
    Py_END_ALLOW_THREADS
#endif
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
            "{s:K,s:K,s:K,s:K,s:i,s:i,s:d,s:d,s:i,s:K}", "points", (unsigned long long)rs->points,
            "tried", (unsigned long long)rs->tried, "inserted", (unsigned long long)rs->inserted,
            "deferred", (unsigned long long)rs->deferred, "threads", rs->threads, "passes",
            rs->passes, "alpha", rs->tried ? (double)rs->inserted / (double)rs->tried : 1.0,
            "alpha_first_pass", rs->alpha_first, "ownership", rs->ownership, "rebalanced",
            (unsigned long long)rs->rebalanced);
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
