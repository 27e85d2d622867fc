"""Pickling and copying a Delaunay (NOTES.md E180, Q25): every protocol, copy.copy,
copy.deepcopy and a round trip through a spawned process give an object equal in every
attribute, with the tets in the order they were saved in (the arrays are saved, the points are
not triangulated again: a run with threads may number the tets otherwise)."""
import copy
import multiprocessing
import operator
import pickle

import numpy as np
import pytest

import gigatet
from gigatet import _gigatet

# every attribute and zero-argument result the class exposes (scipy's and gigatet's own)
ARRAYS = ("points", "simplices", "neighbors", "vertex_to_simplex", "convex_hull", "transform",
          "equations", "coplanar", "min_bound", "max_bound", "input_map", "vertex_input_index",
          "duplicates", "mesh_vertices", "mesh_tets", "mesh_neighbors", "mesh_input_map")
SCALARS = ("npoints", "nsimplex", "ndim", "nvertices", "paraboloid_scale", "paraboloid_shift",
           "furthest_site", "NO_TET")


def points_with_duplicates(n=3000, seed=11):
    p = np.random.default_rng(seed).random((n, 3))
    # duplicates, one of them -0.0 against +0.0, so that the vertex maps are not the identity
    p = np.concatenate([p, p[[7, 3, 7]], [[0.0, 0.25, 0.5]], [[-0.0, 0.25, 0.5]]])
    return p


def queries(d):
    rng = np.random.default_rng(3)
    q = np.concatenate([rng.random((500, 3)) * 1.2 - 0.1, d.points[:20],
                        d.points[d.simplices[:20]].mean(axis=1)])
    return q


def assert_same(a, b):
    assert type(a) is type(b)
    for name in ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape, name
        # bit for bit (NaN-free here): the same tets in the same order, the same floats
        assert np.array_equal(x.view(np.uint8), y.view(np.uint8)), name
    for name in SCALARS:
        assert getattr(a, name) == getattr(b, name), name
    for k in range(2):
        assert np.array_equal(a.vertex_neighbor_vertices[k], b.vertex_neighbor_vertices[k])
    assert a.stats == b.stats
    assert repr(a) == repr(b)
    q = queries(a)
    assert np.array_equal(a.find_simplex(q), b.find_simplex(q))
    assert np.array_equal(a.plane_distance(q[:5]), b.plane_distance(q[:5]))
    assert np.array_equal(a.lift_points(q), b.lift_points(q))
    assert b.check(full=False)["ok"]


@pytest.fixture(scope="module")
def tri():
    return gigatet.Delaunay(points_with_duplicates(), threads=2)


@pytest.mark.parametrize("protocol", range(pickle.HIGHEST_PROTOCOL + 1))
def test_every_pickle_protocol(tri, protocol):
    data = pickle.dumps(tri, protocol=protocol)
    back = pickle.loads(data)
    assert_same(tri, back)
    # the copy owns its arrays: the zero-copy views are over the new mesh
    assert back._mesh is not tri._mesh
    assert isinstance(back.mesh_tets.base, _gigatet.Mesh) and back.mesh_tets.base is back._mesh
    # and pickles again to the same state (the bytes may differ in pickle's memo only)
    again = pickle.loads(pickle.dumps(back, protocol=protocol))
    assert_same(tri, again)


def test_pickle_protocol_5_out_of_band(tri):
    buffers = []
    data = pickle.dumps(tri, protocol=5, buffer_callback=buffers.append)
    assert buffers  # the big arrays travel out of band, without a copy into the pickle
    assert_same(tri, pickle.loads(data, buffers=buffers))


def test_copy_and_deepcopy(tri):
    shallow = copy.copy(tri)
    assert shallow._mesh is tri._mesh and shallow.points is tri.points
    assert_same(tri, shallow)
    deep = copy.deepcopy(tri)
    assert deep._mesh is not tri._mesh
    assert not np.shares_memory(deep.points, tri.points)
    assert not np.shares_memory(deep.mesh_tets, tri.mesh_tets)
    assert_same(tri, deep)
    # the raw mesh object too
    m = copy.deepcopy(tri._mesh)
    assert m.ntets == tri._mesh.ntets and m.nhull == tri._mesh.nhull
    assert m.nduplicates == tri._mesh.nduplicates == 4


def test_unpickling_does_not_triangulate(tri, monkeypatch):
    """The arrays are restored, not computed again: with threads the tets' order of a new run
    may differ (ARCHITECTURE.md), so a rebuild would silently renumber simplices."""
    data = pickle.dumps(tri)

    def refuse(*args, **kw):
        raise AssertionError("unpickling triangulated the points again")

    monkeypatch.setattr(_gigatet, "triangulate", refuse)
    assert_same(tri, pickle.loads(data))


def test_cached_results_and_user_attributes(tri):
    d = gigatet.Delaunay(tri.points[:500])
    d.simplices, d.transform, d.stats  # cached before pickling: recomputed, not saved
    d.label = "run 7"
    data = pickle.dumps(d)
    assert len(data) < 2 * (d.points.nbytes + d.mesh_vertices.nbytes + 2 * d.mesh_tets.nbytes
                            + d.mesh_input_map.nbytes) + 4096
    back = pickle.loads(data)
    assert back.label == "run 7"
    assert_same(d, back)


def test_saved_arrays_are_checked(tri):
    """A hand-made or damaged state is refused with ValueError, never read out of bounds."""
    fn, args = tri._mesh.__reduce__()
    assert fn is _gigatet._restore
    fmt, pts, v, t, nb, im, stats, ta, th = args
    fn(*args)  # the untouched tuple is accepted

    def with_(k, value):
        a = list(args)
        a[k] = value
        return a

    bad_t = np.array(t)
    bad_t[5, 2] = v.shape[0]
    bad_nb = np.array(nb)
    bad_nb[9, 1] = t.shape[0]
    bad_im = np.array(im)
    bad_im[0] = 1  # vertex 1 before vertex 0: not in order of first occurrence
    bad_v = np.array(v)
    bad_v[4, 0] = np.nan
    cases = [with_(0, 99), with_(3, bad_t), with_(4, bad_nb), with_(5, bad_im),
             with_(2, bad_v), with_(5, im[:-1]), with_(3, t[:-1]), with_(3, t.astype(np.int64)),
             with_(2, v[:, :2]), with_(1, pts[:, :2])]
    for a in cases:  # a wrong dtype is a TypeError (no casts), anything else a ValueError
        with pytest.raises(TypeError if a[3] is not t and a[3].dtype != np.uint32 else ValueError):
            fn(*a)


def test_round_trip_through_a_spawned_process(tri):
    """As multiprocessing and joblib use it: the object goes to a fresh interpreter (spawn)
    and comes back; the child's results equal the parent's."""
    q = queries(tri)
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(1) as pool:
        found = pool.apply(operator.methodcaller("find_simplex", q), (tri,))
        simplices = pool.apply(operator.attrgetter("simplices"), (tri,))
        back = pool.apply(copy.copy, (tri,))  # pickled there and back
    assert np.array_equal(found, tri.find_simplex(q))
    assert np.array_equal(simplices, tri.simplices)
    assert_same(tri, back)
