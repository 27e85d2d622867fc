"""The interface: input conversion, dtypes and shapes, zero-copy views kept alive by the
Delaunay object, duplicates, the GIL released, errors, stats, write() and to_meshio()."""
import gc
import os
import threading
import time

import numpy as np
import pytest

import gigatet


def coord_set(points, tets):
    """A mesh as the sorted list of its tets' sorted vertex coordinates."""
    return sorted(tuple(sorted(map(tuple, points[t]))) for t in tets)


def cube_points(n=2000, seed=5):
    return np.random.default_rng(seed).random((n, 3))


def test_any_float_dtype_and_layout():
    p = cube_points(500)
    ref = gigatet.Delaunay(p)
    for q in (np.asfortranarray(p), p.astype(">f8"), np.repeat(p, 2, axis=0)[::2]):
        d = gigatet.Delaunay(q)
        assert np.array_equal(d.simplices, ref.simplices)
        assert d.points.flags.c_contiguous and d.points.dtype == np.float64
    # float32, float16, longdouble, ints, lists: converted once to float64
    for q in (p.astype(np.float32), p.astype(np.longdouble), (p * 1000).astype(np.int64),
              p.tolist()):
        d = gigatet.Delaunay(q)
        assert d.points.dtype == np.float64
        assert np.array_equal(d.points, np.asarray(q, dtype=np.float64))
        d.check()
    # a float64 C-contiguous input is used as is (no copy), as scipy does
    assert gigatet.Delaunay(p).points is p
    # numbers held as objects (ints past 2**64, Fractions, Decimals): converted, as scipy
    # does; before, "points must be real numbers, not object"
    from decimal import Decimal
    from fractions import Fraction
    q = [[Fraction(1, 3), 0, 0], [0, Decimal("0.5"), 0], [0, 0, 2**70], [1, 1, 1], [0, 0, 0]]
    d = gigatet.Delaunay(q)
    assert np.array_equal(d.points, np.array([[1 / 3, 0, 0], [0, 0.5, 0], [0, 0, 2.0**70],
                                              [1, 1, 1], [0, 0, 0]]))
    assert np.array_equal(gigatet.Delaunay(p.astype(object)).simplices, ref.simplices)
    for bad in ([[0, 0, "1"]] + q[1:], [[0, 0, None]] + q[1:], [[0, 0, 1j]] + q[1:]):
        with pytest.raises(TypeError, match="real numbers"):
            gigatet.Delaunay(np.array(bad, dtype=object))


def test_bad_shapes_and_types():
    with pytest.raises(ValueError):
        gigatet.Delaunay(np.zeros((10, 2)))
    with pytest.raises(ValueError):
        gigatet.Delaunay(np.zeros(12))
    with pytest.raises(ValueError):
        gigatet.Delaunay(np.zeros((2, 4, 3)))
    with pytest.raises(TypeError):
        gigatet.Delaunay(np.zeros((10, 3), dtype=complex))
    with pytest.raises(TypeError):
        gigatet.Delaunay([["a", "b", "c"]] * 5)
    with pytest.raises(ValueError):
        gigatet.Delaunay(cube_points(10), threads=-1)
    with pytest.raises(TypeError):
        gigatet.Delaunay(cube_points(10), threads=1.5)
    # counts past the kernel's 255 mean 255, however large (2**31 raised OverflowError)
    ref = gigatet.Delaunay(cube_points(10), threads=1)
    for many in (256, 2**31, 10**30):
        d = gigatet.Delaunay(cube_points(10), threads=many)
        assert d.nsimplex == ref.nsimplex


def test_errors():
    p = cube_points(100)
    p[37, 1] = np.nan
    with pytest.raises(ValueError, match="point 37 ") as e:
        gigatet.Delaunay(p)
    assert e.value.index == 37
    with pytest.raises(gigatet.DegenerateInputError) as e:
        gigatet.Delaunay(np.zeros((0, 3)))
    assert e.value.dimension == -1
    for dim, pts in ((0, [[1, 2, 3]] * 5), (1, [[i, 2 * i, 3] for i in range(6)]),
                     (2, [[i, j, 7] for i in range(4) for j in range(3)])):
        with pytest.raises(gigatet.DegenerateInputError, match="dimension %d" % dim) as e:
            gigatet.Delaunay(pts)
        assert e.value.dimension == dim
        assert isinstance(e.value, ValueError)
    assert issubclass(gigatet.DegenerateInputError, ValueError)
    assert issubclass(gigatet.CheckError, RuntimeError)


