#!/usr/bin/env bash
# test_formats_roundtrip.sh -- the same points in every input format give the same mesh, in
# every output format, and every written mesh passes `gigatet check` against its input.
# Also: the summary line, --stats JSON, -q, --check, duplicates (-0.0 == +0.0) counted, and
# the degenerate generator families triangulated and checked.
# Needs the kernel and the checker for a meaningful pass (with a stand-in kernel it only
# exercises the plumbing).
. "$(dirname "$0")/common.sh"
cd "$W"

for f in xyz node ply bin; do
    expect 0 "" -- "$G" generate ball 200 --seed 5 -o "in.$f" -q
    [ -s "$T/out" ] && fail "generate -q printed '$(cat "$T/out")'"
done
# a hand-written ascii PLY with float/double coordinates among other properties, and a
# 0-based .node: the same 5 points
printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty uchar tag\nproperty double x\nproperty float y\nproperty double z\nproperty float nx\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n' > hand.ply
printf '7 0 0 0 1\n7 1 0 0 1\n7 0 1 0 1\n7 0 0 1 1\n7 1 1 1 1\n' >> hand.ply
printf '5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n' > hand.node
printf '0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n' > hand.xyz

summary_re='^points=[0-9]+ duplicates=[0-9]+ tets=[0-9]+ seconds=[0-9.]+ tets/s=[0-9]+( check=ok)?$'
for f in xyz node ply bin; do
    for o in ele msh vtu; do
        expect 0 "" -- "$G" triangulate "in.$f" -o "out_$f.$o"
        grep -qE "$summary_re" "$T/out" || fail "summary line: '$(cat "$T/out")'"
        grep -q '^points=200 duplicates=0 ' "$T/out" || fail "counts: '$(cat "$T/out")'"
        [ -s "$T/err" ] && fail "stderr not empty without a terminal: '$(cat "$T/err")'"
    done
    expect 0 "" -- "$G" check "out_$f.ele" --points "in.$f"
    grep -q '^check=ok ' "$T/out" || fail "check summary: '$(cat "$T/out")'"
    expect 0 "" -- "$G" check "out_$f.msh" --points "in.$f"
    expect 0 "" -- "$G" check "out_$f.vtu" --points "in.$f"
done
# the same points in any input format: the same vertices (byte for byte) and the same oriented
# tets in every output format (compared in canonical form: tet order may vary between runs)
py=$(find_python json) || fail "no python3 at all"
for f in xyz node ply bin; do
    cmp -s out_xyz.node "out_$f.node" || fail "in.$f and in.xyz give different vertices"
    for o in ele msh vtu; do
        "$py" "$HERE/canon_tets.py" "out_$f.$o" > "canon_$f.$o" || fail "canon_tets out_$f.$o"
        cmp -s canon_xyz.ele "canon_$f.$o" || fail "in.$f gives other tets in .$o than in.xyz in .ele"
    done
done
[ "$(wc -l < canon_xyz.ele)" -gt 300 ] || fail "suspiciously few tets: $(wc -l < canon_xyz.ele)"
expect 0 "" -- "$G" check out_bin.ele
# MESH.ELE goes with MESH.NODE (tools on case-insensitive file systems write capitals)
expect 0 "" -- "$G" triangulate in.xyz -o UP.ELE -q
[ -f UP.NODE ] && [ ! -e UP.node ] && pass "UP.ELE wrote UP.NODE" || fail "UP.ELE wrote: $(ls UP.*)"
expect 0 "" -- "$G" check UP.ELE --points in.xyz
cp out_xyz.node TG.NODE && cp out_xyz.ele TG.ELE
expect 0 "" -- "$G" check TG.ELE --points in.xyz

for f in ply node xyz; do
    expect 0 "" -- "$G" triangulate "hand.$f" -o "hand_$f.ele"
    grep -q '^points=5 duplicates=0 ' "$T/out" || fail "hand.$f: '$(cat "$T/out")'"
done
for f in ply node; do
    cmp -s hand_xyz.node "hand_$f.node" || fail "hand.$f gives other vertices than hand.xyz"
    [ "$("$py" "$HERE/canon_tets.py" hand_xyz.ele)" = "$("$py" "$HERE/canon_tets.py" "hand_$f.ele")" ] ||
        fail "hand.$f gives other tets than hand.xyz"
done

# --check, -q, --stats
expect 0 "" -- "$G" triangulate in.bin --check
grep -q ' check=ok$' "$T/out" || fail "--check: '$(cat "$T/out")'"
expect 0 "" -- "$G" triangulate in.bin -o q.ele -q --stats
[ -s "$T/out" ] || [ -s "$T/err" ] && fail "-q printed something: '$(cat "$T/out" "$T/err")'"
[ -s q.ele ] && [ -s q.node ] || fail "-q did not write the mesh"
expect 0 "" -- "$G" triangulate in.bin --stats -t 2
[ "$(wc -l < "$T/out")" -eq 2 ] || fail "--stats: expected the summary and one JSON line"
if [ -n "$py" ]; then
    tail -n 1 "$T/out" | "$py" -c '
import json, sys
s = json.load(sys.stdin)
need = ["points", "vertices", "duplicates", "tets", "threads", "seconds", "bytes_per_tet",
        "kernel_peak_bytes", "max_rss_bytes", "predicates", "rounds", "num_rounds", "tets_per_second",
        "pages", "small_fault_us"]
missing = [k for k in need if k not in s]
assert not missing, "missing keys %s" % missing
assert s["points"] == 200 and s["duplicates"] == 0 and s["tets"] > 0, s
assert s["max_rss_bytes"] > 0
assert s["pages"] in ("huge", "4k"), s["pages"]
assert s["small_fault_us"] is None or s["small_fault_us"] > 0, s["small_fault_us"]
for k in ["read", "validate", "sort", "insert", "finalize", "kernel", "write", "wall"]:
    assert k in s["seconds"], k
' || fail "--stats JSON is not what the contract says"
else
    fail "no python3 at all to parse the --stats JSON"
fi

# duplicates, signed zeros included, are counted and checked
printf '0 0 0\n1 0 0\n0 1 0\n0 0 1\n-0 0 0\n1 0 0\n0.5 0.5 0.5\n0 -0 -0\n' > dups.xyz
expect 0 "" -- "$G" triangulate dups.xyz -o dups.ele
grep -q '^points=8 duplicates=3 ' "$T/out" || fail "duplicates: '$(cat "$T/out")'"
[ "$(head -n 1 dups.node | cut -d' ' -f1)" = 5 ] || fail "dups.node does not hold the 5 distinct points"
expect 0 "" -- "$G" check dups.ele --points dups.xyz

# the degenerate families of the generator, triangulated, checked against their input; the
# O(n*m) --full empty-sphere test only on the small ones (it costs seconds at 300 points)
for k in grid:64 jittered:64 cospherical:100 paraboloid:49 fcc:100 bcc:100 plane-apex:60 \
         plane-apex-denormal:60 clustered:300 sphere:200 uniform:200 far-point:300 cauchy:300; do
    kind=${k%%:*} n=${k##*:} full=
    [ "$n" -le 64 ] && full=--full
    expect 0 "" -- "$G" generate "$kind" "$n" -o "$kind.bin" -q
    expect 0 "" -- "$G" triangulate "$kind.bin" --check -o "$kind.ele"
    expect 0 "" -- "$G" check "$kind.ele" --points "$kind.bin" $full
done
expect 0 "" -- "$G" check hand_xyz.ele --points hand.xyz --full
finish
