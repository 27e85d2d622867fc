#!/usr/bin/env bash
# check_diff_cgal.sh GIGATET CGAL_DT -- CGAL's meshes through `gigatet check` and `gigatet diff`.
# CGAL breaks ties with the same symbolic perturbation as gigatet, so on a grid and on a
# co-spherical set its mesh passes the canonical check and --delaunay, and diff finds it
# identical to gigatet's; TetGen's mesh of the same grid differs from CGAL's by tie-breaking
# only (diff exit 5, "diff=ties").  CGAL's canonical output (tests/cgal/cgal_dt.cpp: one
# sorted line per tet, ids = input indices, so unoriented: checked with --any-orientation) is
# written as a 0-based TetGen mesh over the input.
set -u
G=${1:?usage: $0 GIGATET CGAL_DT}
C=${2:?usage: $0 GIGATET CGAL_DT}
T=$(mktemp -d "${TMPDIR:-/tmp}/gtet-cgal-XXXXXX")
trap 'rm -rf "$T"' EXIT
cd "$T"
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
run() {  # run CODE CMD...
    local code=$1; shift
    "$@" >out 2>err; local rc=$?
    if [ $rc -ne "$code" ]; then fail "'$*' exited $rc, expected $code: $(head -c 400 err) $(head -c 400 out)"
    else echo "ok   $* -> $rc"; fi
}
PY=/usr/bin/python3; [ -x $PY ] || PY=python3
for kind in grid cospherical; do
    "$G" generate $kind 1000 --seed 2 -o $kind.bin -q
    "$G" generate $kind 1000 --seed 2 -o $kind.node -q
    "$C" $kind.bin >$kind.cgal || fail "cgal_dt failed on $kind"
    "$PY" - "$kind" <<'PYEOF'
import sys
k = sys.argv[1]
tets = [l.split() for l in open(k + ".cgal") if l.strip() and not l.startswith("#")]
with open("cgal_" + k + ".ele", "w") as f:
    f.write("%d 4 0\n" % len(tets))
    for i, t in enumerate(tets):
        f.write("%d %s\n" % (i, " ".join(t)))
rows = [l for l in open(k + ".node") if l.strip() and not l.startswith("#")]
n = int(rows[0].split()[0])
with open("cgal_" + k + ".node", "w") as f:
    f.write("%d 3 0 0\n" % n)
    for i, r in enumerate(rows[1:1 + n]):
        f.write("%d %s\n" % (i, " ".join(r.split()[1:4])))
PYEOF
    run 0 "$G" check cgal_$kind.ele --points $kind.bin --any-orientation
    run 0 "$G" check cgal_$kind.ele --points $kind.bin --any-orientation --delaunay
    "$G" triangulate $kind.bin -o g_$kind.msh -q
    run 0 "$G" diff g_$kind.msh cgal_$kind.ele --points $kind.bin
    grep -q "diff=identical" out || fail "$kind: gigatet vs CGAL not identical: $(cat out)"
done
tetgen -Q grid.node >/dev/null 2>&1 || fail "tetgen failed"
run 5 "$G" diff cgal_grid.ele grid.1.ele --points grid.bin
grep -q "diff=ties" out || fail "CGAL vs TetGen on the grid is not a tie-breaking difference: $(head -3 out)"
[ $fails -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
echo "all passed"