def test_scipy_keywords():
    """NOTES.md E154: scipy's keyword arguments are accepted (code written for
    scipy.spatial.Delaunay runs); qhull_options is ignored (the result is exact), the
    furthest-site and incremental modes are refused with NotImplementedError."""
    p = cube_points(200)
    ref = gigatet.Delaunay(p)
    for kw in ({"qhull_options": "Qbb Qc Qz Q12"}, {"qhull_options": "QJ"},
               {"qhull_options": b"Qt"}, {"qhull_options": None},
               {"furthest_site": False, "incremental": False}):
        assert np.array_equal(gigatet.Delaunay(p, **kw).simplices, ref.simplices), kw
    for kw in ({"furthest_site": True}, {"incremental": True}):
        with pytest.raises(NotImplementedError, match=next(iter(kw))):
            gigatet.Delaunay(p, **kw)
    with pytest.raises(TypeError, match="qhull_options"):
        gigatet.Delaunay(p, qhull_options=7)


def test_memory_limit():
    """The memory guard: a limit the run cannot fit raises MemoryError at once, naming it;
    "off" and a large value run; bad values are ValueError."""
    pts = np.random.default_rng(5).random((2000, 3))
    with pytest.raises(MemoryError, match="needs about .* available \\(the memory_limit option\\)"):
        gigatet.Delaunay(pts, memory_limit=1 << 20)
    n = gigatet.Delaunay(pts).nsimplex
    assert gigatet.Delaunay(pts, memory_limit="off").nsimplex == n
    assert gigatet.Delaunay(pts, memory_limit=1 << 34).nsimplex == n
    assert gigatet.Delaunay(pts, memory_limit=10**30).nsimplex == n   # was OverflowError
    for bad in (0, -5, "on"):
        with pytest.raises((ValueError, TypeError)):
            gigatet.Delaunay(pts, memory_limit=bad)


def test_views_are_zero_copy_and_keep_the_mesh_alive():
    p = cube_points(3000)
    d = gigatet.Delaunay(p)
    v, t, nb, im = d.mesh_vertices, d.mesh_tets, d.mesh_neighbors, d.mesh_input_map
    assert v.dtype == np.float64 and v.shape == (d.nvertices, 3)
    assert t.dtype == np.uint32 and t.shape == (d.nsimplex, 4)
    assert nb.dtype == np.uint32 and nb.shape == (d.nsimplex, 4)
    assert im.dtype == np.uint32 and im.shape == (d.npoints,)
    for a in (v, t, nb, im):
        assert not a.flags.writeable and not a.flags.owndata
        assert isinstance(a.base, gigatet._gigatet.Mesh)
    assert np.array_equal(nb == d.NO_TET, d.neighbors == -1)
    assert np.array_equal(np.where(nb == d.NO_TET, -1, nb.astype(np.intp)), d.neighbors)
    assert np.array_equal(v, p)  # no duplicates: the vertices are the points
    # the views outlive the Delaunay object
    expect = t.copy()
    del d
    gc.collect()
    junk = [np.ones(100000) for _ in range(20)]  # reuse freed memory if it was freed
    assert np.array_equal(t, expect)
    del junk
    # results are cached and read-only
    d = gigatet.Delaunay(p)
    assert d.simplices is d.simplices
    with pytest.raises(ValueError):
        d.simplices[0, 0] = 1


def test_duplicates_index_the_input_points():
    base = cube_points(200)
    p = np.concatenate([base, base[[5, 7, 5]], [[-0.0 + base[9, 0], base[9, 1], base[9, 2]]]])
    p[0] = [0.0, 0.5, 0.5]
    p = np.concatenate([p, [[-0.0, 0.5, 0.5]]])  # -0.0 == +0.0: a duplicate of point 0
    d = gigatet.Delaunay(p)
    n = len(p)
    assert d.npoints == n and d.nvertices == 200
    assert d.duplicates.tolist() == [[200, 5], [201, 7], [202, 5], [203, 9], [204, 0]]
    assert d.coplanar[:, 0].tolist() == [200, 201, 202, 203, 204]
    assert d.coplanar[:, 2].tolist() == [5, 7, 5, 9, 0]
    for row in d.coplanar:
        assert row[2] in d.simplices[row[1]]
    assert d.simplices.max() < 200
    assert np.array_equal(d.input_map[:200], np.arange(200))
    assert d.input_map[200:].tolist() == [5, 7, 5, 9, 0]
    assert (d.vertex_to_simplex[200:] == -1).all()
    indptr, _ = d.vertex_neighbor_vertices
    assert (np.diff(indptr)[200:] == 0).all()
    assert d.stats["duplicates"] == 5
    d.check()
    # with duplicates before the first occurrence of others, ids still index the input
    q = np.concatenate([base[:3], base[:3], base[3:]])
    e = gigatet.Delaunay(q)
    assert e.vertex_input_index.tolist()[:5] == [0, 1, 2, 6, 7]
    assert set(np.unique(e.simplices)) <= set(range(len(q))) - {3, 4, 5}
    assert coord_set(e.points, e.simplices) == coord_set(base, gigatet.Delaunay(base).simplices)


