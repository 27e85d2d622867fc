#!/usr/bin/env bash
# tests/mpi/run_tests.sh GROUP GIGATET_MPI GIGATET WORKDIR MPIRUN API_TEST
# The distributed mode's tests (registered as ctests by src/mpi/mpi.cmake):
#   equal       np 1..4 x threads 1..2: the gathered mesh is the single-process mesh (gigatet
#               diff exits 0) and gigatet check accepts it, on uniform points, a shuffled grid,
#               a co-spherical set, a sphere surface and a dense cluster in a sparse set; a
#               thin slab whose later rounds' queries fetch points; a cube with a void, whose
#               queries must not change when far tile vertices skip the ball test (D11)
#   degenerate  a rank whose tile is empty, ranks without input points, tiny sets, duplicates
#               across ranks, the smallest ids all on one plane, --check
#   io          .bin (MPI-IO) and .xyz (rank 0) give the same mesh; .ele/.msh; .pvtu read by VTK;
#               the library's fallback to 64-bit ids (GTET_MPI_IDS32_LIMIT) gives the CLI the
#               same mesh and .pvtu pieces
#   bad_input   NaN on one rank (exit 2 everywhere, naming the global index), an allocation
#               failure on one rank (4 everywhere), coplanar input (3), a missing file (2),
#               usage (1), an unwritable output (2, no partial files): each under a time limit
#   api         the C API under mpirun (tests/mpi/test_mpi_api.c)
set -euo pipefail
group=$1 mpicli=$2 cli=$3 work=$4/$1 mpirun=$5 api=${6:-}
# Open MPI refuses root without these; set here only, for the tests
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# oversubscribed ranks yield instead of spinning in collectives (2 cores, up to 4 ranks)
export OMPI_MCA_mpi_yield_when_idle=1
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fails=0
run() { timeout 60 "$mpirun" --oversubscribe -np "$@"; }
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; fails=$((fails + 1)); }

# every rank's exit code, through a wrapper that logs it
each_rank_code() {  # each_rank_code NP EXPECTED LABEL -- args...
  local np=$1 want=$2 label=$3; shift 4
  rm -f codes.*
  set +e
  timeout 60 "$mpirun" --oversubscribe -np "$np" sh -c '"$@"; echo $? > codes.$OMPI_COMM_WORLD_RANK' sh "$@" \
      > out.txt 2> err.txt
  local to=$?
  set -e
  if [ "$to" = 124 ]; then bad "$label: timed out (hang)"; return; fi
  local codes; codes=$(cat codes.* 2>/dev/null | sort | uniq -c | tr -s ' ' | tr '\n' ';')
  local n; n=$(ls codes.* 2>/dev/null | wc -l)
  if [ "$n" = "$np" ] && [ "$(cat codes.* | sort -u)" = "$want" ]; then ok "$label: exit $want on all $np ranks"
  else bad "$label: want $want on $np ranks, got [$codes]"; cat err.txt; fi
}

shuffle() {  # shuffle IN OUT: the points of a .xyz in a fixed random order
  python3 -c "
import random, sys
random.seed(7)
p = [l for l in open(sys.argv[1]) if l.strip() and not l.startswith('#')]
random.shuffle(p)
open(sys.argv[2], 'w').writelines(p)" "$1" "$2"
}

same() {  # same NAME INPUT NP THREADS [extra args]: gathered == single process, and checked
  local name=$1 in=$2 np=$3 t=$4; shift 4
  if ! run "$np" "$mpicli" triangulate "$in" -t "$t" -o "d_$name.vtu" -q "$@"; then
    bad "$name np=$np t=$t: gigatet-mpi failed"; return; fi
  if ! "$cli" diff "ref_$name.vtu" "d_$name.vtu" -q; then bad "$name np=$np t=$t: differs"; return; fi
  if ! "$cli" check "d_$name.vtu" --points "$in" -q; then bad "$name np=$np t=$t: check"; return; fi
  ok "$name np=$np t=$t identical, checked"
}

