#!/usr/bin/env bash
# test_no_partial_output.sh -- a failed run leaves no output file and no temporary behind,
# and an existing output survives a failed run untouched; the mesh never overwrites its input.
# Needs the kernel for the degenerate-input case.
. "$(dirname "$0")/common.sh"
cd "$W"
mkdir out
"$G" generate uniform 200 -o in.xyz -q || fail "generate"
printf '0 0 0\n1 0 0\n0 1 0\n1 1 0\n' > flat.xyz
printf '0 0 0\n1 0 0\n0 1\n0 0 1\n' > bad.xyz

for o in ele msh vtu; do
    expect 2 "bad.xyz:3:" -- "$G" triangulate bad.xyz -o "out/m.$o"
    expect 3 "flat.xyz" -- "$G" triangulate flat.xyz -o "out/m.$o"
    expect 2 "out/nodir/m.$o" -- "$G" triangulate in.xyz -o "out/nodir/m.$o"
    expect 2 "in.xyz/m.$o" -- "$G" triangulate in.xyz -o "in.xyz/m.$o"
done
expect 2 "out/nodir/p.bin" -- "$G" generate uniform 10 -o out/nodir/p.bin
[ -z "$(listing out)" ] || fail "failed runs left: $(listing out)"

# a read-only directory (root ignores permissions, so this case needs an ordinary user)
if [ "$(id -u)" -ne 0 ]; then
    mkdir ro && chmod 555 ro
    expect 2 "ro/m.ele" -- "$G" triangulate in.xyz -o ro/m.ele
    expect 2 "ro/p.xyz" -- "$G" generate uniform 10 -o ro/p.xyz
    [ -z "$(listing ro)" ] || fail "read-only directory holds: $(listing ro)"
else
    echo "NOTE: running as root, which ignores directory permissions: the read-only-directory case is covered by the missing-directory and not-a-directory cases above"
fi

# an output name that is a directory: refused before the work, with the reason (it used to
# fail only at the rename after the whole run: "cannot rename the finished output into
# place"), and nothing beside it (the .node) stays behind; the writer's own cleanup when its
# rename fails is tests/test_io_writers.c's
for o in ele vtu; do
    mkdir "out/m.$o"
    expect 2 "out/m.$o: is a directory" -- "$G" triangulate in.xyz -o "out/m.$o"
    [ "$(listing out)" = "m.$o " ] || fail "after a directory output name: $(listing out)"
    rmdir "out/m.$o"
done

# an existing output survives failed runs byte for byte
echo "precious" > out/keep.msh
expect 2 "bad.xyz" -- "$G" triangulate bad.xyz -o out/keep.msh
expect 3 "flat.xyz" -- "$G" triangulate flat.xyz -o out/keep.msh
[ "$(cat out/keep.msh)" = precious ] || fail "a failed run changed an existing output"
expect 0 "" -- "$G" triangulate in.xyz -o out/keep.msh
grep -q '^\$MeshFormat' out/keep.msh || fail "a successful run did not replace the output"
[ "$(listing out)" = "keep.msh " ] || fail "temporaries left: $(listing out)"

# NOTES.md E156: a signal (Ctrl-C, kill, hang-up) while the mesh is written removes its
# temporaries (NAME.tmp-PID-N; for .ele the .node's too) and the process still dies of it.
# Job control on (set -m): bash's background jobs otherwise start with SIGINT ignored.
nbig=300000   # a write of ~0.3 s; the sanitizers' kernel is 5-20x slower, their write too
[ "${GTET_SANITIZE:-OFF}" = ON ] || [ "${GTET_TSAN:-OFF}" = ON ] && nbig=60000
"$G" generate uniform $nbig --seed 2 -o big.bin -q || fail "generate"
mkdir sig
set -m
for s in INT TERM HUP; do
    for o in vtu ele; do
        "$G" triangulate big.bin -o "sig/m.$o" -t 1 -q --degeneracies sig/d.json &
        pid=$!
        # until the mesh's temporary has data (at most 60 s): the write is under way (the
        # empty temporaries of the writability checks at the start do not count)
        for _ in $(seq 6000); do
            [ -n "$(find sig -name "m.*.tmp-*" -size +0)" ] && break
            sleep 0.01
        done
        [ -n "$(find sig -name "m.*.tmp-*" -size +0)" ] || fail "SIG$s .$o: no temporary seen"
        kill -"$s" "$pid"
        wait "$pid"
        rc=$?
        [ "$rc" -eq $((128 + $(kill -l "$s"))) ] || fail "SIG$s .$o: exit $rc, not death by the signal"
        [ -z "$(listing sig)" ] && pass "SIG$s while writing .$o: nothing left" ||
            fail "SIG$s while writing .$o left: $(listing sig)"
        rm -f sig/*
    done
done
set +m

# NOTES.md E159e: a valid output name of 240-255 bytes: its temporary (NAME.tmp-PID-N) went
# past NAME_MAX and the run failed with 'File name too long'; a name past NAME_MAX itself is
# refused before the work, saying so
mkdir long
long=$(printf 'a%.0s' $(seq 247))
for o in vtu ele; do
    expect 0 "" -- "$G" triangulate in.xyz -o "long/$long.$o"
    [ -s "long/$long.$o" ] || fail "long name .$o: no output"
done
[ "$(ls -A long | wc -l)" -eq 3 ] || fail "long names left: $(listing long)"
rm -f long/*
expect 2 "(its name has 256 bytes, at most 255)" -- "$G" triangulate in.xyz -o "long/${long}aaaaa.vtu"
[ -z "$(listing long)" ] || fail "a refused long name left: $(listing long)"

# the mesh must not overwrite its own input (NAME.node for NAME.ele)
cp in.xyz tmp.xyz
"$G" generate uniform 50 -o pts.node -q
cp pts.node pts.node.orig
expect 1 "overwrite the input" -- "$G" triangulate pts.node -o pts.ele
cmp -s pts.node pts.node.orig || fail "the input .node was overwritten"
[ ! -e pts.ele ] || fail "pts.ele written although the run was refused"
finish
