#!/usr/bin/env bash
# test_degeneracies.sh -- `gigatet triangulate --degeneracies FILE.json [--degeneracies-limit N]`:
# the file is JSON (read with Python's json module), its counters are the --stats
# "predicates" of the same run, its records add up to them (stored + omitted == sos_calls,
# records per term == sos_depth when nothing was omitted), its coordinates are the mesh
# vertices' bit for bit (compared with the .node written by the same run), the limit is
# honoured, an unwritable destination fails before the work (exit 2, nothing written) and a
# bad option value is a usage error (exit 1).
. "$(dirname "$0")/common.sh"
PY=$(find_python json) || skip_loudly "no python3 with the json module"
cd "$W"
"$G" generate grid 1000 -o grid.xyz -q || fail "generate grid"
"$G" generate uniform 3000 -o uni.xyz -q || fail "generate uniform"
"$G" generate cospherical 600 -o sph.xyz -q || fail "generate cospherical"

# check JSON STATS_LINE_FILE NODE_FILE|- LIMIT: every claim about one run's file
check() {
    "$PY" - "$@" <<'EOF'
import json, sys
path, stats_path, node_path, limit = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
d = json.load(open(path))
lines = open(stats_path).read().splitlines()
stats = json.loads(lines[1])
errors = []
def need(cond, msg):
    if not cond:
        errors.append(msg)
pred = d["predicates"]
need(pred == stats["predicates"], "counters differ from --stats: %s vs %s" % (pred, stats["predicates"]))
dec = d["decisions"]
need(d["total"] == pred["sos_calls"], "total %d != sos_calls %d" % (d["total"], pred["sos_calls"]))
need(d["stored"] == len(dec), "stored %d != %d records" % (d["stored"], len(dec)))
need(d["stored"] == min(d["total"], limit), "stored %d, total %d, limit %d" % (d["stored"], d["total"], limit))
need(d["stored"] + d["omitted"] == d["total"], "stored + omitted != total")
need(d["truncated"] == (d["omitted"] > 0), "truncated flag")
need(d["limit"] == limit, "limit field")
need(d["points"] == stats["points"] and d["vertices"] == stats["vertices"], "points/vertices")
if d["omitted"] == 0:
    per = [0, 0, 0, 0]
    for r in dec:
        per[r["term"] - 1] += 1
    need(per == pred["sos_depth"], "records per term %s != sos_depth %s" % (per, pred["sos_depth"]))
node = None
if node_path != "-":
    node = {}
    with open(node_path) as f:
        rows = [l.split() for l in f if l.strip() and not l.startswith("#")]
    for r in rows[1:]:
        node[int(r[0]) - 1] = [float(x) for x in r[1:4]]
for r in dec:
    k = r["kind"]
    n = 5 if k == "cospherical" else 4
    need(k in ("cospherical", "coplanar"), "kind %r" % k)
    need(len(r["vertices"]) == n and len(r["coords"]) == n, "arity of %r" % r)
    need(r["term"] in (1, 2, 3, 4) and r["sign"] in (1, -1), "term/sign of %r" % r)
    need(all(0 <= v < d["vertices"] for v in r["vertices"]), "vertex ids of %r" % r)
    if node is not None:
        need(all(node[v] == c for v, c in zip(r["vertices"], r["coords"])),
             "coordinates of %r are not the mesh's" % r)
    if len(errors) > 5:
        break
for e in errors[:5]:
    print("FAIL:", e, file=sys.stderr)
sys.exit(1 if errors else 0)
EOF
}

# a grid: many decisions, full list, coordinates against the .node of the same run
for t in 1 2; do
    expect 0 "" -- "$G" triangulate grid.xyz -t $t --stats --degeneracies g$t.json -o g$t.ele
    cp "$T/out" g$t.stats
    if check g$t.json g$t.stats g$t.node 100000; then pass "grid -t $t: file consistent"
    else fail "grid -t $t: file inconsistent"; fi
    "$PY" -c "import json,sys; d=json.load(open('g$t.json')); sys.exit(0 if d['stored'] > 0 and not d['truncated'] else 1)" \
        || fail "grid -t $t: expected a non-empty, untruncated list"
