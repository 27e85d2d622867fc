"""Property tests (hypothesis): small point sets with duplicates, co-spherical and coplanar
subsets, huge and tiny exponents.  check() passes (the exact checker, with the O(n*m)
empty-sphere test), the tets do not depend on the order of the points nor on the threads,
find_simplex is the smallest closed tet containing the point, and bad input raises the
documented exception."""
import numpy as np
import pytest
from hypothesis import assume, event, given
from hypothesis import strategies as st

import gigatet
from conftest import tets_as_coordinates

# Small integer lattices: many coplanar and co-spherical subsets (every lattice point of
# the cube on the sphere of radius sqrt(3) around the origin, say), and exact duplicates.
coord = st.integers(-3, 3)
lattice_point = st.tuples(coord, coord, coord)
# power-of-two scales keep the arithmetic on the lattice exact: denormals, 1, 2^1000
scale_exp = st.sampled_from([-1074, -1060, -540, -30, 0, 1, 30, 500, 1000])


@st.composite
def lattice_sets(draw, min_size=4, max_size=40):
    pts = draw(st.lists(lattice_point, min_size=min_size, max_size=max_size))
    if draw(st.booleans()) and pts:  # repeat some points: exact duplicates
        extra = draw(st.lists(st.sampled_from(pts), max_size=10))
        pts = pts + extra
        order = draw(st.permutations(range(len(pts))))
        pts = [pts[i] for i in order]
    e = draw(scale_exp)
    return np.ldexp(np.array(pts, dtype=np.float64).reshape(-1, 3), e)


@st.composite
def cospherical_sets(draw):
    """Points on the sphere x^2+y^2+z^2 = 9 (the 30 lattice points of radius 3) or 27, plus a
    few others; shifted by a lattice vector."""
    r2 = draw(st.sampled_from([9, 27]))
    sphere = [(x, y, z) for x in range(-5, 6) for y in range(-5, 6) for z in range(-5, 6)
              if x * x + y * y + z * z == r2]
    pick = draw(st.lists(st.sampled_from(sphere), min_size=4, max_size=len(sphere), unique=True))
    others = draw(st.lists(st.tuples(st.integers(-6, 6), st.integers(-6, 6),
                                     st.integers(-6, 6)), max_size=6))
    shift = np.array(draw(lattice_point))
    pts = np.array(pick + others, dtype=np.float64).reshape(-1, 3) + shift
    return np.ldexp(pts, draw(scale_exp))


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@st.composite
def wild_sets(draw):
    """Any finite doubles, huge and tiny exponents mixed, and a few repeated coordinates."""
    n = draw(st.integers(4, 14))
    pool = draw(st.lists(finite, min_size=3, max_size=12))
    vals = draw(st.lists(st.one_of(finite, st.sampled_from(pool)), min_size=3 * n,
                         max_size=3 * n))
    return np.array(vals, dtype=np.float64).reshape(n, 3)


def affine_dimension(pts):
    """Affine dimension of the distinct points, exactly (fractions on the doubles)."""
    from fractions import Fraction
    uniq = np.unique(pts + 0.0, axis=0)   # -0.0 -> 0.0
    if len(uniq) == 0:
        return -1
    rows = [[Fraction(float(c)) for c in (p - 0.0)] for p in uniq]
    base = rows[0]
    m = [[a - b for a, b in zip(r, base)] for r in rows[1:]]
    rank, col = 0, 0
    while m and col < 3:
        piv = next((i for i in range(rank, len(m)) if m[i][col] != 0), None)
        if piv is None:
            col += 1
            continue
        m[rank], m[piv] = m[piv], m[rank]
        for i in range(len(m)):
            if i != rank and m[i][col] != 0:
                f = m[i][col] / m[rank][col]
                m[i] = [a - f * b for a, b in zip(m[i], m[rank])]
        rank += 1
        col += 1
    return rank


def triangulate_or_degenerate(pts, **kw):
    dim = affine_dimension(pts)
    event("affine dimension %d" % dim)
    if dim < 3:
        with pytest.raises(gigatet.DegenerateInputError) as e:
            gigatet.Delaunay(pts, **kw)
        assert e.value.dimension == dim
        assert isinstance(e.value, ValueError)
        return None
    return gigatet.Delaunay(pts, **kw)


