"""gigatet.Delaunay against scipy.spatial.Delaunay (Qhull) on random points, where the
Delaunay tetrahedrization is unique: the same simplices, neighbours, hull and vertex
neighbours as sets; find_simplex agrees away from facets; transform interpolates linear
functions exactly to rounding."""
import numpy as np
import pytest

import gigatet
from conftest import sorted_rows

spatial = pytest.importorskip("scipy.spatial")

SIZES = [10, 25, 60, 150, 400, 1000, 3000, 8000, 20000, 50000]
CASES = list(enumerate(SIZES))  # 10 seeds, 10-50k points


def match(g, s):
    """g2s[t]: scipy's index of gigatet's tet t (the same vertex set)."""
    kg = np.sort(g.simplices, axis=1)
    ks = np.sort(s.simplices, axis=1)
    og = np.lexsort(kg.T[::-1])
    os_ = np.lexsort(ks.T[::-1])
    assert np.array_equal(kg[og], ks[os_]), "simplices differ as sets"
    g2s = np.empty(len(og), dtype=np.intp)
    g2s[og] = os_
    return g2s


@pytest.fixture(scope="module", params=CASES, ids=["seed%d-n%d" % c for c in CASES])
def pair(request):
    seed, n = request.param
    pts = np.random.default_rng(seed).random((n, 3))
    return pts, gigatet.Delaunay(pts, threads=2), spatial.Delaunay(pts)


def test_simplices_same_set(pair):
    pts, g, s = pair
    assert g.nsimplex == s.nsimplex and g.npoints == s.npoints == len(pts)
    assert g.simplices.dtype == np.intp and g.simplices.shape == (g.nsimplex, 4)
    match(g, s)
    assert np.array_equal(g.points, pts)
    assert g.ndim == 3
    np.testing.assert_array_equal(g.min_bound, s.min_bound)
    np.testing.assert_array_equal(g.max_bound, s.max_bound)


