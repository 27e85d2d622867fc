"""readback.py -- read a mesh written by gigatet with an independent reader and check it.

    python3 readback.py LIB MESH POINTS.bin TETS [MESH POINTS.bin TETS ...]

LIB is meshio (.ele, .msh, .vtu), gmsh (.msh) or vtk (.vtu).  POINTS.bin is the input the
mesh was built from, without duplicates, so the vertices must equal it bit for bit and in
order; TETS is the tet count gigatet reported.  Every tet must have a positive volume
(det[b-a, c-a, d-a] > 0, the orientation Gmsh and VTK expect).  Exit 0 on success, 1 with
a message on the first violation.
"""
import struct
import sys

import numpy as np


def load_bin(path):
    with open(path, "rb") as f:
        data = f.read()
    (n,) = struct.unpack_from("<Q", data, 0)
    return np.frombuffer(data, dtype="<f8", count=3 * n, offset=8).reshape(n, 3)


def read_meshio(path):
    import meshio
    m = meshio.read(path)
    tets = [c.data for c in m.cells if c.type == "tetra"]
    others = [c.type for c in m.cells if c.type != "tetra"]
    if others:
        sys.exit("meshio found non-tetra cells %s in %s" % (others, path))
    return np.asarray(m.points, dtype=float), np.concatenate(tets) if tets else np.zeros((0, 4), int)


def read_gmsh(path):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(path)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags)
    pts = np.asarray(coords, dtype=float).reshape(-1, 3)[order]
    tags = np.asarray(tags)[order]
    if not np.array_equal(tags, np.arange(1, len(tags) + 1)):
        sys.exit("gmsh: node tags are not 1..n")
    etags, enodes = gmsh.model.mesh.getElementsByType(4)
    types = gmsh.model.mesh.getElementTypes()
    gmsh.finalize()
    if any(t != 4 for t in types):
        sys.exit("gmsh found element types %s, expected only 4 (tetrahedra)" % list(types))
    return pts, np.asarray(enodes, dtype=np.int64).reshape(-1, 4) - 1


def read_vtk(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if r.GetErrorCode() != 0 or g is None:
        sys.exit("vtk could not read %s" % path)
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    nc = g.GetNumberOfCells()
    types = set(g.GetCellType(i) for i in range(nc))
    if nc and types != {10}:
        sys.exit("vtk found cell types %s, expected {10} (VTK_TETRA)" % types)
    tets = np.zeros((nc, 4), dtype=np.int64)
    ids = vtk.vtkIdList()
    for i in range(nc):
        g.GetCellPoints(i, ids)
        tets[i] = [ids.GetId(k) for k in range(4)]
    return pts, tets


def check(lib, path, points, ntets):
    pts, tets = {"meshio": read_meshio, "gmsh": read_gmsh, "vtk": read_vtk}[lib](path)
    want = load_bin(points)
    if pts.shape != want.shape:
        sys.exit("%s: %s vertices, expected %s" % (lib, pts.shape, want.shape))
    if not np.array_equal(pts.view(np.uint64), want.astype(float).view(np.uint64)):
        bad = np.argwhere(pts.view(np.uint64) != want.astype(float).view(np.uint64))[0]
        sys.exit("%s: vertex coordinates differ from the input, first at %s: %r vs %r"
                 % (lib, bad, pts[tuple(bad)], want[tuple(bad)]))
    if len(tets) != ntets:
        sys.exit("%s: %d tets, gigatet reported %d" % (lib, len(tets), ntets))
    if len(tets) == 0:
        sys.exit("%s: no tets" % lib)
    if tets.min() < 0 or tets.max() >= len(pts):
        sys.exit("%s: vertex index out of range" % lib)
    a, b, c, d = (pts[tets[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)
    if not (vol > 0).all():
        i = int(np.argmin(vol))
        sys.exit("%s: tet %d has volume %r (not positive)" % (lib, i, vol[i] / 6))
    print("%s read %s: %d vertices bit-exact, %d tets, all volumes positive (min %.3g)"
          % (lib, path, len(pts), len(tets), vol.min() / 6))


def main():
    lib, rest = sys.argv[1], sys.argv[2:]
    if not rest or len(rest) % 3:
        sys.exit(__doc__)
    for i in range(0, len(rest), 3):
        check(lib, rest[i], rest[i + 1], int(rest[i + 2]))


if __name__ == "__main__":
    main()
