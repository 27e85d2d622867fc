#!/usr/bin/env bash
# test_check_foreign_files.sh -- `gigatet check` judges meshes written by other tools: the
# same Delaunay mesh written by meshio (vtu ascii/binary, msh 2.2/4.1 ascii/binary, mixed
# cell types), VTK's XML writer (ascii, inline binary, appended raw and base64, zlib or none,
# UInt32/UInt64 headers), the Gmsh API (MSH 2.2/4.1, ASCII/binary, sparse shuffled node
# tags) and TetGen itself (.node/.ele 1- and 0-based, -A, node attributes and markers) must
# pass `check --points`, and the tet count check reports must be the count the writer was
# given.  The points are random (so the Delaunay mesh is unique and the canonical check
# applies to any correct one) with 9 significant digits, so that ASCII writers that print 12
# or 16 digits still give back the same doubles.  Skips (exit 77, loudly) only when a python
# module or tetgen is really missing.
. "$(dirname "$0")/common.sh"
cd "$W"
py=$(find_python meshio) || skip_loudly "python3 module 'meshio' is missing (python3-meshio)"
for mod in vtk gmsh numpy; do
    "$py" -c "import $mod" >/dev/null 2>&1 || skip_loudly "python3 module '$mod' is missing for $py (Debian: python3-vtk9 / python3-gmsh / python3-numpy)"
done
command -v tetgen >/dev/null 2>&1 || skip_loudly "tetgen is missing (Debian package tetgen)"

n=1500
[ "${GTET_SANITIZE:-OFF}" = ON ] && n=400
"$G" generate uniform $n --seed 3 -o raw.xyz -q || fail "generate"
# 9 significant digits: distinct, in general position, exact through any %.12g writer
awk '!/^#/ { printf "%.9g %.9g %.9g\n", $1, $2, $3 }' raw.xyz > pts.xyz
{ echo "$n 3 0 0"; awk '{ print NR, $0 }' pts.xyz; } > pts.node
expect 0 "" -- "$G" triangulate pts.xyz -o own.vtu
nt=$(sed -n 's/.* tets=\([0-9]*\) .*/\1/p' "$T/out")

# check FILE TETS [SKIPPED]: passes, and reports TETS tets
check_file() {
    local f=$1 want=$2
    if "$G" check "$f" --points pts.xyz >"$T/out" 2>"$T/err"; then
        local got
        got=$(sed -n 's/.* tets=\([0-9]*\).*/\1/p' "$T/out")
        if [ "$got" = "$want" ]; then
            pass "check $f: $got tets"
        else
            fail "check $f reports tets=$got, the writer wrote $want: $(cat "$T/out")"
        fi
    else
        fail "check $f failed: $(head -c 400 "$T/err")"
    fi
}

mkdir foreign
if "$py" "$HERE/write_foreign.py" own.vtu foreign >"$T/written" 2>"$T/pyerr"; then
    count=0
    while read -r f k; do
        check_file "foreign/$f" "$k"
        [ "$k" = "$nt" ] || fail "$f: the writer was given $k tets, gigatet made $nt"
        count=$((count + 1))
    done <"$T/written"
    [ "$count" -ge 20 ] || fail "only $count foreign files were written"
else
    fail "write_foreign.py: $(tail -n 5 "$T/pyerr")"
fi

# TetGen's own output from the same points: 1-based, 0-based (-z), with -A, and from a
# .node with attributes and a boundary marker column
tetgen -Q pts.node >/dev/null 2>&1 || fail "tetgen -Q"
check_file pts.1.ele "$(awk 'NR==1{print $1}' pts.1.ele)"
cp pts.node z.node && tetgen -Qz z.node >/dev/null 2>&1 || fail "tetgen -Qz"
head -n 2 z.1.ele | tail -n 1 | grep -q '^ *0 ' || fail "tetgen -z did not write 0-based ids"
check_file z.1.ele "$(awk 'NR==1{print $1}' z.1.ele)"
cp pts.node a.node && tetgen -QA a.node >/dev/null 2>&1 || fail "tetgen -QA"
check_file a.1.ele "$(awk 'NR==1{print $1}' a.1.ele)"
{ echo "$n 3 2 1"; awk '{ print NR, $0, 0.5, -3, NR % 3 }' pts.xyz; } > m.node
tetgen -Q m.node >/dev/null 2>&1 || fail "tetgen -Q with attributes and markers"
head -n 1 m.1.node | grep -q "3 *2 *1" || fail "tetgen dropped the attributes: $(head -n 1 m.1.node)"
check_file m.1.ele "$(awk 'NR==1{print $1}' m.1.ele)"
# a region attribute column, as tetgen -A writes with regions
awk 'NR==1{ print $1, $2, 1; next } /^#/ { print; next } { print $0, 2 }' pts.1.ele > r.1.ele
cp pts.1.node r.1.node
check_file r.1.ele "$(awk 'NR==1{print $1}' r.1.ele)"

# a damaged foreign file is a clean input error (exit 2) naming the file
if [ -f foreign/gmsh_4.1_bin.msh ]; then
    head -c 3000 foreign/gmsh_4.1_bin.msh > cut.msh
    expect 2 "cut.msh" -- "$G" check cut.msh
fi
if [ -f foreign/vtk_appended_raw_zlib.vtu ]; then
    sed 's/vtkZLibDataCompressor/vtkLZ4DataCompressor/' foreign/vtk_appended_raw_zlib.vtu > lz4.vtu
    expect 2 "vtkLZ4DataCompressor" -- "$G" check lz4.vtu
fi
finish