ref() { "$cli" triangulate "$2" -o "ref_$1.vtu" -q; }

case "$group" in
equal)
  "$cli" generate uniform 6000 --seed 3 -o uniform.xyz -q
  "$cli" generate grid 4000 -o grid0.xyz -q; shuffle grid0.xyz grid.xyz
  "$cli" generate cospherical 700 --seed 3 -o cosph0.xyz -q; shuffle cosph0.xyz cosph.xyz
  "$cli" generate sphere 1000 --seed 3 -o sphere.xyz -q
  # a dense cluster (1e-3 cube) inside a sparse set
  python3 -c "
import random
random.seed(11)
with open('cluster.xyz', 'w') as f:
    for i in range(2000): f.write('%.17g %.17g %.17g\n' % tuple(random.random() for _ in range(3)))
    for i in range(3000): f.write('%.17g %.17g %.17g\n' % tuple(0.4 + 1e-3 * random.random() for _ in range(3)))"
  for s in uniform grid cosph sphere cluster; do
    ref "$s" "$s.xyz"
    for np in 1 2 3 4; do for t in 1 2; do same "$s" "$s.xyz" "$np" "$t"; done; done
  done
  # later rounds patch the new points' cavity (proofs/distributed.md D9): these sets need a
  # second round, and no rank may fall back to a whole new triangulation (a fallback hides a
  # wrong patch: the mesh stays right, only slower) nor find the cavity by testing every tet
  # instead of locating the new points (D10: the same hiding); --check: the patched mesh's
  # neighbour links, which the gathered mesh's comparison does not see (mpi_patch.c moves the
  # kept tets into the cavity's slots and redirects their neighbours' links, NOTES E80)
  # (and the hull facets counted, mpi_output.c match_facets: gigatet's count)
  # (on the sphere every ball holds most of the new points and the growth would give way to a
  # new triangulation past its budget, D10: GTET_MPI_PATCH_BUDGET=off keeps the patch there;
  # uniform points and the cluster must stay under the budget)
  for s in uniform cluster sphere; do for np in 2 4; do
    "$cli" triangulate "$s.xyz" --stats | tail -n 1 > ref_stats.json
    budget=; [ "$s" = sphere ] && budget=off
    if GTET_MPI_PATCH_BUDGET=$budget run "$np" -x GTET_MPI_PATCH_BUDGET "$mpicli" triangulate "$s.xyz" -q --stats --check > stats.json &&
       python3 -c "
