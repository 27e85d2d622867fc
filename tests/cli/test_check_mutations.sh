#!/usr/bin/env bash
# test_check_mutations.sh -- `gigatet check` catches a corrupted mesh (issue 5, "the checker is
# checked"): take a valid .ele/.node and swap two vertices of a tet, drop a tet, duplicate a
# tet, move a vertex, rewire a tet to another tet's vertex -> exit 5 each time; the untouched
# mesh passes.  Needs the real checker (gtet_check_arrays) and kernel.
. "$(dirname "$0")/common.sh"
cd "$W"
"$G" generate ball 120 --seed 4 -o in.bin -q || fail "generate"
expect 0 "" -- "$G" triangulate in.bin -o m.ele
expect 0 "" -- "$G" check m.ele --points in.bin

mutant() {  # NAME AWK-PROGRAM-ON-.ele [AWK-PROGRAM-ON-.node]
    local name=$1
    awk "$2" m.ele > "$name.ele"
    if [ -n "${3:-}" ]; then awk "$3" m.node > "$name.node"; else cp m.node "$name.node"; fi
    cmp -s m.ele "$name.ele" && cmp -s m.node "$name.node" && fail "mutation $name changed nothing"
    expect 5 "check failed" -- "$G" check "$name.ele"
}
# .ele lines: header "T 4 0", then "id a b c d" (1-based), then a comment
mutant swapped   'NR == 2 { t = $3; $3 = $4; $4 = t } { print }'
mutant dropped   'NR == 1 { $1 = $1 - 1 } NR == 2 { next } NR > 2 && /^[0-9]/ { $1 = $1 - 1 } { print }'
mutant duplicated 'NR == 1 { $1 = $1 + 1 } /^#/ { print n + 1, a, b, c, d } NR == 2 { a = $2; b = $3; c = $4; d = $5 } NR > 1 && /^[0-9]/ { n = $1 } { print }'
# tet 1 gets a vertex of the last tet that it does not have
last=$(awk 'NR > 2 && /^[0-9]/ { l = $2 " " $3 " " $4 " " $5 } END { print l }' m.ele)
mutant rewired   'NR == 2 { split("'"$last"'", L, " "); for (k = 1; k <= 4; k++) { v = L[k]; if (v != $2 && v != $3 && v != $4 && v != $5) { $2 = v; break } } } { print }'
mutant moved     '{ print }' 'NR == 2 { $2 = $2 + 50 } { print }'
# with --points, a moved vertex also no longer matches the input point set
cp m.ele moved_in.ele
awk 'NR == 2 { $2 = $2 + 1e-9 } { print }' m.node > moved_in.node
expect 5 "check failed" -- "$G" check moved_in.ele --points in.bin
# NOTES.md E159d: the message numbers tets and vertices from 0 in file order; gigatet's .ele
# is 1-based, so the failure says so (the swapped tet is the file's tet 1, named 'tet 0')
expect 5 "tet 0 (" -- "$G" check swapped.ele
grep -qF "[tets and vertices are numbered from 0 in the order of the file's .ele and .node, not by its own ids: add 1 for a 1-based file]" "$T/err" ||
    fail "swapped: no numbering note: $(cat "$T/err")"
# NOTES.md E159: a failed check of a file with skipped cells (not linear tetrahedra: here one
# tet relabelled VTK_QUADRATIC_TETRA) says they were skipped; a file without them does not
expect 0 "" -- "$G" triangulate in.bin -o m.vtu
awk '/Name="types"/ { t = 1; print; next } t && $1 == 10 { print 24; t = 0; next } { print }' m.vtu > quad.vtu
expect 5 "(1 cell of the file is not linear tetrahedra and was skipped" -- "$G" check quad.vtu
expect 5 "check failed" -- "$G" check moved_in.ele --points in.bin
grep -q "skipped" "$T/err" && fail "a note on skipped cells where there are none: $(cat "$T/err")"
# NOTES.md E157: coordinates rounded by the writer (12 digits, as meshio's ASCII .vtu): the
# message names the nearest vertex and asks whether they were rounded; a vertex far from
# every input point gets the plain message
cp m.ele rounded.ele
awk 'NR > 1 && /^[0-9]/ { printf "%d %.12g %.12g %.12g\n", $1, $2, $3, $4; next } { print }' m.node > rounded.node
expect 5 "were the coordinates rounded when the mesh was written?" -- "$G" check rounded.ele --points in.bin
grep -q "is off by a relative [0-9.]*e-1[0-9]" "$T/err" || fail "rounded: no relative offset in: $(cat "$T/err")"
cp m.ele far.ele
awk 'NR == 2 { $2 = $2 + 50 } { print }' m.node > far.node
expect 5 "is not a vertex of the mesh" -- "$G" check far.ele --points in.bin
grep -q "rounded" "$T/err" && fail "far: a vertex moved by 50 called rounding: $(cat "$T/err")"
# NOTES.md E181, E182: diff's verdicts get the same notes (on stdout, in the verdict's line):
# rounded coordinates named with the nearest point of the other mesh and its relative offset,
# a vertex far from every other point not called rounding; the numbering note for the mesh
# whose violation is quoted (A or B), none for a .vtu (0-based already); skipped cells
expect 5 "" -- "$G" diff m.ele rounded.ele
grep -q "^different point sets: .*(one is B's (.*; A's nearest point (.*) is off by a relative [0-9.]*e-1[0-9]: were the coordinates rounded when a mesh was written?" "$T/out" ||
    fail "diff rounded: no rounding note: $(cat "$T/out")"
expect 5 "" -- "$G" diff far.ele m.ele
grep -q "^diff=points" "$T/out" || fail "diff far: not diff=points: $(cat "$T/out")"
grep -q "rounded" "$T/out" && fail "diff far: a vertex moved by 50 called rounding: $(cat "$T/out")"
expect 5 "" -- "$G" diff m.ele rewired.ele
grep -qF "B is not Delaunay: tets 0 and " "$T/out" && grep -qF "[tets and vertices are numbered from 0 in the order of B's .ele and .node, not by its own ids: add 1 for a 1-based file]" "$T/out" ||
    fail "diff rewired: no numbering note for B: $(cat "$T/out")"
grep -q "skipped" "$T/out" && fail "diff rewired: a note on skipped cells where there are none: $(cat "$T/out")"
expect 0 "" -- "$G" triangulate in.bin -o m.msh
expect 5 "" -- "$G" diff rewired.ele m.msh
grep -qF "A is not Delaunay: tets 0 and " "$T/out" && grep -qF "in the order of A's .ele and .node" "$T/out" ||
    fail "diff rewired as A: no numbering note for A: $(cat "$T/out")"
grep -qF "order of B" "$T/out" && fail "diff rewired as A: a note for B: $(cat "$T/out")"
"$G" diff m.ele rewired.ele --json | grep -qF "numbered from 0" && fail "diff --json: the note is for the text verdict"
expect 5 "" -- "$G" diff m.vtu quad.vtu
grep -qF "(1 cell of B is not linear tetrahedra and was skipped" "$T/out" ||
    fail "diff quad: no skipped-cells note: $(cat "$T/out")"
finish
