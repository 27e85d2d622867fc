# readback_common.sh -- run readback.py with python module $LIB on meshes gigatet wrote
# from a random and a degenerate (grid) point set; sourced by test_readback_*.sh.
# Needs the kernel: the tet counts and volumes are those of the real triangulation.
readback() {  # LIB EXT...
    local lib=$1
    shift
    local py
    py=$(find_python "$lib") || skip_loudly "python3 module '$lib' is missing (Debian package python3-${lib/vtk/vtk9}); the $lib read-back test did not run"
    find_python numpy >/dev/null || skip_loudly "numpy is missing; the $lib read-back test did not run"
    cd "$W"
    local set ext nt args=()
    for set in ball_400 grid_125 cospherical_60; do
        "$G" generate "${set%%_*}" "${set##*_}" --seed 9 -o "$set.bin" -q || fail "generate $set"
        for ext in "$@"; do
            expect 0 "" -- "$G" triangulate "$set.bin" -o "$set.$ext"
            nt=$(sed -n 's/.* tets=\([0-9]*\) .*/\1/p' "$T/out")
            args+=("$set.$ext" "$set.bin" "${nt:-0}")
        done
    done
    # one interpreter for all files: importing gmsh or vtk takes a second
    if "$py" "$HERE/readback.py" "$lib" "${args[@]}" >"$T/py" 2>&1; then
        pass "$(tr -s '\n' ' ' < "$T/py")"
    else
        fail "$lib: $(tr -s '\n' ' ' < "$T/py")"
    fi
    finish
}