import json, sys
d = json.load(open('stats.json'))
hull = json.load(open('ref_stats.json'))['hull_facets']
sys.exit(not (d['rounds'] >= 2 and d['hull_facets'] == hull and
              all(r['rebuilds'] == 0 and r['scans'] == 0 for r in d['per_rank'])))"; then
      ok "$s np=$np: later rounds patched, hull facets counted"
    else bad "$s np=$np: rounds/rebuilds/scans/hull facets: $(cat stats.json) $(cat ref_stats.json)"; fi
  done; done
  # D12: a round's tet queries answered from DT(tile + the queries' vertices) give the same
  # answers as the grid scans: GTET_MPI_LIFT=on (always) and =off (never) must give the same
  # mesh and the same ghost points on every rank, on sets with every insphere degenerate (grid,
  # co-spherical), on a sphere and on uniform points (GTET_MPI_DUMP=off: no rank sends the rest
  # of its tile after many tests, which the co-spherical set does at np 3 in the runs above)
  g() { python3 -c "import json, sys; print([r['ghost_points'] for r in json.loads(sys.stdin.read().splitlines()[-1])['per_rank']])"; }
  for s in uniform grid cosph sphere; do for np in 2 3; do
    a=$(GTET_MPI_LIFT=off run "$np" -x GTET_MPI_LIFT "$mpicli" triangulate "$s.xyz" -q --stats | g)
    if GTET_MPI_LIFT=on GTET_MPI_DUMP=off run "$np" -x GTET_MPI_LIFT -x GTET_MPI_DUMP \
         "$mpicli" triangulate "$s.xyz" -q --stats \
         -o "d_$s.vtu" > lift.json && "$cli" diff "ref_$s.vtu" "d_$s.vtu" -q &&
       [ -n "$a" ] && [ "$(g < lift.json)" = "$a" ]; then ok "$s np=$np: answers from DT(X) = scans ($a)"
    else bad "$s np=$np: GTET_MPI_LIFT=on: $(cat lift.json), ghosts with off: $a"; fi
  done; done
  # a tet's answer of more than NEAR_TET_MIN points is cut to those near the asker's box, as a
  # hull facet's is (mpi_query.c mx_answer_near; proofs step 6c): on 20k uniform points some
  # flat hull tets' answers are (answers_near > 0) and GTET_MPI_NEAR=off (whole answers) cuts
  # none, both giving the single-process mesh; GTET_MPI_NEAR=on cuts every tet's answer (an
  # answer left empty while a conflicting point was unsent would leave a wrong tet: the mesh
  # would differ), on uniform, grid, co-spherical and sphere sets (the grid's and the
  # co-spherical set's seeded layers may leave no answer to cut)
  "$cli" generate uniform 20000 --seed 3 -o u20k.xyz -q; ref u20k u20k.xyz
  nr() { python3 -c "import json, sys; d = json.loads(sys.stdin.read().splitlines()[-1]); print(sum(r['answers_near'] for r in d['per_rank']), sum(r['ghost_points'] for r in d['per_rank']))"; }
  for np in 2 3; do
    if run "$np" "$mpicli" triangulate u20k.xyz -q --stats -o d_u20k.vtu > near.json &&
       "$cli" diff ref_u20k.vtu d_u20k.vtu -q &&
       GTET_MPI_NEAR=off run "$np" -x GTET_MPI_NEAR "$mpicli" triangulate u20k.xyz -q --stats \
         -o d_u20k_off.vtu > whole.json && "$cli" diff ref_u20k.vtu d_u20k_off.vtu -q &&
       python3 -c "
