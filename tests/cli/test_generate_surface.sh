#!/usr/bin/env bash
# test_generate_surface.sh -- `gigatet generate surface N --mesh FILE`: the count, every
# sample on the mesh (distance to the nearest triangle's plane <= 1e-12 of the mesh's size,
# and inside the triangle's box), determinism per seed, .off and .ply meshes, bad mesh files
# (exit 2 with a message) and misuse (exit 1); then a sample of a real scanned mesh from
# Debian's CGAL data (libcgal-demo), triangulated with --check (skipped with a message when
# the data is not installed).
. "$(dirname "$0")/common.sh"
cd "$W"
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

# A tetrahedron with slanted faces (four triangles), and the unit cube as OFF quads (fanned
# by the reader).
cat > tet.off <<'EOF'
OFF
# a slanted tetrahedron
4 4 0
1 2 3
4 1 2
2 5 1.5
3 3 6
3 0 2 1
3 0 1 3
3 1 2 3
3 0 3 2
EOF
cat > cube.off <<'EOF'
OFF 8 6 12
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 1 2 6 5
4 2 3 7 6
4 3 0 4 7
EOF
# the same cube as an ascii PLY with faces
{
    printf 'ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\n'
    printf 'property double z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n'
    sed -n '2,9p' cube.off
    sed -n '10,15p' cube.off
} > cube.ply

# on_surface MESH.off POINTS.xyz N: every point within 1e-12 * size of some triangle's plane
# and inside that triangle's bounding box (widened by the same tolerance); exactly N points.
on_surface() {
    "$PY" - "$1" "$2" "$3" <<'PYEOF'
import sys
tok = [l.split('#')[0].split() for l in open(sys.argv[1])]
tok = [t for t in tok if t]
i = 1 if len(tok[0]) == 1 else 0
nv, nf = int(tok[i][0] if i else tok[0][1]), int(tok[i][1] if i else tok[0][2])
vs = [tuple(map(float, t[:3])) for t in tok[i + 1:i + 1 + nv]]
tris = []
for t in tok[i + 1 + nv:i + 1 + nv + nf]:
    ids = list(map(int, t[1:1 + int(t[0])]))
    tris += [(ids[0], ids[j - 1], ids[j]) for j in range(2, len(ids))]
size = max(max(v[k] for v in vs) - min(v[k] for v in vs) for k in range(3))
tol = 1e-12 * size
def sub(a, b): return [a[k] - b[k] for k in range(3)]
planes = []
for a, b, c in tris:
    A, B, C = vs[a], vs[b], vs[c]
    u, v = sub(B, A), sub(C, A)
    n = [u[1]*v[2]-u[2]*v[1], u[2]*v[0]-u[0]*v[2], u[0]*v[1]-u[1]*v[0]]
    l = sum(x * x for x in n) ** 0.5
    lo = [min(A[k], B[k], C[k]) - tol for k in range(3)]
    hi = [max(A[k], B[k], C[k]) + tol for k in range(3)]
    planes.append(([x / l for x in n], A, lo, hi))
pts = [tuple(map(float, l.split())) for l in open(sys.argv[2]) if l.strip() and l[0] != '#']
bad = 0
for p in pts:
    ok = any(abs(sum(n[k] * (p[k] - A[k]) for k in range(3))) <= tol and
             all(lo[k] <= p[k] <= hi[k] for k in range(3)) for n, A, lo, hi in planes)
    bad += not ok
if len(pts) != int(sys.argv[3]) or bad:
    print("%d points (expected %s), %d off the surface" % (len(pts), sys.argv[3], bad))
    sys.exit(1)
PYEOF
}

# ---- samples on the surface, reproducible
for m in tet cube; do
    expect 0 "" -- "$G" generate surface 3000 --mesh $m.off --seed 5 -o $m.xyz
    grep -q "generated=3000 kind=surface seed=5" "$T/out" || fail "$m: summary line: $(cat "$T/out")"
    if msg=$(on_surface $m.off $m.xyz 3000); then pass "$m: 3000 samples on the surface"
    else fail "$m: $msg"; fi
done
expect 0 "" -- "$G" generate surface 3000 --mesh tet.off --seed 5 -o tet2.xyz -q
cmp -s tet.xyz tet2.xyz && pass "same seed, same points" || fail "seed 5 twice gave different files"
expect 0 "" -- "$G" generate surface 3000 --mesh tet.off --seed 6 -o tet3.xyz -q
cmp -s tet.xyz tet3.xyz && fail "seeds 5 and 6 gave the same points" || pass "another seed, other points"
expect 0 "" -- "$G" generate surface 3000 --mesh cube.ply --seed 5 -o cubep.xyz -q
cmp -s cube.xyz cubep.xyz && pass "the PLY cube samples as the OFF cube" ||
    fail "cube.ply and cube.off gave different samples"
# the samples feed the triangulator in any point format
expect 0 "" -- "$G" generate surface 2000 --mesh tet.off -o tet.bin -q
expect 0 "" -- "$G" triangulate tet.bin --check -q
expect 0 "" -- "$G" triangulate cube.off --check -q   # an .off file as points: its vertices

# ---- bad mesh files: exit 2 with a message; misuse: exit 1
printf 'OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' > range.off
printf 'OFF\n3 0\n0 0 0\n1 0 0\n0 1 0\n' > cloud.off
printf 'OFF\n3 1\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n' > flat.off
printf 'OFF\n3 1\n0 0 0\n1 0 0\n' > short.off
: > empty.off
mkdir dir.off
expect 2 "range.off:6: face 0: vertex index 7 out of range" -- "$G" generate surface 10 --mesh range.off -o x.xyz
expect 2 "no faces" -- "$G" generate surface 10 --mesh cloud.off -o x.xyz
expect 2 "zero area" -- "$G" generate surface 10 --mesh flat.off -o x.xyz
expect 2 "more than the" -- "$G" generate surface 10 --mesh short.off -o x.xyz
expect 2 "empty file" -- "$G" generate surface 10 --mesh empty.off -o x.xyz
expect 2 "is a directory" -- "$G" generate surface 10 --mesh dir.off -o x.xyz
expect 2 "cannot open" -- "$G" generate surface 10 --mesh missing.off -o x.xyz
"$G" generate uniform 10 -o pts.ply -q
expect 2 "no face element" -- "$G" generate surface 10 --mesh pts.ply -o x.xyz
expect 1 "needs --mesh" -- "$G" generate surface 10 -o x.xyz
expect 1 "only for the kind 'surface'" -- "$G" generate uniform 10 --mesh tet.off -o x.xyz
expect 1 "generate surface reads .ply or .off" -- "$G" generate surface 10 --mesh tet.stl -o x.xyz
[ ! -e x.xyz ] && pass "no output after a failure" || fail "x.xyz written by a failed run"

# ---- a real scanned mesh (Debian's libcgal-demo ships the CGAL data tarball)
tarball=/usr/share/doc/libcgal-demo/data.tar.gz
if [ -r "$tarball" ] && tar xzf "$tarball" data/meshes/armadillo.off 2>/dev/null; then
    expect 0 "" -- "$G" generate surface 20000 --mesh data/meshes/armadillo.off -o arm.bin -q
    expect 0 "" -- "$G" triangulate arm.bin -t 2 --check
    grep -q "check=ok" "$T/out" && pass "armadillo sample: check=ok" || fail "no check=ok: $(cat "$T/out")"
else
    echo "skipped: the real-mesh case needs $tarball (apt-get install libcgal-demo)"
fi
finish
