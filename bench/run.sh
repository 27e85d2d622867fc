#!/usr/bin/env bash
# bench/run.sh -- time gigatet against CGAL, TetGen and HXT on the same inputs, in the same run.
#
#   bench/run.sh [--runs N] [--inputs "u1M u4M g100"] [--big] [--quick] [--tools "..."]
#                [--build DIR] [--out FILE.md]
#
# Inputs (generated once into bench/data/ by tests/cgal/pointsets.py, seed 1, as .bin and
# TetGen .node): u1M, u4M = 1M / 4M uniform points in [0,1)^3; g100 = the 100^3 integer grid
# (shuffled); --big adds u10M; --quick uses u100k and g20 instead (for development).
# Tools (a missing one is skipped with a message):
#   cgal_seq   CGAL Delaunay_triangulation_3, Epick, range insertion (spatial sort), 1 thread
#   cgal_par2  the same with Parallel_tag, Spatial_lock_grid_3 and 2 TBB threads
#   tetgen     Debian's tetgen -NEF (Delaunay only, nothing written); its "Delaunay seconds"
#   hxt1 hxt2  HXT via Debian's libgmsh: tetrahedralize() with Mesh.Algorithm3D = 10
#   gigatet1 gigatet2   build/gigatet triangulate FILE.bin -t T --stats
# Runs are interleaved: for each repetition, every input, every tool -- so a slow phase of the
# (shared) machine hits all tools alike -- and each repetition runs the tools in its own order
# (a shuffle seeded by the repetition's number, printed in the log): a run is slowed by some
# predecessors (a memory-heavy peer just before it), so a fixed order would tax the same tool
# every time.  Seconds are each tool's own timing of the meshing
# (file reading excluded), both wall and process CPU time (all threads): on this shared
# machine the other agents' load inflates wall time, and CPU time is the fairer figure for a
# one-thread run; TetGen reports only CPU time (clock()).  gigatet: its --stats total (else
# the process's wall time) and the process's CPU time, marked.  Peak RSS is /usr/bin/time's
# %M for the whole process (input arrays included), bytes/tet = RSS / tets.  The load average
# before and after the run goes into the report.
# Every run is bounded: BENCH_TIMEOUT seconds (default 900) and BENCH_MEM_GB GiB of virtual
# memory (default 20).  Output: a markdown table on stdout and in bench/results/<date>.md;
# raw measurements in bench/results/<date>.tsv.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)

runs=5
inputs="u1M u4M g100"
build="$root/build"
tools="cgal_seq cgal_par2 tetgen hxt1 hxt2 gigatet1 gigatet2"
out=""
while (($#)); do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --inputs) inputs=$2; shift 2 ;;
    --big) inputs="$inputs u10M"; shift ;;
    --quick) inputs="u100k g20"; shift ;;
    --tools) tools=$2; shift 2 ;;
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "bench/run.sh: unknown argument $1" >&2; exit 1 ;;
  esac
done

timeout_s=${BENCH_TIMEOUT:-900}
mem_kb=$(( ${BENCH_MEM_GB:-20} * 1024 * 1024 ))
if [ ! -x /usr/bin/time ]; then
  echo "bench/run.sh: /usr/bin/time is missing (Debian package 'time'): apt-get install time" >&2
  exit 1
fi
data="$here/data"
results="$here/results"
mkdir -p "$data" "$results"
stamp=$(date -u +%Y-%m-%d-%H%M)
[ -n "$out" ] || out="$results/$stamp.md"
raw="${out%.md}.tsv"
gen="$root/tests/cgal/pointsets.py"

# ---- inputs
input_args() {  # name -> "KIND N" for pointsets.py
  case "$1" in
    u100k) echo "uniform 100000" ;;
    u1M) echo "uniform 1000000" ;;
    u4M) echo "uniform 4000000" ;;
    u10M) echo "uniform 10000000" ;;
    g20) echo "grid 20" ;;
    g100) echo "grid 100" ;;
    *) echo "bench/run.sh: unknown input $1" >&2; exit 1 ;;
  esac
}
for in in $inputs; do
  for ext in bin node; do
    f="$data/$in.$ext"
    if [ ! -s "$f" ]; then
      echo "bench: generating $f" >&2
      # shellcheck disable=SC2046
      python3 "$gen" $(input_args "$in") --seed 1 -o "$data/$in.tmp.$ext" &&  # format by extension
        mv "$data/$in.tmp.$ext" "$f"
    fi
  done
done