import sys
(a, ga), (b, gb) = [map(int, l.split()) for l in sys.argv[1:]]
sys.exit(not (a > 0 and b == 0 and ga <= gb))" "$(nr < near.json)" "$(nr < whole.json)"; then
      ok "uniform 20k np=$np: large tet answers cut near the asker (cut, ghosts: $(nr < near.json); whole: $(nr < whole.json)), identical"
    else bad "uniform 20k np=$np: answers near: $(cat near.json) whole: $(cat whole.json)"; fi
  done
  for s in uniform grid cosph sphere; do for np in 2 3; do
    if GTET_MPI_NEAR=on run "$np" -x GTET_MPI_NEAR "$mpicli" triangulate "$s.xyz" -q --stats \
         -o "d_$s.vtu" > near.json && "$cli" diff "ref_$s.vtu" "d_$s.vtu" -q &&
       { [ "$s" = grid ] || [ "$s" = cosph ] || [ "$(nr < near.json | cut -d' ' -f1)" -gt 0 ]; }; then
      ok "$s np=$np: every tet answer cut near the asker ($(nr < near.json | cut -d' ' -f1)), identical"
    else bad "$s np=$np: GTET_MPI_NEAR=on: $(cat near.json)"; fi
  done; done
  # the sphere's answers are near-linear: the exact tests they make (answer_tests) stay under
  # 100 a point where the scans made ~n/2 a point (20k points, np 2: 4.3e8 tests, 44 s before
  # D12), and the same counter sees the scans' quadratic cost with GTET_MPI_LIFT=off (4000
  # points: over 100 a point)
  "$cli" generate sphere 20000 --seed 1 -o sph20k.bin -q; ref sph20k sph20k.bin
  "$cli" generate sphere 4000 --seed 2 -o sph4k.bin -q; ref sph4k sph4k.bin
  t() { python3 -c "import json, sys; print(max(r['answer_tests'] for r in json.loads(sys.stdin.read().splitlines()[-1])['per_rank']))"; }
  # identical_bounded NAME INPUT BOUND LABEL: at np 2 and 4 the mesh of INPUT is ref_NAME's and
  # a rank's answers make at most BOUND exact tests
  identical_bounded() {
    for np in 2 4; do
      if run "$np" "$mpicli" triangulate "$2" -q --stats -o "d_$1.vtu" > st.json &&
         "$cli" diff "ref_$1.vtu" "d_$1.vtu" -q && [ "$(t < st.json)" -le "$3" ]; then
        ok "$4 np=$np: identical, $(t < st.json) exact tests in a rank's answers"
      else bad "$4 np=$np: $(cat st.json)"; fi
    done
  }
  identical_bounded sph20k sph20k.bin 2000000 "sphere 20k"
  a=$(run 2 "$mpicli" triangulate sph4k.bin -q --stats | t)
  b=$(GTET_MPI_LIFT=off run 2 -x GTET_MPI_LIFT "$mpicli" triangulate sph4k.bin -q --stats | t)
  if [ -n "$a" ] && [ -n "$b" ] && [ "$a" -le 400000 ] && [ "$b" -gt 400000 ]; then
    ok "sphere 4k np=2: $a exact tests in a rank's answers ($b with the scans)"
  else bad "sphere 4k np=2: $a exact tests in a rank's answers, $b with the scans (bound 400000)"; fi
  # a surface sample (a torus, 6000 points): the tets' conflict sets from DT(X) are large, and
  # a rank whose searches for an asker go over their limit sends it the rest of its tile (D12's
  # complete answer; it does at np 2 and 4): identical meshes, and a rank's answers stay under
  # 100 exact tests a point
  python3 -c "
import math, random
r = random.Random(5)
with open('torus.xyz', 'w') as f:
    for i in range(6000):
        u, v = 2 * math.pi * r.random(), 2 * math.pi * r.random()
        f.write('%.17g %.17g %.17g\\n' % ((1 + 0.3 * math.cos(v)) * math.cos(u), (1 + 0.3 * math.cos(v)) * math.sin(u), 0.3 * math.sin(v)))"
  ref torus torus.xyz
  identical_bounded torus torus.xyz 600000 "torus"
  # a thin slab (3000 points, z in [0, 0.02]): here the tets a patched round makes have
  # circumballs reaching points of other tiles that no earlier query fetched, so the mesh is
  # right only if a later round queries its new tets (proofs/distributed.md 6b): with no
  # queries after round 1 it needs 2 rounds instead of 4 and differs at np 2 and 4; --check
  # as above
  python3 -c "
import random
r = random.Random(2)
with open('slab.xyz', 'w') as f:
    for i in range(3000):
        x = r.random(); y = r.random(); z = 0.02 * r.random()
        f.write('%.17g %.17g %.17g\n' % (x, y, z))"
  ref slab slab.xyz
  for np in 2 4; do same slab slab.xyz "$np" 1 --check; done
  # a cube with a spherical void across the first split: a tet with a far tile vertex sends
  # no query (proofs/distributed.md D11, mpi_query.c mx_grid_far), which must change nothing,
  # not even the queries sent (such a tet's ball misses every other tile's box): the counts
  # equal GTET_MPI_FAR=off's.  Without the empty-block test (far_cell_covered) the void's wall
  # counts as far and np 2-4 send fewer queries (the mesh happens to stay right here)
  python3 -c "
