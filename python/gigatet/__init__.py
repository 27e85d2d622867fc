"""gigatet: the exact, canonical and fast 3D Delaunay tetrahedrization, with
``scipy.spatial.Delaunay``'s interface.

>>> import numpy as np, gigatet
>>> d = gigatet.Delaunay(np.random.default_rng(1).random((1000, 3)))
>>> d.simplices.shape[1], d.find_simplex([0.5, 0.5, 0.5]) >= 0
(4, True)

What differs from scipy (Qhull):

* The result is *the* Delaunay tetrahedrization of the distinct points, with exact zeros
  (co-spherical, coplanar points) broken by a symbolic perturbation (CGAL's rule): no
  joggling, no precision errors, the same tets for any input order or thread count.
* Exact duplicates (-0.0 == +0.0) are not vertices: a vertex is named by the input index of
  its *first* occurrence, so ``simplices``, ``convex_hull``, ``vertex_neighbor_vertices``
  index the input ``points`` as scipy's do; the duplicates are listed in ``coplanar`` (scipy's
  "input points not in the triangulation") and ``duplicates``.
* Every simplex is positively oriented (orient3d > 0): ``convex_hull`` facets are
  counter-clockwise seen from outside.
* ``find_simplex`` is exact (orientation tests with exact arithmetic); a point on a facet,
  edge or vertex shared by several tets gets the smallest of their indices.
* Index arrays are ``intp``; result arrays are read-only (they are cached).
* A Delaunay pickles (every protocol) and copies (copy.copy, copy.deepcopy) with its arrays
  as they are, so ``simplices`` keeps its order in the copy; the points are not triangulated
  again (a run with threads orders the same tets otherwise).
"""
import functools
import operator
import os
import warnings

import numpy as np

from . import _gigatet
from ._gigatet import CheckError, DegenerateInputError, insphere, orient3d

__all__ = ["Delaunay", "DegenerateInputError", "CheckError", "orient3d", "insphere"]
__version__ = _gigatet.__version__

_CHECK_FULL = _gigatet.CHECK_FULL
_CHECK_DELAUNAY = _gigatet.CHECK_DELAUNAY


def _as_points(points, what="points"):
    """Any real array of shape (..., 3) -> C-contiguous float64 (a copy only if needed)."""
    a = np.asarray(points)
    if a.dtype.kind == "O" and a.size:
        # numbers numpy holds as objects (ints past 2**64, Fractions, Decimals, a pandas
        # frame's mixed columns): converted as scipy converts them; text, complex and None
        # are no real numbers (numpy would parse the text and take None for a NaN)
        if any(x is None or isinstance(x, (str, bytes, complex)) for x in a.flat):
            raise TypeError("%s must be real numbers, not text, complex or None" % what)
        try:
            a = a.astype(np.float64)
        except (TypeError, ValueError) as e:
            raise TypeError("%s must be real numbers: %s" % (what, e)) from None
    if a.dtype.kind not in "fiub":
        raise TypeError("%s must be real numbers, not %s" % (what, a.dtype))
    if a.ndim < 1 or a.shape[-1] != 3:
        raise ValueError("%s must have shape (..., 3), got %s" % (what, a.shape))
    return np.ascontiguousarray(a, dtype=np.float64)


def _is_cached(cls, name):
    """Whether name is a functools.cached_property of cls (its value is computed, not state)."""
    return isinstance(getattr(cls, name, None), functools.cached_property)


def _readonly(a):
    a.flags.writeable = False
    return a