done
cmp -s g1.ele g2.ele || fail "recording: -t 1 and -t 2 meshes differ"

# co-spherical integer points
expect 0 "" -- "$G" triangulate sph.xyz -t 1 --stats --degeneracies s.json
cp "$T/out" s.stats
check s.json s.stats - 100000 && pass "cospherical: file consistent" || fail "cospherical: file inconsistent"
"$PY" -c "import json,sys; d=json.load(open('s.json')); sys.exit(0 if any(r['kind']=='cospherical' for r in d['decisions']) else 1)" \
    || fail "cospherical: no co-spherical record"

# generic points: an empty list
expect 0 "" -- "$G" triangulate uni.xyz --stats --degeneracies u.json
cp "$T/out" u.stats
check u.json u.stats - 100000 && pass "uniform: file consistent" || fail "uniform: file inconsistent"
"$PY" -c "import json,sys; d=json.load(open('u.json')); sys.exit(0 if d['decisions']==[] and d['total']==0 and d['truncated'] is False else 1)" \
    || fail "uniform: expected an empty list"

# the limit: exact totals, only N records (one thread: the same total as the full run)
for n in 0 7; do
    expect 0 "" -- "$G" triangulate grid.xyz -t 1 --stats --degeneracies l$n.json --degeneracies-limit $n
    cp "$T/out" l$n.stats
    check l$n.json l$n.stats - $n && pass "limit $n: file consistent" || fail "limit $n: file inconsistent"
    "$PY" -c "import json,sys; d=json.load(open('l$n.json')); f=json.load(open('g1.json')); sys.exit(0 if d['stored']==$n and d['truncated'] is True and d['total']==f['total'] else 1)" \
        || fail "limit $n: not truncated to $n with the full total"
done
expect 0 "" -- "$G" triangulate grid.xyz -t 1 -q --degeneracies=q.json --degeneracies-limit=3
[ ! -s "$T/out" ] || fail "-q printed: $(head -c 200 "$T/out")"
"$PY" -c "import json,sys; d=json.load(open('q.json')); sys.exit(0 if d['stored']==3 else 1)" \
    || fail "--degeneracies=FILE --degeneracies-limit=N"

# unwritable destinations: exit 2 before the work, nothing written (neither file)
mkdir out
expect 2 "out/nodir/d.json" -- "$G" triangulate grid.xyz --degeneracies out/nodir/d.json -o out/m.ele
expect 2 "grid.xyz/d.json" -- "$G" triangulate grid.xyz --degeneracies grid.xyz/d.json
[ -z "$(listing out)" ] || fail "failed runs left: $(listing out)"

# usage errors: exit 1, nothing written
expect 1 "needs a file name" -- "$G" triangulate grid.xyz --degeneracies
expect 1 "needs a count" -- "$G" triangulate grid.xyz --degeneracies out/d.json --degeneracies-limit
expect 1 "invalid degeneracy limit" -- "$G" triangulate grid.xyz --degeneracies out/d.json --degeneracies-limit abc
expect 1 "invalid degeneracy limit" -- "$G" triangulate grid.xyz --degeneracies out/d.json --degeneracies-limit -5
expect 1 "invalid degeneracy limit" -- "$G" triangulate grid.xyz --degeneracies out/d.json --degeneracies-limit 99999999999999999999999
expect 1 "needs --degeneracies" -- "$G" triangulate grid.xyz --degeneracies-limit 5
expect 1 "overwrite the input" -- "$G" triangulate grid.xyz --degeneracies grid.xyz
expect 1 "both the mesh" -- "$G" triangulate grid.xyz --degeneracies out/m.node -o out/m.ele
[ -z "$(listing out)" ] || fail "usage errors left: $(listing out)"

# a failed run (degenerate input) leaves no file
printf '0 0 0\n1 0 0\n0 1 0\n1 1 0\n' > flat.xyz
expect 3 "flat.xyz" -- "$G" triangulate flat.xyz --degeneracies out/f.json
[ -z "$(listing out)" ] || fail "a failed run left: $(listing out)"
finish