import random
r = random.Random(6)
n = 0
with open('void.xyz', 'w') as f:
    while n < 60000:
        x, y, z = r.random(), r.random(), r.random()
        if (x - 0.5)**2 + (y - 0.47)**2 + (z - 0.52)**2 < 0.09: continue
        f.write('%.17g %.17g %.17g\n' % (x, y, z)); n += 1"
  ref void void.xyz
  q() { python3 -c "import json, sys; print([r['queries_sent'] for r in json.load(sys.stdin)['per_rank']])"; }
  for np in 2 3 4; do
    same void void.xyz "$np" 1
    a=$(run "$np" "$mpicli" triangulate void.xyz -q --stats | q)
    b=$(GTET_MPI_FAR=off run "$np" -x GTET_MPI_FAR "$mpicli" triangulate void.xyz -q --stats | q)
    if [ -n "$a" ] && [ "$a" = "$b" ]; then ok "void np=$np: far vertices change no query ($a)"
    else bad "void np=$np: queries sent $a, with GTET_MPI_FAR=off $b"; fi
  done ;;
degenerate)
  # more than half the points on the plane x = 0 and x the longest axis: the kd split is at
  # x = 0 and the first rank's tile is empty
  python3 -c "
import random
random.seed(12)
with open('emptytile.xyz', 'w') as f:
    for i in range(1200): f.write('0 %.17g %.17g\n' % (0.1 * random.random(), 0.1 * random.random()))
    for i in range(800): f.write('%.17g %.17g %.17g\n' % (10 * random.random(), 0.1 * random.random(), 0.1 * random.random()))"
  ref emptytile emptytile.xyz
  for np in 2 3 4; do for t in 1 2; do same emptytile emptytile.xyz "$np" "$t" --check; done; done
  # 5 and 7 points: ranks with no input points, tiles of one point
  printf '0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n' > five.xyz
  printf '0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n0.2 0.3 0.1\n-1 2 0.5\n' > seven.xyz
  ref five five.xyz; ref seven seven.xyz
  for np in 2 3 4; do same five five.xyz "$np" 1 --check; same seven seven.xyz "$np" 2; done
  # duplicates everywhere, across ranks (and -0.0 against +0.0)
  python3 -c "
import random
random.seed(13)
p = [tuple(random.randint(0, 9) * 0.125 for _ in range(3)) for i in range(400)]
q = [random.choice(p) for i in range(1600)] + p
random.shuffle(q)
with open('dups.xyz', 'w') as f:
    f.write('-0.0 0 0\n')
    for x in q: f.write('%r %r %r\n' % x)
    f.write('0 -0.0 0\n')"
  ref dups dups.xyz
  for np in 1 2 3 4; do same dups dups.xyz "$np" 2 --check; done
  # the 300 smallest ids on one plane, 3 points off it: the seeds' last stage finds no point
  # among a tile's smallest ids and scans the whole tile (mpi_ids.c smallest_ids, NOTES.md E228)
  python3 -c "
import random
r = random.Random(14)
with open('plane300.xyz', 'w') as f:
    for i in range(300): f.write('%.17g %.17g 0\n' % (r.random(), r.random()))
    for i in range(3): f.write('%.17g %.17g %.17g\n' % (r.random(), r.random(), 0.5 + r.random()))"
  ref plane300 plane300.xyz
  for np in 1 2 3; do same plane300 plane300.xyz "$np" 1 --check; done ;;
io)
  "$cli" generate uniform 5000 --seed 9 -o u.bin -q
  "$cli" generate uniform 5000 --seed 9 -o u.xyz -q
  ref u u.bin
  for np in 1 3; do same u u.bin "$np" 1; same u u.xyz "$np" 2 --check; done
  for ext in ele msh; do
    run 3 "$mpicli" triangulate u.bin -o "d.$ext" -q
    if "$cli" diff ref_u.vtu "d.$ext" -q; then ok ".$ext identical"; else bad ".$ext differs"; fi
  done
  run 4 "$mpicli" triangulate u.bin -o pieces.pvtu -q
  if /usr/bin/python3 - <<'PY'   # Debian's python3 has python3-vtk9
