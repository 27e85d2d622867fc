#!/usr/bin/env bash
# bench/mpi_bench.sh [BUILD_DIR] [RUNS] -- the distributed mode's benchmark (not a test).
#  1. 4M uniform points: `mpirun -np 2 gigatet-mpi -t 1` against `gigatet -t 2` (goal: <= 1.25x),
#     RUNS interleaved repetitions, medians; wall seconds of the whole command and the
#     library's own seconds (gigatet's summary `seconds`, gigatet-mpi's per-rank total);
#  2. ghost points per rank and bytes sent per point (from --stats);
#  3. weak scaling: -np 4 (oversubscribed on a 2-core machine) with 1M points per rank:
#     ghost and message volumes.
# Prints one JSON line per run and a summary table; the model of 10^10 points on 64 nodes
# built from these figures is in NOTES.md.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
b=${1:-$here/build-mpi}
runs=${2:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d /tmp/gtet-mpi-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$b/gigatet" generate uniform 4000000 --seed 1 -o "$work/u4M.bin" -q
results=$work/results.txt
for r in $(seq "$runs"); do
  order="single mpi2"
  if [ $((r % 2)) = 0 ]; then order="mpi2 single"; fi
  for what in $order; do
    if [ "$what" = single ]; then
      s=$(date +%s.%N)
      line=$("$b/gigatet" triangulate "$work/u4M.bin" -t 2)
      e=$(date +%s.%N)
      lib=$(echo "$line" | sed -n 's/.*seconds=\([0-9.]*\).*/\1/p')
      echo "single wall=$(echo "$e - $s" | bc) lib=$lib" | tee -a "$results"
    else
      s=$(date +%s.%N)
      json=$(mpirun -np 2 --bind-to none "$b/gigatet-mpi" triangulate "$work/u4M.bin" -t 1 --stats)
      e=$(date +%s.%N)
      echo "$json" > "$work/mpi2-$r.json"
      lib=$(echo "$json" | python3 -c "import json,sys; d=json.load(sys.stdin); print(max(r['seconds']['total'] for r in d['per_rank']))")
      echo "mpi2 wall=$(echo "$e - $s" | bc) lib=$lib" | tee -a "$results"
    fi
  done
done
python3 - "$results" "$work/mpi2-1.json" <<'PY'
import sys, json, statistics as st
rows = [l.split() for l in open(sys.argv[1])]
def med(kind, key):
    return st.median(float(r[[x.split('=')[0] for x in r].index(key)].split('=')[1]) for r in rows if r[0] == kind)
sw, sl, mw, ml = med('single','wall'), med('single','lib'), med('mpi2','wall'), med('mpi2','lib')
print(f"4M uniform: gigatet -t 2: wall {sw:.2f} s (kernel {sl:.2f} s); mpirun -np 2 -t 1: wall {mw:.2f} s (library {ml:.2f} s); ratio wall {mw/sw:.3f}, library/kernel {ml/sl:.3f}")
d = json.load(open(sys.argv[2]))
n = d['vertices']
for r in d['per_rank']:
    print(f"  rank {r['rank']}: tile {r['tile_points']}, ghosts {r['ghost_points']} ({100*r['ghost_points']/r['tile_points']:.2f}%), seeded {r['ghost_seeded']}, queries {r['queries_sent']}, bytes sent {r['bytes_sent']} ({r['bytes_sent']/r['tile_points']:.1f} B/point; ghost part {r['bytes_sent_ghost']/r['tile_points']:.2f} B/point), seconds {r['seconds']}")
print(f"  rounds {d['rounds']}")
PY
# weak scaling volumes: 1M points per rank, 4 ranks (oversubscribed: times are not meaningful)
"$b/gigatet" generate uniform 4000000 --seed 2 -o "$work/w4M.bin" -q
OMPI_MCA_mpi_yield_when_idle=1 mpirun -np 4 --oversubscribe --bind-to none "$b/gigatet-mpi" triangulate "$work/w4M.bin" -t 1 --stats > "$work/np4.json"
python3 - "$work/np4.json" <<'PY'
import sys, json
d = json.load(open(sys.argv[1]))
print(f"weak scaling, 4 ranks x 1M points (oversubscribed): rounds {d['rounds']}")
for r in d['per_rank']:
    print(f"  rank {r['rank']}: tile {r['tile_points']}, ghosts {r['ghost_points']} ({100*r['ghost_points']/r['tile_points']:.2f}%), queries {r['queries_sent']}, bytes sent {r['bytes_sent']/r['tile_points']:.1f} B/point (ghost part {r['bytes_sent_ghost']/r['tile_points']:.2f}), seconds total {r['seconds']['total']:.2f} (triangulate {r['seconds']['triangulate']:.2f}, exchange {r['seconds']['exchange']:.2f})")
PY
