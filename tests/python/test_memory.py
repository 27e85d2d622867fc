"""No leaks: build and free many meshes (every attribute, method and error path used) and
watch the process's resident memory."""
import ctypes
import gc

import numpy as np
import pytest

import gigatet


def rss_bytes():
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * 4096


def settle():
    gc.collect()
    try:  # give freed heap back to the system so that RSS measures what is live
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):  # pragma: no cover
        pass
    return rss_bytes()


def one_cycle(rng, tmp_path):
    p = rng.random((10000, 3))
    p[-100:] = p[:100]  # duplicates
    d = gigatet.Delaunay(p, threads=2)
    for name in ("simplices", "neighbors", "vertex_to_simplex", "convex_hull",
                 "vertex_neighbor_vertices", "transform", "equations", "coplanar",
                 "duplicates", "input_map", "vertex_input_index", "stats", "min_bound"):
        getattr(d, name)
    d.find_simplex(rng.random((2000, 3)) * 1.2 - 0.1)
    d.plane_distance(p[:10])
    d.check()
    d.write(tmp_path / "m.vtu")
    views = d._mesh.views()
    del d, views
    for bad in (np.array([[0.0, 0, 0], [1, 0, 0], [np.nan, 0, 0], [0, 0, 1]]),
                np.zeros((10, 3)), np.zeros((0, 3))):
        with pytest.raises(ValueError):
            gigatet.Delaunay(bad)
    with pytest.raises(OSError):
        gigatet.Delaunay(p[:50]).write(tmp_path / "missing" / "m.vtu")


def test_no_leak(tmp_path):
    rng = np.random.default_rng(0)
    for _ in range(3):
        one_cycle(rng, tmp_path)
    before = settle()
    cycles = 20
    for _ in range(cycles):
        one_cycle(rng, tmp_path)
    growth = settle() - before
    # one leaked mesh of 10k points is about 2.5 MB (its tets and neighbours alone): 20 leaked
    # meshes would be 50 MB
    assert growth < 8 * 2**20, "RSS grew by %.1f MB over %d cycles" % (growth / 2**20, cycles)
