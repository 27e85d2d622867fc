#!/usr/bin/env bash
# test_input_map.sh -- `gigatet triangulate --map FILE`: where every input point went.  The file
# has two '#' lines and then one line per input point, its vertex's 0-based position in the
# mesh's vertex list; a duplicate names its first occurrence's vertex.  Checked against the
# points and the .node of the same run (every input point's coordinates are its vertex's, bit
# for bit as %.17g text), at 1 and 2 threads; an unwritable map fails before the work (exit 2,
# nothing written), a map path that collides with the input, the mesh or the degeneracy record
# is a usage error (exit 1), and a failed run leaves no map.
. "$(dirname "$0")/common.sh"
cd "$W"

# a small set with every kind of repeat: a later copy, a copy of a copy, -0.0 against 0.0
printf '0 0 0\n1 0 0\n0 1 0\n1 0 0\n0 0 1\n-0 0 0\n1 1 1\n1 0 0\n' > dup.xyz
expect 0 "" -- "$G" triangulate dup.xyz --map dup.map -o dup.ele
grep -q "duplicates=3" "$T/out" || fail "summary: $(cat "$T/out")"
[ "$(sed -n 1p dup.map)" = "# gigatet input map: 8 points, 5 vertices, 3 duplicates" ] ||
    fail "map header: $(sed -n 1p dup.map)"
[ "$(grep -c '^#' dup.map)" = 2 ] || fail "map comment lines: $(grep -c '^#' dup.map)"
[ "$(grep -v '^#' dup.map | tr '\n' ' ')" = "0 1 2 1 3 0 4 1 " ] ||
    fail "map of dup.xyz: $(grep -v '^#' dup.map | tr '\n' ' ')"

# check_map POINTS.xyz MAP NODE: every input point is its vertex (the .node's coordinates are
# written with %.17g, so they read back as the same doubles; the node ids are 1-based)
check_map() {
    awk -v pts="$1" -v node="$3" '
        BEGIN {
            while ((getline l < node) > 0) {
                if (l ~ /^#/ || l ~ /^[ \t]*$/) continue
                split(l, f)
                if (!hdr) { hdr = 1; nv = f[1]; continue }
                vx[f[1] - 1] = f[2] + 0; vy[f[1] - 1] = f[3] + 0; vz[f[1] - 1] = f[4] + 0
            }
            k = 0
            while ((getline l < pts) > 0) {
                if (l ~ /^#/ || l ~ /^[ \t]*$/) continue
                split(l, f); px[k] = f[1] + 0; py[k] = f[2] + 0; pz[k] = f[3] + 0; k++
            }
            np = k; i = 0
        }
        /^#/ { next }
        {
            v = $1 + 0
            if (v < 0 || v >= nv) { print "input " i ": vertex " v " of " nv; bad++ }
            else if (vx[v] != px[i] || vy[v] != py[i] || vz[v] != pz[i]) {
                print "input " i " (" px[i] " " py[i] " " pz[i] ") is not vertex " v; bad++
            }
            i++
        }
        END {
            if (i != np) { print "map lines " i ", points " np; bad++ }
            exit bad > 0
        }' "$2"
}
check_map dup.xyz dup.map dup.node || fail "dup.xyz's map against its .node"

# a larger set with repeats spread through it, at 1 and 2 threads: the same map either way
"$G" generate uniform 20000 --seed 3 -o u.xyz -q || fail "generate"
{ cat u.xyz; awk 'NR % 7 == 0' u.xyz; awk 'NR % 11 == 0' u.xyz; } > urep.xyz
for t in 1 2; do
    expect 0 "" -- "$G" triangulate urep.xyz -t $t --map u$t.map -o u$t.ele
    check_map urep.xyz u$t.map u$t.node || fail "urep.xyz's map at -t $t"
done
cmp -s u1.map u2.map || fail "the map depends on the thread count"
[ "$(grep -vc '^#' u1.map)" = "$(grep -vc '^#' urep.xyz)" ] || fail "one line per input point"

# without -o the map is written alone; with -q nothing is printed
expect 0 "" -- "$G" triangulate dup.xyz --map=alone.map -q
[ ! -s "$T/out" ] || fail "-q printed: $(head -c 200 "$T/out")"
cmp -s alone.map dup.map || fail "the map without -o differs"

# unwritable destinations: exit 2 before the work, nothing written
mkdir out
expect 2 "out/nodir/m.map" -- "$G" triangulate dup.xyz --map out/nodir/m.map -o out/m.ele
expect 2 "dup.xyz/m.map" -- "$G" triangulate dup.xyz --map dup.xyz/m.map -o out/m.ele
[ -z "$(listing out)" ] || fail "failed runs left: $(listing out)"

# usage errors: exit 1, nothing written
expect 1 "needs a file name" -- "$G" triangulate dup.xyz --map
expect 1 "overwrite the input" -- "$G" triangulate dup.xyz --map dup.xyz
expect 1 "both the mesh and the input map" -- "$G" triangulate dup.xyz --map out/m.node -o out/m.ele
expect 1 "both the mesh and the input map" -- "$G" triangulate dup.xyz --map out/m.vtu -o out/m.vtu
expect 1 "both the input map and the degeneracies" -- "$G" triangulate dup.xyz --map out/d --degeneracies out/d
[ -z "$(listing out)" ] || fail "usage errors left: $(listing out)"

# a failed run (degenerate input, a bad line) leaves no map and no mesh
printf '0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 0\n' > flat.xyz
expect 3 "flat.xyz" -- "$G" triangulate flat.xyz --map out/f.map -o out/f.ele
printf '0 0 0\n1 0 0\n0 1\n' > bad.xyz
expect 2 "bad.xyz:3:" -- "$G" triangulate bad.xyz --map out/b.map
[ -z "$(listing out)" ] || fail "a failed run left: $(listing out)"
finish