import vtk
r = vtk.vtkXMLPUnstructuredGridReader(); r.SetFileName('pieces.pvtu'); r.Update()
g = r.GetOutput()
tets = set()
for c in range(g.GetNumberOfCells()):
    cell = g.GetCell(c)
    assert cell.GetCellType() == 10
    tets.add(tuple(sorted(tuple(g.GetPoint(cell.GetPointId(i))) for i in range(4))))
r2 = vtk.vtkXMLUnstructuredGridReader(); r2.SetFileName('ref_u.vtu'); r2.Update()
h = r2.GetOutput()
ref = set()
for c in range(h.GetNumberOfCells()):
    cell = h.GetCell(c)
    ref.add(tuple(sorted(tuple(h.GetPoint(cell.GetPointId(i))) for i in range(4))))
assert g.GetNumberOfCells() == len(tets) == len(ref) and tets == ref, (len(tets), len(ref))
print('pvtu: %d pieces, %d tets, the single-process set' % (r.GetNumberOfPieces(), len(tets)))
PY
  then ok ".pvtu read by VTK, identical"; else bad ".pvtu"; fi
  # the CLI asks for 32-bit ids; with GTET_MPI_IDS32_LIMIT below the counts the library falls
  # back to 64-bit ids: the same mesh, checked, and the same .pvtu pieces byte for byte
  export GTET_MPI_IDS32_LIMIT=100
  for np in 1 3; do same u u.bin "$np" 1 --check; done
  run 4 "$mpicli" triangulate u.bin -o pieces64.pvtu -q
  if run 2 "$mpicli" triangulate u.bin --stats | python3 -c "import json,sys; assert json.load(sys.stdin)['id_bits'] == 64"
  then ok "--stats: 64-bit ids past GTET_MPI_IDS32_LIMIT"; else bad "--stats id_bits with the limit"; fi
  unset GTET_MPI_IDS32_LIMIT
  p64=0
  for q in 0 1 2 3; do cmp -s "pieces_$q.vtu" "pieces64_$q.vtu" || p64=1; done
  if [ "$p64" = 0 ]; then ok ".pvtu pieces of a 64-bit result identical"; else bad ".pvtu 64-bit pieces differ"; fi
  # --stats is one JSON object
  if run 2 "$mpicli" triangulate u.bin --stats | python3 -c "import json,sys; d=json.load(sys.stdin); assert d['ranks']==2 and len(d['per_rank'])==2 and d['id_bits']==32"
  then ok "--stats JSON"; else bad "--stats"; fi ;;
bad_input)
  "$cli" generate uniform 4000 --seed 4 -o u.bin -q
  # a NaN at global index 3500 (in the last rank's slice)
  python3 -c "
import struct
b = bytearray(open('u.bin','rb').read())
struct.pack_into('<d', b, 8 + 24 * 3500 + 8, float('nan'))
open('nan.bin','wb').write(b)"
  each_rank_code 4 2 "NaN on rank 3" -- "$mpicli" triangulate nan.bin -q
  if grep -q "input point 3500 " err.txt; then ok "NaN message names global index 3500"; else bad "NaN message: $(cat err.txt)"; fi
  each_rank_code 3 2 "NaN, -o" -- "$mpicli" triangulate nan.bin -o nan_out.vtu -q
  if ls nan_out* 2>/dev/null; then bad "partial output after NaN"; else ok "no output after NaN"; fi
  for k in 0 3 9 20 40; do
    GTET_MPI_FAIL_ALLOC="1:$k" each_rank_code 3 4 "allocation $k fails on rank 1" -- "$mpicli" triangulate u.bin -q
  done
  # a sphere's rounds answer from DT(tile + the queries' vertices) (D12): rank 1's allocations
  # 79-90 are that triangulation's (its map, points, adjacency, tets, the searches' queue)
  "$cli" generate sphere 3000 --seed 4 -o sph3k.bin -q
  for k in 70 76 79 80 82 84 86 88 90 96; do
    GTET_MPI_FAIL_ALLOC="1:$k" each_rank_code 2 4 "sphere: allocation $k fails on rank 1" -- "$mpicli" triangulate sph3k.bin -q
  done
  GTET_MPI_FAIL_ALLOC="2:25" each_rank_code 4 4 "allocation fails on rank 2 (-o)" -- "$mpicli" triangulate u.bin -o oom.vtu -q
  if ls oom* 2>/dev/null; then bad "partial output after OOM"; else ok "no output after OOM"; fi
  python3 -c "
