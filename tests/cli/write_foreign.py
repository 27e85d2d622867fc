"""write_foreign.py -- rewrite a tet mesh in every variant other tools write, for
test_check_foreign_files.sh.

usage: write_foreign.py MESH.vtu OUTDIR
Reads MESH.vtu (gigatet's own output) with meshio and writes it again with meshio (vtu
ascii/binary, msh 2.2 and 4.1 ascii/binary), VTK's vtkXMLUnstructuredGridWriter (ascii,
inline binary, appended raw and base64, zlib or none, UInt32 or UInt64 headers) and the Gmsh
API (MSH 2.2 and 4.1, ASCII and binary).  Prints one line "FILE TETS" per file written: the
number of tetrahedra the writer was given.
"""
import os
import sys
import warnings

import meshio
import numpy as np


def main():
    src, out = sys.argv[1], sys.argv[2]
    warnings.simplefilter("ignore")
    mesh = meshio.read(src)
    pts = np.asarray(mesh.points, dtype=np.float64)
    tets = np.asarray(mesh.cells_dict["tetra"], dtype=np.int64)
    nt = len(tets)
    written = []

    def done(name):
        written.append(name)

    # meshio
    m = meshio.Mesh(pts, [("tetra", tets)])
    for binary in (False, True):
        tag = "bin" if binary else "ascii"
        meshio.write(os.path.join(out, f"meshio_{tag}.vtu"), m, binary=binary)
        done(f"meshio_{tag}.vtu")
        meshio.write(os.path.join(out, f"meshio_{tag}_22.msh"), m, file_format="gmsh22",
                     binary=binary)
        done(f"meshio_{tag}_22.msh")
        meshio.write(os.path.join(out, f"meshio_{tag}_41.msh"), m, file_format="gmsh",
                     binary=binary)
        done(f"meshio_{tag}_41.msh")
    # a mixed mesh: a triangle and a line besides the tets (skipped by the reader)
    mixed = meshio.Mesh(pts, [("triangle", tets[:3, :3]), ("tetra", tets),
                              ("line", tets[:2, :2])])
    meshio.write(os.path.join(out, "meshio_mixed.vtu"), mixed, binary=True)
    done("meshio_mixed.vtu")
    meshio.write(os.path.join(out, "meshio_mixed_22.msh"), mixed, file_format="gmsh22",
                 binary=True)
    done("meshio_mixed_22.msh")

    # VTK
    import vtk
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(src)
    reader.Update()
    grid = reader.GetOutput()
    variants = [("ascii", "a", None, 32, True), ("binary", "b", None, 32, True),
                ("binary_zlib", "b", "zlib", 32, True), ("binary_zlib64", "b", "zlib", 64, True),
                ("appended_raw", "p", None, 32, False), ("appended_raw_zlib", "p", "zlib", 32, False),
                ("appended_b64", "p", None, 64, True), ("appended_b64_zlib", "p", "zlib", 32, True)]
    for name, mode, comp, hdr, encode in variants:
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetInputData(grid)
        w.SetFileName(os.path.join(out, f"vtk_{name}.vtu"))
        {"a": w.SetDataModeToAscii, "b": w.SetDataModeToBinary, "p": w.SetDataModeToAppended}[mode]()
        if comp is None:
            w.SetCompressorTypeToNone()
        else:
            w.SetCompressorTypeToZLib()
        if hdr == 64:
            w.SetHeaderTypeToUInt64()
        w.SetEncodeAppendedData(1 if encode else 0)
        if w.Write() != 1:
            raise SystemExit(f"vtk could not write {name}")
        done(f"vtk_{name}.vtu")

    # Gmsh API: one discrete volume, node tags shuffled and sparse
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 1)
    gmsh.model.add("foreign")
    vol = gmsh.model.addDiscreteEntity(3)
    rng = np.random.default_rng(5)
    tags = rng.permutation(len(pts)) * 3 + 7
    gmsh.model.mesh.addNodes(3, vol, tags.tolist(), pts.ravel().tolist())
    gmsh.model.mesh.addElementsByType(vol, 4, [], tags[tets].ravel().tolist())
    for version in ("2.2", "4.1"):
        for binary in (0, 1):
            gmsh.option.setNumber("Mesh.MshFileVersion", float(version))
            gmsh.option.setNumber("Mesh.Binary", binary)
            name = f"gmsh_{version}_{'bin' if binary else 'ascii'}.msh"
            gmsh.write(os.path.join(out, name))
            done(name)
    gmsh.finalize()
    for name in written:
        print(name, nt)


main()