def test_threads_and_determinism():
    p = cube_points(20000)
    a = gigatet.Delaunay(p, threads=1)
    b = gigatet.Delaunay(p, threads=2)
    c = gigatet.Delaunay(p)
    assert a.stats["threads"] == 1 and b.stats["threads"] == 2
    for x in (b, c):
        assert np.array_equal(np.sort(np.sort(a.simplices, 1), 0), np.sort(np.sort(x.simplices, 1), 0))


def test_threads_the_system_will_not_start():
    """NOTES.md E183: under a limit on threads (GTET_THREAD_SHIM, tests/threads.cmake: an
    LD_PRELOAD that fails pthread_create past 2 live threads) the run uses the threads it can
    start, warns, and gives the same tets; libgomp ended the interpreter with exit 1 before."""
    import subprocess
    import sys
    shim = os.environ.get("GTET_THREAD_SHIM")
    if not shim or not os.path.exists(shim):
        pytest.skip("GTET_THREAD_SHIM (tests/threads.cmake) not set")
    code = """if True:
        import warnings
        import numpy as np, gigatet
        p = np.random.default_rng(2).random((100000, 3))  # validate's regions start threads
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            d = gigatet.Delaunay(p, threads=8)
        assert d.stats["threads"] == 3 == d._mesh.threads, d.stats["threads"]
        msgs = [str(x.message) for x in w if x.category is RuntimeWarning]
        assert msgs and "ran on 3 of the 8 threads asked for" in msgs[0], msgs
        # again in the same process: libgomp's pool holds 2 threads now, which a new probe
        # would count against the limit and find room for none
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            again = gigatet.Delaunay(p, threads=8)
        assert again.stats["threads"] == 3, again.stats["threads"]
        ref = gigatet.Delaunay(p, threads=1)
        key = lambda s: sorted(map(tuple, np.sort(s, axis=1)))
        assert key(d.simplices) == key(ref.simplices)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            gigatet.Delaunay(p)  # threads=0: as many as can run, no warning
        print("ok")
    """
    env = dict(os.environ, LD_PRELOAD=shim, GTET_SHIM_MAX_LIVE="2", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120, env=env)
    assert r.returncode == 0 and r.stdout.strip() == "ok", (r.returncode, r.stdout, r.stderr)


def test_check_and_stats():
    d = gigatet.Delaunay(cube_points(300), check=True)
    rep = d.check(full=True)
    assert rep["ok"] and rep["mode"] == "canonical" and rep["euler"] == 1
    assert rep["tets"] == d.nsimplex and rep["hull_facets"] == len(d.convex_hull)
    s = d.stats
    for key in ("points", "vertices", "duplicates", "tets", "hull_facets", "threads",
                "tets_per_second", "seconds", "bytes_per_tet", "kernel_peak_bytes",
                "tets_created", "walk_steps", "predicates", "num_rounds", "rounds"):
        assert key in s
    assert set(s["seconds"]) >= {"validate", "sort", "insert", "finalize", "kernel"}
    assert s["tets"] == d.nsimplex and len(s["rounds"]) == s["num_rounds"]
    assert s["predicates"]["orient_calls"] > 0 and len(s["predicates"]["sos_depth"]) == 4
    # the counters of gtet_pred_counters, as the CLI's --stats prints them (src/cli/json.c)
    assert set(s["predicates"]) == {
        "orient_calls", "orient_exact", "orient_int", "orient_gmp", "orient_zero",
        "insphere_calls", "insphere_exact", "insphere_int", "insphere_int122", "insphere_gmp",
        "insphere_zero", "sos_calls", "sos_depth"}


def test_write_every_format(tmp_path):
    d = gigatet.Delaunay(cube_points(400))
    for ext in (".ele", ".msh", ".vtu"):
        path = tmp_path / ("mesh" + ext)
        d.write(path)
        assert path.stat().st_size > 0
    assert (tmp_path / "mesh.node").exists()
    with pytest.raises(ValueError):
        d.write(tmp_path / "mesh.xyz")
    with pytest.raises(OSError):
        d.write(tmp_path / "no" / "such" / "dir.vtu")
    meshio = pytest.importorskip("meshio")
    for ext in (".ele", ".msh", ".vtu"):
        m = meshio.read(str(tmp_path / ("mesh" + ext)))
        tets = m.cells_dict["tetra"]
        assert len(tets) == d.nsimplex
        assert coord_set(m.points, tets) == coord_set(d.points, d.simplices)