import random
random.seed(3)
with open('flat.xyz','w') as f:
    for i in range(3000):
        x, y = random.randint(-1000, 1000), random.randint(-1000, 1000)
        f.write('%d %d %d\n' % (x, y, 2 * x - y))"
  each_rank_code 4 3 "coplanar" -- "$mpicli" triangulate flat.xyz -q
  if grep -q "coplanar" err.txt; then ok "coplanar message"; else bad "coplanar message: $(cat err.txt)"; fi
  printf '1 2 3\n1 2 3\n' > point.xyz
  each_rank_code 3 3 "one distinct point" -- "$mpicli" triangulate point.xyz -q
  each_rank_code 2 2 "missing file" -- "$mpicli" triangulate nosuch.bin -q
  each_rank_code 2 2 "missing .xyz" -- "$mpicli" triangulate nosuch.xyz -q
  printf 'abc' > short.bin
  each_rank_code 3 2 "truncated .bin" -- "$mpicli" triangulate short.bin -q
  each_rank_code 2 1 "usage" -- "$mpicli" triangulate
  each_rank_code 2 1 "bad -t" -- "$mpicli" triangulate u.bin -t x
  each_rank_code 2 2 "unwritable output" -- "$mpicli" triangulate u.bin -o /nonexistent/dir/x.vtu -q
  each_rank_code 2 2 "unwritable .pvtu" -- "$mpicli" triangulate u.bin -o /nonexistent/dir/x.pvtu -q
  # NOTES.md E156: every rank killed by SIGTERM while writing (what a batch system's time limit
  # or scancel does; mpirun itself does not pass a signal on before the ranks finish): each
  # rank's handler removes its temporaries, and no output appears
  "$cli" generate uniform 300000 --seed 4 -o sig.bin -q
  mkdir -p sig
  for o in vtu pvtu; do
    rm -rf sig/*
    "$mpirun" --oversubscribe -np 2 "$mpicli" triangulate sig.bin -o "sig/m.$o" -q > /dev/null 2>&1 &
    pid=$!
    for _ in $(seq 6000); do  # until a temporary has data (at most 60 s)
      [ -n "$(find sig -name "*.tmp-*" -size +0)" ] && break
      sleep 0.01
    done
    if [ -z "$(find sig -name "*.tmp-*" -size +0)" ]; then bad "SIGTERM .$o: no temporary seen"; fi
    pkill -TERM -f "$mpicli triangulate sig.bin" || true
    set +e; timeout 60 tail --pid="$pid" -f /dev/null; wait "$pid"; set -e
    left=$(find sig -type f)
    if [ -z "$left" ]; then ok "ranks killed (SIGTERM) while writing .$o: nothing left"
    else bad "ranks killed (SIGTERM) while writing .$o left: $left"; fi
  done ;;
api)
  run 1 "$api" && ok "api np=1" || bad "api np=1"
  run 3 "$api" && ok "api np=3" || bad "api np=3"
  run 4 "$api" && ok "api np=4" || bad "api np=4" ;;
*) echo "unknown group $group"; exit 2 ;;
esac
echo "$group: $fails failure(s)"
[ "$fails" = 0 ]
