#!/usr/bin/env bash
# test_check_other_tools.sh -- `gigatet check` and `gigatet diff` on meshes other tools wrote.
#   TetGen on a grid: every cube is a co-spherical group that TetGen splits its own way, so the
#     canonical check fails naming the tie and its group of 8, --delaunay passes, and diff
#     classifies the difference as tie-breaking with the 729 cubes listed as groups; TetGen on
#     points with duplicates keeps them as vertices in no tet: accepted as copies.
#   scipy (Qhull) on random points: simplices unoriented and renumbered: the default check
#     fails on orientation alone, --any-orientation passes, diff with gigatet's mesh: identical.
#     On the grid scipy writes flat tets: every mode fails them.
#   A 2-3 flip of a Delaunay mesh: fails both modes; diff names the side that is not Delaunay.
#   --json reports parse and carry the mode, the counts and the first violation.
#   TetGen -o2 (10-node tets, mid-edge nodes after the corners in its .node): the corners'
#     mesh passes, the mid-edge nodes are not taken for vertices in no tet.
# Skips (77, loudly) only when tetgen or Debian's python3 with numpy + scipy is really missing.
. "$(dirname "$0")/common.sh"
command -v tetgen >/dev/null 2>&1 || skip_loudly "tetgen is not installed (apt-get install tetgen)"
PY=$(find_python scipy) || skip_loudly "no python3 with scipy (apt-get install python3-scipy)"
cd "$W"

# json FILE EXPR: evaluate a python expression on the parsed JSON object j; fail unless true
json() {
    if "$PY" -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1"; then
        pass "json: $2"
    else
        fail "json: $2 is false in $(head -c 600 "$1")"
    fi
}
has() {  # has FILE STRING
    if grep -qF -- "$2" "$1"; then pass "output has '$2'"; else fail "output lacks '$2': $(head -c 400 "$1")"; fi
}

# ---- TetGen on a grid --------------------------------------------------------------------
"$G" generate grid 1000 -o grid.node -q
tetgen -Q grid.node >/dev/null 2>&1 || fail "tetgen failed on grid.node"
expect 5 "a tie broken against the symbolic perturbation" -- "$G" check grid.1.ele --points grid.node
has "$T/err" "co-spherical group of 8 vertices"
expect 0 "" -- "$G" check grid.1.ele --points grid.node --delaunay
has "$T/out" "check=ok mode=delaunay"
"$G" check grid.1.ele --points grid.node --json >canon.json 2>/dev/null; rc=$?
[ $rc -eq 5 ] && pass "check --json exit 5" || fail "check --json exited $rc"
json canon.json 'j["mode"]=="canonical" and not j["ok"] and j["status"]=="check_failed" and j["violation"]["tie"] and j["violation"]["group_size"]==8 and len(j["violation"]["vertices"])==5 and len(j["violation"]["tets"])==2 and j["violation"]["stage"]=="delaunay" and all(len(v["point"])==3 for v in j["violation"]["vertices"])'
"$G" check grid.1.ele --points grid.node --delaunay --json >closed.json; rc=$?
[ $rc -eq 0 ] && pass "check --delaunay --json exit 0" || fail "check --delaunay --json exited $rc"
json closed.json 'j["mode"]=="delaunay" and j["ok"] and j["violation"] is None and j["tets"]>4000 and j["cospherical_facets"]>0'
"$G" triangulate grid.node -o gg.ele -q
expect 0 "" -- "$G" check gg.ele --points grid.node
expect 5 "" -- "$G" diff gg.ele grid.1.ele --points grid.node
has "$T/out" "diff=ties"
has "$T/out" "groups=729"
has "$T/out" "group 1: 8 co-spherical points on the hull"
"$G" diff gg.ele grid.1.ele --json --groups 0 >diff.json
json diff.json 'j["verdict"]=="ties" and j["groups_total"]==729 and len(j["groups"])==729 and all(g["size"]==8 for g in j["groups"]) and j["check_a"]["ok"] and j["check_b"]["ok"]'
"$G" triangulate grid.node -o gg.vtu -q
expect 0 "" -- "$G" diff gg.ele gg.vtu
has "$T/out" "diff=identical"