# ---- tools: each prints "SECONDS TETS" for one input, or fails
have_tool() {
  case "$1" in
    cgal_seq|cgal_par2) [ -x "$build/bench/bench_cgal" ] ;;
    tetgen) command -v tetgen >/dev/null ;;
    hxt1|hxt2) [ -x "$build/bench/hxt_peer" ] ;;
    gigatet1|gigatet2) [ -x "$build/gigatet" ] ;;
    *) return 1 ;;
  esac
}
tool_cmd() {  # tool input -> sets the array cmd (paths with spaces stay one word)
  local t=$1 in=$2
  case "$t" in
    cgal_seq) cmd=("$build/bench/bench_cgal" --time "$data/$in.bin") ;;
    cgal_par2) cmd=("$build/bench/bench_cgal" --time --parallel 2 "$data/$in.bin") ;;
    tetgen) cmd=(tetgen -NEF "$data/$in.node") ;;
    hxt1) cmd=("$build/bench/hxt_peer" -t 1 "$data/$in.bin") ;;
    hxt2) cmd=("$build/bench/hxt_peer" -t 2 "$data/$in.bin") ;;
    gigatet1) cmd=("$build/gigatet" triangulate "$data/$in.bin" -t 1 --stats) ;;
    gigatet2) cmd=("$build/gigatet" triangulate "$data/$in.bin" -t 2 --stats) ;;
  esac
}
active=""
for t in $tools; do
  if have_tool "$t"; then
    active="$active $t"
  else
    case "$t" in
      gigatet*) echo "bench: skipping $t: $build/gigatet does not exist yet (the CLI is not merged)" >&2 ;;
      cgal*) echo "bench: skipping $t: $build/bench/bench_cgal not built (CGAL missing?)" >&2 ;;
      hxt*) echo "bench: skipping $t: $build/bench/hxt_peer not built (libgmsh-dev missing?)" >&2 ;;
      tetgen) echo "bench: skipping tetgen: not installed (Debian package tetgen)" >&2 ;;
      *) echo "bench: unknown tool $t" >&2 ;;
    esac
  fi
done
[ -n "$active" ] || { echo "bench: no tool to run" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'tool\tinput\trun\tseconds\tcpu\ttets\trss_kb\twall\tnote\n' > "$raw"
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for ((r = 1; r <= runs; r++)); do
  # shellcheck disable=SC2086
  order=$(python3 -c 'import random, sys; t = sys.argv[2:]; random.Random(int(sys.argv[1])).shuffle(t); print(" ".join(t))' "$r" $active)
  echo "bench: run $r order: $order" >&2
  for in in $inputs; do
    for t in $order; do
      tool_cmd "$t" "$in"
      set +e
      ( ulimit -v "$mem_kb"; cd "$tmp" && exec /usr/bin/time -f '%M %e %U %S' -o "$tmp/time" \
          timeout "$timeout_s" "${cmd[@]}" ) > "$tmp/out" 2> "$tmp/err"
      rc=$?
      set -e
      read -r rss wall ucpu scpu < <(tail -n 1 "$tmp/time")
      pcpu=$(awk -v u="${ucpu:-0}" -v s="${scpu:-0}" 'BEGIN { print u + s }')
      parsed=$(python3 "$here/parse_output.py" "$t" "$tmp/out" "$wall" "$pcpu") || parsed=""
      if [ "$rc" -ne 0 ] || [ -z "$parsed" ]; then
        echo "bench: $t on $in (run $r) failed, exit $rc: $(tail -n 3 "$tmp/err" "$tmp/out" | tr '\n' ' ')" >&2
        printf '%s\t%s\t%d\tnan\tnan\t0\t%s\t%s\tfailed rc=%d\n' "$t" "$in" "$r" "${rss:-0}" "${wall:-0}" "$rc" >> "$raw"
        continue
      fi
      read -r secs cpu tets note <<< "$parsed"
      printf '%s\t%s\t%d\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$in" "$r" "$secs" "$cpu" "$tets" "$rss" "$wall" "${note:-}" >> "$raw"
      echo "bench: run $r $in $t: wall ${secs}s cpu ${cpu}s ${tets} tets ${rss} KiB" >&2
    done
  done
done

load_after=$(cut -d' ' -f1-3 /proc/loadavg)
python3 "$here/report.py" "$raw" --runs "$runs" --load "$load_before / $load_after" --commands "$(for t in $active; do tool_cmd "$t" '<input>'; echo "${cmd[*]}"; done)" > "$out"
cat "$out"
echo "bench: wrote $out and $raw" >&2