def test_positive_orientation(pair):
    pts, g, _ = pair
    v = pts[g.simplices]
    det = np.linalg.det(v[:, 1:] - v[:, :1])
    # floating point is enough on random points; a sample is checked exactly
    assert (det > 0).all()
    for t in g.simplices[:: max(1, g.nsimplex // 50)]:
        assert gigatet.orient3d(*[tuple(pts[i]) for i in t]) == 1


def test_neighbors_same(pair):
    _, g, s = pair
    g2s = match(g, s)
    assert g.neighbors.dtype == np.intp and g.neighbors.shape == (g.nsimplex, 4)
    # gigatet's neighbour opposite vertex v of tet t is scipy's opposite v in the same tet
    t, k = np.nonzero(np.ones_like(g.neighbors, dtype=bool))
    v = g.simplices[t, k]
    st = g2s[t]
    pos = np.argmax(s.simplices[st] == v[:, None], axis=1)
    assert (s.simplices[st, pos] == v).all()
    gn = g.neighbors[t, k]
    expect = np.where(gn >= 0, g2s[np.maximum(gn, 0)], -1)
    assert np.array_equal(s.neighbors[st, pos], expect)


def test_hull_same(pair):
    pts, g, s = pair
    assert g.convex_hull.dtype == np.intp
    assert np.array_equal(sorted_rows(g.convex_hull), sorted_rows(s.convex_hull))
    # outward: the hull facets are counter-clockwise seen from outside
    c = pts.mean(axis=0)
    f = pts[g.convex_hull]
    normal = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
    assert (np.einsum("ij,ij->i", normal, f[:, 0] - c) > 0).all()


def test_vertex_neighbor_vertices_same(pair):
    _, g, s = pair

    gi, gx = g.vertex_neighbor_vertices
    assert gi.dtype == np.intp and gx.dtype == np.intp and len(gi) == g.npoints + 1
    a = np.stack([np.repeat(np.arange(g.npoints), np.diff(gi)), gx], axis=1)
    si, sx = s.vertex_neighbor_vertices
    b = np.stack([np.repeat(np.arange(s.npoints), np.diff(si)), sx], axis=1)
    a = a[np.lexsort(a.T[::-1])]
    b = b[np.lexsort(b.T[::-1])]
    assert np.array_equal(a, b)
    # each list ascending
    for k in range(0, g.npoints, max(1, g.npoints // 100)):
        seg = gx[gi[k]:gi[k + 1]]
        assert (np.diff(seg) > 0).all()


def test_vertex_to_simplex(pair):
    _, g, _ = pair
    v2s = g.vertex_to_simplex
    assert v2s.dtype == np.intp and (v2s >= 0).all()
    assert (g.simplices[v2s] == np.arange(g.npoints)[:, None]).any(axis=1).all()
    # the smallest tet of each vertex
    first = np.full(g.npoints, g.nsimplex)
    np.minimum.at(first, g.simplices.ravel(), np.repeat(np.arange(g.nsimplex), 4))
    assert np.array_equal(v2s, first)


def test_find_simplex_agrees(pair):
    pts, g, s = pair
    g2s = match(g, s)
    rng = np.random.default_rng(7)
    q = rng.uniform(-0.2, 1.2, size=(2000, 3))
    rg = g.find_simplex(q)
    rs = s.find_simplex(q)
    assert rg.dtype == np.intp and rg.shape == (2000,)
    # away from facets: scipy's barycentric coordinates all clearly positive
    inside = rs >= 0
    tr = s.transform[rs[inside]]
    c = np.einsum("ijk,ik->ij", tr[:, :3, :], q[inside] - tr[:, 3, :])
    bary = np.concatenate([c, 1 - c.sum(axis=1, keepdims=True)], axis=1)
    clear = bary.min(axis=1) > 1e-9
    idx = np.flatnonzero(inside)[clear]
    assert (rg[idx] >= 0).all()
    assert np.array_equal(g2s[rg[idx]], rs[idx])
    # clearly outside the hull (outside the unit cube): both -1
    out = (q < -1e-9).any(axis=1) | (q > 1 + 1e-9).any(axis=1)
    assert (rg[out] == -1).all() and (rs[out] == -1).all()
    # gigatet's answers are exact: each point is in its closed tet (a sample, exactly)
    for i in range(0, len(q), 40):
        t = rg[i]
        if t < 0:
            continue
        a, b, cc, d = (tuple(pts[j]) for j in g.simplices[t])
        x = tuple(q[i])
        assert min(gigatet.orient3d(x, b, cc, d), gigatet.orient3d(a, x, cc, d),
                   gigatet.orient3d(a, b, x, d), gigatet.orient3d(a, b, cc, x)) >= 0


def test_find_simplex_shapes(pair):
    pts, g, _ = pair
    assert g.find_simplex(pts[0]).shape == ()
    assert g.find_simplex(pts[:6].reshape(2, 3, 3)).shape == (2, 3)
    assert g.find_simplex(np.empty((0, 3))).shape == (0,)
    assert g.find_simplex([[np.nan, 0, 0], [np.inf, 0.5, 0.5]]).tolist() == [-1, -1]
    assert g.find_simplex(pts[:4].astype(np.float32)).shape == (4,)


def test_transform_barycentric_exact_to_rounding(pair):
    pts, g, s = pair
    assert g.transform.shape == (g.nsimplex, 4, 3)
    rng = np.random.default_rng(3)
    t = rng.integers(0, g.nsimplex, 500)
    w = rng.dirichlet(np.ones(4), 500)
    x = np.einsum("ij,ijk->ik", w, pts[g.simplices[t]])
    T = g.transform[t]
    c = np.einsum("ijk,ik->ij", T[:, :3, :], x - T[:, 3, :])
    bary = np.concatenate([c, 1 - c.sum(axis=1, keepdims=True)], axis=1)
    coef, off = np.array([1.5, -2.0, 0.75]), 0.25
    f = pts @ coef + off
    interp = (bary * f[g.simplices[t]]).sum(axis=1)
    exact = x @ coef + off
    # rounding of the inverse grows with the tet's condition number: scale the tolerance
    cond = np.linalg.cond(T[:, :3, :])
    assert (np.abs(interp - exact) <= 1e-13 * (1 + cond) * (1 + np.abs(exact))).all()
    # the same as scipy's barycentric coordinates, up to the vertex order
    g2s = match(g, s)
    Ts = s.transform[g2s[t]]
    cs = np.einsum("ijk,ik->ij", Ts[:, :3, :], x - Ts[:, 3, :])
    bs = np.concatenate([cs, 1 - cs.sum(axis=1, keepdims=True)], axis=1)
    vs = s.simplices[g2s[t]]
    order = np.argsort(vs, axis=1)
    mine = np.take_along_axis(bary, np.argsort(g.simplices[t], axis=1), axis=1)
    theirs = np.take_along_axis(bs, order, axis=1)
    assert np.allclose(mine, theirs, atol=1e-9 * (1 + cond[:, None]))


def test_plane_distance_and_equations(pair):
    pts, g, s = pair
    eq = g.equations
    assert eq.shape == (g.nsimplex, 5)
    assert np.allclose(np.linalg.norm(eq[:, :4], axis=1), 1)
    assert (eq[:, 3] < 0).all()
    # a tet's own vertices lie on its hyperplane; a query inside a tet's circumsphere has a
    # positive distance to it (scipy's convention), and scipy's sign agrees
    m = min(50, g.nsimplex)
    z = g.lift_points(pts[g.simplices[:m]])
    dist = np.einsum("ijk,ik->ij", z, eq[:m, :4]) + eq[:m, 4:5]
    scale = np.abs(z).max() + 1
    assert np.abs(dist).max() <= 1e-9 * scale
    x = pts[g.simplices[:m]].mean(axis=1)   # centroids: inside the circumsphere
    pd = g.plane_distance(x)
    assert pd.shape == (m, g.nsimplex)
    assert (pd[np.arange(m), np.arange(m)] > 0).all()
    ps = s.plane_distance(x)
    g2s = match(g, s)
    assert (ps[np.arange(m), g2s[:m]] > 0).all()
