"""On grids and co-spherical sets, where Qhull joggles or fails, gigatet.Delaunay's simplices
equal CGAL's tet for tet (tests/cgal/cgal_dt: CGAL's Delaunay_triangulation_3 with the same
symbolic perturbation, printing its tets with the same ids: the input index of each point's
first occurrence).  Runs when GTET_CGAL_DT names the program (tests/python.cmake sets it when
the CGAL tests are built)."""
import os
import subprocess

import numpy as np
import pytest

import gigatet

CGAL_DT = os.environ.get("GTET_CGAL_DT")
pytestmark = pytest.mark.skipif(not CGAL_DT or not os.access(CGAL_DT, os.X_OK),
                                reason="GTET_CGAL_DT (tests/cgal's cgal_dt) not given")


def cgal_tets(pts, tmp_path):
    path = tmp_path / "pts.bin"
    with open(path, "wb") as f:
        f.write(np.uint64(len(pts)).tobytes())
        f.write(np.ascontiguousarray(pts, dtype="<f8").tobytes())
    out = subprocess.run([CGAL_DT, str(path)], check=True, capture_output=True, text=True).stdout
    rows = [list(map(int, line.split())) for line in out.splitlines()
            if line and not line.startswith("#")]
    return np.array(rows, dtype=np.intp).reshape(-1, 4)


def canonical(simplices):
    a = np.sort(simplices, axis=1)
    return a[np.lexsort(a.T[::-1])]


def grid(k):
    r = np.arange(k, dtype=np.float64)
    return np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)


def cospherical():
    pts = [(x, y, z) for x in range(-5, 6) for y in range(-5, 6) for z in range(-5, 6)
           if x * x + y * y + z * z in (9, 25)]
    return np.array(pts, dtype=np.float64)


SETS = {
    "grid6": lambda: grid(6),
    "grid10-shuffled": lambda: grid(10)[np.random.default_rng(1).permutation(1000)],
    "cospherical-shells": cospherical,
    "grid5-with-duplicates": lambda: np.concatenate([grid(5), grid(5)[::7], [[-0.0, 0, 0]]]),
    "tiny-grid": lambda: np.ldexp(grid(4), -1070),
}


@pytest.mark.parametrize("name", sorted(SETS))
def test_equals_cgal(name, tmp_path):
    pts = SETS[name]()
    d = gigatet.Delaunay(pts, threads=2)
    assert np.array_equal(canonical(d.simplices), canonical(cgal_tets(pts, tmp_path)))
    d.check()