def check_mesh(d):
    rep = d.check(full=True)
    assert rep["ok"] and rep["violation"] is None
    assert rep["tets"] == d.nsimplex
    assert d.check(delaunay=True)["mode"] == "delaunay"
    # duplicates: coplanar / duplicates / input_map agree
    dup = d.duplicates
    assert len(dup) == d.npoints - d.nvertices == len(d.coplanar)
    assert (d.points[dup[:, 0]] == d.points[dup[:, 1]]).all()
    assert (dup[:, 1] < dup[:, 0]).all()
    assert (d.vertex_to_simplex[dup[:, 0]] == -1).all()
    assert np.array_equal(d.simplices, d.vertex_input_index[d.mesh_tets])
    used = np.zeros(d.npoints, dtype=bool)
    used[d.simplices.ravel()] = True
    assert np.array_equal(used, d.vertex_to_simplex >= 0)
    assert not used[dup[:, 0]].any()


def same_mesh(a, b):
    assert tets_as_coordinates(a) == tets_as_coordinates(b)


@given(lattice_sets())
def test_lattice_sets(pts):
    d = triangulate_or_degenerate(pts, threads=1)
    if d is None:
        return
    check_mesh(d)
    same_mesh(d, gigatet.Delaunay(pts, threads=2))
    perm = np.random.default_rng(len(pts)).permutation(len(pts))
    same_mesh(d, gigatet.Delaunay(pts[perm]))


@given(cospherical_sets())
def test_cospherical_sets(pts):
    d = triangulate_or_degenerate(pts, threads=2)
    if d is None:
        return
    check_mesh(d)
    same_mesh(d, gigatet.Delaunay(pts[::-1].copy(), threads=1))


@given(wild_sets())
def test_huge_and_tiny_exponents(pts):
    d = triangulate_or_degenerate(pts)
    if d is None:
        return
    check_mesh(d)
    same_mesh(d, gigatet.Delaunay(pts[::-1], threads=1))


def brute_force_locate(d, q):
    """The smallest tet whose closed tet contains q (exact), -1 if none."""
    p = d.points
    x = tuple(q)
    for t, (a, b, c, e) in enumerate(d.simplices):
        a, b, c, e = tuple(p[a]), tuple(p[b]), tuple(p[c]), tuple(p[e])
        if min(gigatet.orient3d(x, b, c, e), gigatet.orient3d(a, x, c, e),
               gigatet.orient3d(a, b, x, e), gigatet.orient3d(a, b, c, x)) >= 0:
            return t
    return -1


@given(lattice_sets(max_size=25), st.lists(st.tuples(st.integers(-8, 8), st.integers(-8, 8),
                                                     st.integers(-8, 8)), max_size=12))
def test_find_simplex_smallest_closed_tet(pts, halves):
    """Queries on vertices, edges, facets (half-lattice points) and outside: the answer is
    the smallest tet containing the point, whatever the walk."""
    d = triangulate_or_degenerate(pts)
    if d is None:
        return
    q = np.concatenate([d.points, np.ldexp(np.array(halves, dtype=np.float64).reshape(-1, 3),
                                           -1) * np.abs(d.points).max()])
    got = d.find_simplex(q)
    want = [brute_force_locate(d, x) for x in q]
    assert got.tolist() == want
    # and not on the order of queries (the walk starts where the last one ended)
    assert d.find_simplex(q[::-1]).tolist() == want[::-1]


@given(lattice_sets(min_size=5), st.data())
def test_nonfinite_named(pts, data):
    i = data.draw(st.integers(0, len(pts) - 1))
    k = data.draw(st.integers(0, 2))
    bad = pts.copy()
    bad[i, k] = data.draw(st.sampled_from([np.nan, np.inf, -np.inf]))
    with pytest.raises(ValueError) as e:
        gigatet.Delaunay(bad)
    assert not isinstance(e.value, gigatet.DegenerateInputError)
    assert e.value.index == i
    assert ("point %d " % i) in str(e.value)


@given(st.lists(st.tuples(coord, coord), min_size=0, max_size=30), scale_exp,
       st.sampled_from(["z", "x", "tilted", "line", "point"]))
def test_degenerate_raises(pts2, e, kind):
    a = np.array(pts2, dtype=np.float64).reshape(-1, 2)
    if kind == "z":
        pts = np.column_stack([a, np.full(len(a), 2.0)])
    elif kind == "x":
        pts = np.column_stack([np.full(len(a), -1.0), a])
    elif kind == "tilted":      # the plane x + y + z = 0
        pts = np.column_stack([a, -a.sum(axis=1)])
    elif kind == "line":
        pts = np.column_stack([a[:, 0], 2 * a[:, 0], -a[:, 0]])
    else:
        pts = np.zeros((len(a), 3)) + 1.0
    pts = np.ldexp(pts, e)
    dim = affine_dimension(pts)
    assume(dim < 3)
    with pytest.raises(gigatet.DegenerateInputError) as err:
        gigatet.Delaunay(pts)
    assert err.value.dimension == dim
    if dim >= 0:
        assert ("dimension %d" % dim) in str(err.value)