class Delaunay:
    """Delaunay(points, threads=0, check=False, memory_limit=None, *, furthest_site=False,
    incremental=False, qhull_options=None)

    The Delaunay tetrahedrization of ``points`` (shape (n, 3), any real dtype and layout;
    converted once to C-contiguous float64, which is ``self.points``).

    threads: worker threads of the kernel (0 = all cores); the result does not depend on it.
             At most 255, and at most as many as the system lets the process start (ulimit -u,
             a cgroup's pids.max): fewer than asked for give a RuntimeWarning.
    check:   run the exact checker on the result (raises CheckError if it fails).
    memory_limit: the memory guard (gtet_options.memory_limit): None (default) estimates the
             run's peak before the work and raises MemoryError at once ("needs about X, Y
             available (MemAvailable)") when the machine (MemAvailable, the cgroup's limit,
             ulimit -v) cannot give it; an int: that many bytes are available; "off": no guard.

    furthest_site, incremental, qhull_options: scipy's keywords (keyword-only here: the second
             positional argument is ``threads``), so that code written for scipy runs:
             qhull_options is accepted and ignored (the result is the exact tetrahedrization,
             which no Qhull option changes: no joggling is needed); furthest_site=True and
             incremental=True raise NotImplementedError.

    Raises ValueError for NaN or infinite coordinates (the message and ``.index`` name the
    point), DegenerateInputError (a ValueError, ``.dimension`` = 0, 1, 2 or -1 for no points)
    when the distinct points do not span 3D, MemoryError.  The kernel runs with the GIL
    released; Ctrl-C (KeyboardInterrupt) stops it between passes.

    Attributes, as scipy.spatial.Delaunay's: points, simplices, neighbors, vertex_to_simplex,
    convex_hull, vertex_neighbor_vertices, transform, equations, paraboloid_scale,
    paraboloid_shift, coplanar, npoints, nsimplex, ndim, min_bound, max_bound, furthest_site;
    methods find_simplex, plane_distance, lift_points.

    Pickling and copy.copy / copy.deepcopy keep every attribute, the order of ``simplices``
    included: the mesh's arrays and stats are saved, not recomputed (multiprocessing, joblib
    and caches receive the same object); cached results are computed again from them.

    Beyond scipy: input_map, vertex_input_index, duplicates, check(), stats, write(),
    to_meshio(), and the zero-copy views of the kernel's own arrays: mesh_vertices (the
    distinct points, float64 (nv, 3)), mesh_tets and mesh_neighbors (uint32 (nsimplex, 4), in
    mesh vertex ids; 0xFFFFFFFF = NO_TET on the hull), mesh_input_map (uint32 (n,)).
    """

    ndim = 3
    furthest_site = False
    NO_TET = _gigatet.NO_TET

    def __init__(self, points, threads=0, check=False, memory_limit=None, *,
                 furthest_site=False, incremental=False, qhull_options=None):
        # scipy's keywords (NOTES.md E154): before, a TypeError for code written for scipy
        if furthest_site:
            raise NotImplementedError("furthest_site=True: gigatet builds the Delaunay "
                                      "tetrahedrization, not the furthest-site one")
        if incremental:
            raise NotImplementedError("incremental=True: gigatet does not add points to a "
                                      "built mesh; build a Delaunay of all the points")
        if qhull_options is not None and not isinstance(qhull_options, (str, bytes)):
            raise TypeError("qhull_options must be a string or None (it is ignored: the "
                            "result is exact whatever Qhull's options)")
        pts = _as_points(points)
        if pts.ndim != 2:
            raise ValueError("points must have shape (n, 3), got %s" % (pts.shape,))
        threads = operator.index(threads)
        if threads < 0:
            raise ValueError("threads must be >= 0 (0: all cores)")
        # the kernel uses at most 255 (gigatet.h), so any larger count means 255; passed on
        # as it was, 2**31 and more raised "OverflowError: signed integer is greater than
        # maximum", which names no argument
        threads = min(threads, 255)
        if memory_limit is None:
            limit = 0
        elif isinstance(memory_limit, str) and memory_limit == "off":
            limit = -1
        else:
            limit = operator.index(memory_limit)
            if limit <= 0:
                raise ValueError("memory_limit must be None, 'off' or a number of bytes > 0")
            # more bytes than an address space holds limit nothing ("off"); the C side takes
            # a Py_ssize_t, which 2**63 and more overflowed with a message naming no argument
            limit = min(limit, (1 << 62))
        self._adopt(_gigatet.triangulate(pts, threads, bool(check), limit))
        # the kernel starts only the threads the system lets it (ulimit -u, pids.max) and
        # OpenMP gives (NOTES.md E183, E184): libgomp would end the interpreter otherwise;
        # fewer than asked for is said
        asked = min(threads, 255)
        if asked > 1 and self._mesh.threads < asked:
            warnings.warn("gigatet: ran on %d of the %d threads asked for (no more could be "
                          "started or OpenMP would give no more: ulimit -u, memory for their "
                          "stacks, OMP_THREAD_LIMIT, a call inside a parallel region); the "
                          "triangulation is the same" % (self._mesh.threads, asked),
                          RuntimeWarning, stacklevel=2)

    # the attributes set from the mesh; every other array is computed from it on first use
    _FROM_MESH = ("_mesh", "points", "npoints", "nsimplex", "mesh_vertices", "mesh_tets",
                  "mesh_neighbors", "mesh_input_map")

    def _adopt(self, mesh):
        self._mesh = mesh
        self.points = mesh.points
        self.npoints = self.points.shape[0]
        self.nsimplex = mesh.ntets
        (self.mesh_vertices, self.mesh_tets, self.mesh_neighbors,
         self.mesh_input_map) = mesh.views()

    # ---- pickle, copy.copy, copy.deepcopy (NOTES.md E180) ------------------------------------
    # The state is the mesh (which pickles its points, vertices, tets, neighbours, input map and
    # stats as they are: a new run with threads could order the tets otherwise) and any
    # attribute a user set; the cached arrays are left out and computed again from the mesh on
    # first use, which gives them bit for bit (they are functions of the mesh's arrays).

    def __getstate__(self):
        state = {k: v for k, v in self.__dict__.items()
                 if k not in self._FROM_MESH and not _is_cached(type(self), k)}
        state["_mesh"] = self._mesh
        return state

    def __setstate__(self, state):
        state = dict(state)
        self._adopt(state.pop("_mesh"))
        self.__dict__.update(state)

    def __repr__(self):
        return "<gigatet.Delaunay: %d points, %d vertices, %d tets>" % (
            self.npoints, self._mesh.nvertices, self.nsimplex)

    # ---- scipy's arrays (computed on first use, then cached) ---------------------------------

    @functools.cached_property
    def simplices(self):
        """(nsimplex, 4) intp: the tets, as indices of input points, positively oriented."""
        return _readonly(self._mesh.simplices())

    @functools.cached_property
    def neighbors(self):
        """(nsimplex, 4) intp: neighbors[t, k] is the tet opposite simplices[t, k], -1 on the
        hull."""
        return _readonly(self._mesh.neighbors())

    @functools.cached_property
    def vertex_to_simplex(self):
        """(npoints,) intp: the smallest tet of each point; -1 for duplicates."""
        return _readonly(self._mesh.vertex_to_simplex())

    @functools.cached_property
    def convex_hull(self):
        """(nfaces, 3) intp: hull facets, counter-clockwise seen from outside."""
        return _readonly(self._mesh.convex_hull())

    @functools.cached_property
    def vertex_neighbor_vertices(self):
        """(indptr, indices): the neighbours of point k are indices[indptr[k]:indptr[k+1]]
        (ascending); duplicates have none."""
        indptr, indices = self._mesh.vertex_neighbor_vertices()
        return _readonly(indptr), _readonly(indices)

    @functools.cached_property
    def min_bound(self):
        return _readonly(self.points.min(axis=0))

    @functools.cached_property
    def max_bound(self):
        return _readonly(self.points.max(axis=0))

    @functools.cached_property
    def transform(self):
        """(nsimplex, 4, 3) float64, as scipy's: the barycentric coordinates of x in tet t
        are c = T[t, :3] @ (x - T[t, 3]) and 1 - c.sum() (floating point)."""
        v = self.points[self.simplices]                      # (ns, 4, 3)
        t = np.empty((self.nsimplex, 4, 3))
        c = v[:, :3, :] - v[:, 3:4, :]                       # c[:, j] = v_j - v_3
        # the inverse of the matrix with columns c_0, c_1, c_2: rows c_1 x c_2, c_2 x c_0,
        # c_0 x c_1 over the determinant (stacked 3x3 inverses without LAPACK's overhead)
        t[:, 0, :] = np.cross(c[:, 1], c[:, 2])
        t[:, 1, :] = np.cross(c[:, 2], c[:, 0])
        t[:, 2, :] = np.cross(c[:, 0], c[:, 1])
        det = np.einsum("ij,ij->i", c[:, 0], t[:, 0, :])
        with np.errstate(divide="ignore", invalid="ignore"):
            t[:, :3, :] /= det[:, None, None]
        t[:, 3, :] = v[:, 3, :]
        return _readonly(t)

    @functools.cached_property
    def _paraboloid(self):
        # the lift z = |x|^2 * scale + shift, scaled to the points' extent as Qhull's Qbb does
        sq = np.einsum("ij,ij->i", self.points, self.points)
        lo, hi = (sq.min(), sq.max()) if sq.size else (0.0, 0.0)
        m = float(np.abs(self.points).max()) if sq.size else 1.0
        if hi > lo and m > 0:
            scale = m / (hi - lo)
            return scale, -lo * scale
        return 1.0, 0.0

    @property
    def paraboloid_scale(self):
        return self._paraboloid[0]

    @property
    def paraboloid_shift(self):
        return self._paraboloid[1]

    def lift_points(self, x):
        """Lift points (..., 3) to the paraboloid: (..., 4)."""
        x = _as_points(x, "x")
        z = np.empty(x.shape[:-1] + (4,))
        z[..., :3] = x
        z[..., 3] = np.einsum("...i,...i->...", x, x) * self.paraboloid_scale + \
            self.paraboloid_shift
        return z

    @functools.cached_property
    def equations(self):
        """(nsimplex, 5) float64: [normal, offset] of each tet's hyperplane on the paraboloid
        (unit normal pointing down, as Qhull's lower facets), floating point."""
        z = self.lift_points(self.points[self.simplices])    # (ns, 4, 4)
        e = z[:, :3, :] - z[:, 3:4, :]                       # (ns, 3, 4)
        normal = np.empty((self.nsimplex, 4))
        for k in range(4):                                   # cofactors: a 4D cross product
            a, b, c = (e[:, :, j] for j in range(4) if j != k)
            minor = (a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
                     - a[:, 1] * (b[:, 0] * c[:, 2] - b[:, 2] * c[:, 0])
                     + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]))
            normal[:, k] = minor if k % 2 == 0 else -minor
        normal *= -np.sign(normal[:, 3:4])                  # pointing down (last < 0)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        eq = np.empty((self.nsimplex, 5))
        eq[:, :4] = normal
        eq[:, 4] = -np.einsum("ij,ij->i", normal, z[:, 3, :])
        return _readonly(eq)

    def plane_distance(self, xi):
        """Distances of the lifted points xi (..., 3) to every tet's hyperplane:
        (..., nsimplex); positive when xi is inside the tet's circumsphere."""
        z = self.lift_points(xi)
        return z @ self.equations[:, :4].T + self.equations[:, 4]

    @functools.cached_property
    def coplanar(self):
        """(nduplicates, 3) intp: scipy's "input points not in the triangulation", here the
        duplicates: rows (point index, a tet of the vertex it repeats, that vertex's input
        index, i.e. its first occurrence)."""
        d = self.duplicates
        out = np.empty((d.shape[0], 3), dtype=np.intp)
        out[:, 0] = d[:, 0]
        out[:, 1] = self.vertex_to_simplex[d[:, 1]]
        out[:, 2] = d[:, 1]
        return _readonly(out)

    # ---- beyond scipy ---------------------------------------------------------------------

    @functools.cached_property
    def input_map(self):
        """(npoints,) intp: mesh vertex id (row of mesh_vertices) of each input point."""
        return _readonly(self._mesh.input_map())

    @functools.cached_property
    def vertex_input_index(self):
        """(nvertices,) intp: the input index (first occurrence) of each mesh vertex, so that
        simplices == vertex_input_index[mesh_tets]."""
        return _readonly(self._mesh.vertex_input_index())

    @functools.cached_property
    def duplicates(self):
        """(nduplicates, 2) intp: rows (input index of a duplicate point, input index of its
        first occurrence), ascending."""
        first = self.vertex_input_index[self.input_map]
        dup = np.flatnonzero(first != np.arange(self.npoints))
        return _readonly(np.stack([dup, first[dup]], axis=1).astype(np.intp, copy=False))

    @property
    def nvertices(self):
        """Distinct points (mesh vertices)."""
        return self._mesh.nvertices

    @functools.cached_property
    def stats(self):
        """The run's figures, as the CLI's --stats: counts, seconds per phase, bytes per tet,
        predicate counters, BRIO rounds."""
        return self._mesh.stats()

    def find_simplex(self, xi, bruteforce=False, tol=None):
        """The tet containing each point of xi (..., 3), -1 outside the hull.  Exact (tol and
        bruteforce are accepted for scipy's signature and ignored); a point on the boundary of
        several tets gets the smallest of their indices.  Non-finite points give -1."""
        x = _as_points(xi, "xi")
        flat = np.ascontiguousarray(x.reshape(-1, 3))
        return self._mesh.find_simplex(flat).reshape(x.shape[:-1])

    def check(self, full=False, delaunay=False):
        """Run the exact, independent checker (gtet_check) on the mesh against self.points.
        full: add the O(n*m) empty-sphere test (small meshes only); delaunay: judge the
        Delaunay property with ties allowed instead of the canonical triangulation.  Returns
        the report (a dict, as `gigatet check --json`); raises CheckError (with .report) when
        an invariant is violated.  Ctrl-C (SIGINT) stops it within milliseconds: the checker
        polls Python's signal handlers, and KeyboardInterrupt comes out."""
        flags = (_CHECK_FULL if full else 0) | (_CHECK_DELAUNAY if delaunay else 0)
        return self._mesh.check(flags)

    def write(self, path):
        """Write the mesh as the CLI does, by extension: .ele (TetGen, with NAME.node),
        .msh (Gmsh 4.1), .vtu (VTK).  The files hold the distinct points (mesh_vertices) and
        the tets in mesh vertex ids (mesh_tets); written atomically."""
        self._mesh.write(os.fspath(path))

    def to_meshio(self):
        """A meshio.Mesh of the input points (duplicates included, in no cell) and the tets
        (cell type "tetra"), so point data indexed like `points` lines up."""
        try:
            import meshio
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("to_meshio() needs the meshio package") from e
        return meshio.Mesh(np.array(self.points), [("tetra", np.array(self.simplices))])
