#!/usr/bin/env bash
# bench/mpi_bench.sh [BUILD_DIR] [RUNS] [SIZES] -- the distributed mode's benchmark (not a test).
#  1. for each size in SIZES (default "1000000 4000000") uniform points: `mpirun -np 2
#     gigatet-mpi -t 1` against `gigatet -t 2` (goal at 4M: <= 1.25x), RUNS interleaved
#     repetitions, medians of the wall seconds of the whole command and of the library's own
#     seconds (gigatet's summary `seconds`, gigatet-mpi's per-rank total), of the CPU seconds
#     (user + sys of gigatet, summed over the ranks for gigatet-mpi), of the peak RSS (the
#     largest rank's for gigatet-mpi), the load average
#     before each run; per-rank phase seconds, ghost points, queries and bytes sent per point
#     of the median MPI run;
#  2. weak scaling: -np 4 (oversubscribed on a 2-core machine, so the times are CPU shares, not
#     speed) with 1M points per rank: ghost points, queries, bytes per point, phase seconds.
# The model of 10^10 points on 64 nodes built from these figures is in NOTES.md.
# Memory: 4M points at np 2 take ~2 GB a rank (4.1 GB in all) and part 2 ~4.2 GB; on a shared
# machine give SIZES "1000000" and WEAK=0 (skips part 2).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
b=${1:-$here/build-mpi}
runs=${2:-3}
sizes=${3:-"1000000 4000000"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d /tmp/gtet-mpi-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
load() { cut -d' ' -f1 /proc/loadavg; }
for n in $sizes; do
  "$b/gigatet" generate uniform "$n" --seed 1 -o "$work/u.bin" -q
  results=$work/results-$n.txt
  for r in $(seq "$runs"); do
    order="single mpi2"
    if [ $((r % 2)) = 0 ]; then order="mpi2 single"; fi
    for what in $order; do
      l=$(load)
      s=$(date +%s.%N)
      rm -f "$work"/cpu.*
      if [ "$what" = single ]; then
        line=$(/usr/bin/time -f "%U %S %M" -o "$work/cpu.0" "$b/gigatet" triangulate "$work/u.bin" -t 2)
        e=$(date +%s.%N)
        lib=$(echo "$line" | sed -n 's/.*seconds=\([0-9.]*\).*/\1/p')
      else
        # each rank under /usr/bin/time: CPU seconds (user + sys) summed over the ranks
        json=$(mpirun -np 2 --bind-to none sh -c '/usr/bin/time -f "%U %S %M" -o "$0/cpu.$OMPI_COMM_WORLD_RANK" "$@"' \
               "$work" "$b/gigatet-mpi" triangulate "$work/u.bin" -t 1 --stats)
        e=$(date +%s.%N)
        echo "$json" > "$work/mpi2-$n-$r.json"
        lib=$(echo "$json" | python3 -c "import json,sys; d=json.load(sys.stdin); print(max(r['seconds']['total'] for r in d['per_rank']))")
      fi
      cpu=$(cat "$work"/cpu.* | awk '{c += $1 + $2} END {printf "%.2f", c}')
      rss=$(cat "$work"/cpu.* | awk '$3 > m {m = $3} END {printf "%d", m / 1024}')
      echo "$what run=$r wall=$(echo "$e - $s" | bc) lib=$lib cpu=$cpu rssMiB=$rss load=$l" | tee -a "$results"
    done
  done
  python3 - "$results" "$work" "$n" <<'PY'
import sys, json, statistics as st
rows = [dict(x.split('=') for x in l.split()[1:]) | {'kind': l.split()[0]} for l in open(sys.argv[1])]
def med(kind, key): return st.median(float(r[key]) for r in rows if r['kind'] == kind)
sw, sl, mw, ml = med('single','wall'), med('single','lib'), med('mpi2','wall'), med('mpi2','lib')
sc, mc = med('single','cpu'), med('mpi2','cpu')
loads = [float(r['load']) for r in rows]
n = int(sys.argv[3])
print(f"{n} uniform: gigatet -t 2: wall {sw:.2f} s (library {sl:.2f} s); mpirun -np 2 -t 1: wall {mw:.2f} s (library {ml:.2f} s); ratio wall {mw/sw:.3f}, library {ml/sl:.3f}; CPU (user+sys, all ranks) {sc:.2f} vs {mc:.2f} s, ratio {mc/sc:.3f}; peak RSS {med('single','rssMiB'):.0f} MiB vs {med('mpi2','rssMiB'):.0f} MiB a rank; load {min(loads):.1f}-{max(loads):.1f}")
mp = sorted((float(r['lib']), r['run']) for r in rows if r['kind'] == 'mpi2')
d = json.load(open(f"{sys.argv[2]}/mpi2-{n}-{mp[len(mp)//2][1]}.json"))
print(f"  median MPI run: rounds {d['rounds']}")
for r in d['per_rank']:
    s = r['seconds']
    print(f"  rank {r['rank']}: tile {r['tile_points']}, ghosts {r['ghost_points']} ({100*r['ghost_points']/r['tile_points']:.2f}%, seeded {r['ghost_seeded']}), rebuilds {r.get('rebuilds', 0)}, scans {r.get('scans', 0)}, queries {r['queries_sent']}, {r['bytes_sent']/r['tile_points']:.1f} B sent/point (ghosts and queries {r['bytes_sent_ghost']/r['tile_points']:.2f}); seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in s.items()))
PY
done
# weak scaling volumes: 1M points per rank, 4 ranks (oversubscribed: times are CPU shares)
if [ "${WEAK:-1}" = 0 ]; then exit 0; fi
"$b/gigatet" generate uniform 4000000 --seed 2 -o "$work/w4M.bin" -q
l=$(load)
OMPI_MCA_mpi_yield_when_idle=1 /usr/bin/time -f "%M" -o "$work/rss" mpirun -np 4 --oversubscribe --bind-to none "$b/gigatet-mpi" triangulate "$work/w4M.bin" -t 1 --stats > "$work/np4.json"
python3 - "$work/np4.json" "$l" "$(cat "$work/rss")" <<'PY'
import sys, json
d = json.load(open(sys.argv[1]))
print(f"weak scaling, 4 ranks x 1M points (oversubscribed, load {sys.argv[2]}, largest process {int(sys.argv[3])/1024:.0f} MiB): rounds {d['rounds']}")
for r in d['per_rank']:
    s = r['seconds']
    print(f"  rank {r['rank']}: tile {r['tile_points']}, ghosts {r['ghost_points']} ({100*r['ghost_points']/r['tile_points']:.2f}%, seeded {r['ghost_seeded']}), rebuilds {r.get('rebuilds', 0)}, scans {r.get('scans', 0)}, queries {r['queries_sent']}, {r['bytes_sent']/r['tile_points']:.1f} B sent/point (ghosts and queries {r['bytes_sent_ghost']/r['tile_points']:.2f}); seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in s.items()))
PY