def test_write_ignores_a_decimal_comma_locale(tmp_path):
    """NOTES.md E159f: under locale.setlocale(LC_ALL, "de_DE.UTF-8") write() printed
    coordinates as 0,5118... (the C library's %g follows LC_NUMERIC): files every reader
    rejects or misreads, written with success.  The locale is compiled into tmp_path with
    localedef (libc-bin); a child process sets it, since setlocale is process-wide."""
    import shutil
    import subprocess
    import sys
    loc = tmp_path / "loc"
    loc.mkdir()
    if not shutil.which("localedef") or not os.path.isdir("/usr/share/i18n/locales"):
        pytest.skip("LOUDLY: no localedef or locale sources to build de_DE.UTF-8")
    r = subprocess.run(["localedef", "-i", "de_DE", "-f", "UTF-8", str(loc / "de_DE.UTF-8")],
                       capture_output=True, text=True)
    if not (loc / "de_DE.UTF-8").exists():
        pytest.skip("LOUDLY: localedef could not build de_DE.UTF-8: %s" % r.stderr[-300:])
    code = """if True:
        import locale, sys, numpy as np, gigatet
        locale.setlocale(locale.LC_ALL, "de_DE.UTF-8")
        assert locale.localeconv()["decimal_point"] == ","
        d = gigatet.Delaunay(np.random.default_rng(1).random((50, 3)))
        for ext in (".vtu", ".ele", ".msh"):
            d.write(sys.argv[1] + "/m" + ext)
        print("ok")
    """
    env = dict(os.environ, LOCPATH=str(loc))
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True,
                       text=True, env=env, timeout=60)
    assert r.returncode == 0 and r.stdout.strip() == "ok", (r.stdout, r.stderr)
    for name in ("m.vtu", "m.node", "m.msh"):
        text = (tmp_path / name).read_text()
        assert "," not in text, "%s has a decimal comma: %s" % (name, text[:300])
    meshio = pytest.importorskip("meshio")
    m = meshio.read(str(tmp_path / "m.vtu"))
    assert np.array_equal(np.sort(m.points, axis=0),
                          np.sort(np.random.default_rng(1).random((50, 3)), axis=0))


def test_to_meshio():
    meshio = pytest.importorskip("meshio")
    d = gigatet.Delaunay(cube_points(100))
    m = d.to_meshio()
    assert isinstance(m, meshio.Mesh)
    assert np.array_equal(m.points, d.points)
    assert np.array_equal(m.cells_dict["tetra"], d.simplices)


def test_gil_released():
    """Another Python thread runs while the kernel works."""
    p = cube_points(400000, seed=1)
    done = threading.Event()
    result = {}

    def work():
        result["d"] = gigatet.Delaunay(p, threads=1)
        done.set()

    th = threading.Thread(target=work)
    ticks = 0
    th.start()
    time.sleep(0.05)
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    th.join()
    # with the GIL held for the whole run, this thread could not have looped
    assert ticks > 50, ticks
    assert result["d"].nsimplex > 0


def test_orient3d_insphere_exact():
    a, b, c, d = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
    assert gigatet.orient3d(a, b, c, d) == 1
    assert gigatet.orient3d(a, c, b, d) == -1
    assert gigatet.orient3d(a, b, c, (0.5, 0.5, 0)) == 0
    assert gigatet.insphere(a, b, c, d, (1, 1, 1)) == 0
    assert gigatet.insphere(a, b, c, d, (0.2, 0.2, 0.2)) == 1
    tiny = 2.0 ** -1074
    assert gigatet.orient3d((0, 0, 0), (tiny, 0, 0), (0, tiny, 0), (0, 0, tiny)) == 1


def test_predicates_refuse_nan_and_inf():
    """NOTES.md E159b: a NaN or infinite coordinate reached GMP's mpz_set_d, which raises
    SIGFPE: the interpreter died.  Run in a child so that the old crash fails the test."""
    import subprocess
    import sys
    code = """if True:
        import gigatet
        a, b, c, d, e = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)
        for bad in (float("nan"), float("inf"), -float("inf")):
            for k in range(5):
                pts = [list(p) for p in (a, b, c, d, e)]
                pts[k][k % 3] = bad
                for f, m in ((gigatet.orient3d, 4), (gigatet.insphere, 5)):
                    if k >= m:
                        continue
                    try:
                        f(*pts[:m])
                    except ValueError as err:
                        assert "point %d has" % k in str(err), err
                    else:
                        raise SystemExit("no ValueError for %r" % (pts[:m],))
        print("ok")
    """
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and r.stdout.strip() == "ok", (r.returncode, r.stdout, r.stderr)