# ---- TetGen keeps duplicate points as unused vertices -------------------------------------
"$PY" - <<'PYEOF'
import random
random.seed(5)
pts = [(random.random(), random.random(), random.random()) for _ in range(300)]
pts += [pts[7], pts[100], pts[7]]
with open("dup.node", "w") as f:
    f.write("%d 3 0 0\n" % len(pts))
    for i, p in enumerate(pts):
        f.write("%d %.17g %.17g %.17g\n" % (i + 1, p[0], p[1], p[2]))
PYEOF
tetgen -Q dup.node >/dev/null 2>&1 || fail "tetgen failed on dup.node"
expect 0 "" -- "$G" check dup.1.ele --points dup.node
has "$T/out" "duplicates=3"
"$G" triangulate dup.node -o gdup.ele -q
expect 0 "" -- "$G" diff gdup.ele dup.1.ele --points dup.node

# ---- TetGen -o2: 10-node tets, their mid-edge nodes appended to the .node ------------------
# The corners are the Delaunay mesh; the mid-edge nodes are no input points and in no linear tet.
tetgen -Qo2 dup.node >/dev/null 2>&1 || fail "tetgen -o2 failed on dup.node"
head -1 dup.1.ele | grep -q "^ *[0-9]* *10 " && pass "tetgen -o2 wrote 10-node tets" || fail "tetgen -o2 wrote $(head -1 dup.1.ele)"
expect 0 "" -- "$G" check dup.1.ele --points dup.node
has "$T/out" "duplicates=3"
expect 0 "" -- "$G" diff gdup.ele dup.1.ele --points dup.node

# ---- scipy (Qhull): unoriented, renumbered ------------------------------------------------
"$G" generate uniform 3000 --seed 4 -o r.node -q
"$PY" "$HERE/scipy_ele.py" r.node sr --shuffle 3 >/dev/null || fail "scipy failed"
expect 5 "negatively oriented" -- "$G" check sr.ele --points r.node
expect 0 "" -- "$G" check sr.ele --points r.node --any-orientation
if grep -q "negative_tets=0 " "$T/out"; then fail "no negative tets counted: $(cat "$T/out")"; else pass "negative tets counted"; fi
expect 0 "" -- "$G" check sr.ele --points r.node --any-orientation --delaunay
"$G" triangulate r.node -o gr.vtu -q
expect 0 "" -- "$G" diff gr.vtu sr.ele --points r.node
has "$T/out" "diff=identical"
"$PY" "$HERE/scipy_ele.py" grid.node sg >/dev/null || fail "scipy failed on the grid"
expect 5 "is flat (orient3d = 0)" -- "$G" check sg.ele --points grid.node --delaunay --any-orientation

# ---- a valid triangulation that is not Delaunay -------------------------------------------
"$PY" "$HERE/mesh_edit.py" flip23 sr.ele flip || fail "mesh_edit.py flip23 failed"
expect 5 "not locally Delaunay" -- "$G" check flip.ele --points r.node --any-orientation
expect 5 "not locally Delaunay" -- "$G" check flip.ele --points r.node --any-orientation --delaunay
expect 5 "" -- "$G" diff gr.vtu flip.ele
has "$T/out" "diff=b_not_delaunay"
has "$T/out" "B is not Delaunay"
"$G" diff flip.ele gr.vtu --json >flip.json
json flip.json 'j["verdict"]=="a_not_delaunay" and not j["check_a"]["ok"] and j["check_a"]["violation"]["stage"]=="delaunay" and j["check_b"]["ok"]'

# ---- usage and unreadable input ------------------------------------------------------------
expect 1 "expected two mesh files" -- "$G" diff gr.vtu
expect 1 "unknown option" -- "$G" check gr.vtu --bogus
expect 2 "" -- "$G" diff gr.vtu missing.ele
"$G" check missing.vtu --json >miss.json 2>/dev/null; rc=$?
[ $rc -eq 2 ] && pass "unreadable mesh: exit 2" || fail "unreadable mesh exited $rc"
json miss.json 'j["status"]=="unreadable" and not j["ok"] and j["message"]'

[ "$fails" -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
echo "all passed"
