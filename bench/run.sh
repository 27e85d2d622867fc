#!/usr/bin/env bash
# bench/run.sh -- time gigatet against CGAL, TetGen and HXT on the same inputs, in the same run.
#
#   bench/run.sh [--runs N] [--inputs "u1M u4M g100"] [--big] [--quick] [--issue18] [--tools "..."]
#                [--build DIR] [--out FILE.md]
#
# Inputs (generated once into bench/data/, seed 1, as .bin and TetGen .node): a name is a
# family and a size (100k, 200k, 1M, 4M, 10M, ...; the grid gK is the K^3 grid):
#   uSIZE      uniform in [0,1)^3                               (tests/cgal/pointsets.py)
#   gK         the K^3 integer grid, shuffled                   (pointsets.py)
#   cluSIZE    half uniform in [0,1)^3, half in the cube [0.5, 0.501)^3 (pointsets.py halfcube)
#   mixSIZE    uniform points each scaled by 10^-300, 10^-150, 1, 10^150 or 10^300 (pointsets.py mixed)
#   sphSIZE    `gigatet generate sphere`      (on the unit sphere, within rounding)
#   parSIZE    `gigatet generate paraboloid`  (the lifted integer grid, ~SIZE points)
#   scanASIZE  `gigatet generate surface --mesh armadillo.off`: uniform on the triangles of the
#              Stanford Armadillo scan (52,000 triangles)
#   scanBSIZE  the same on the Stanford Bunny scan (bunny00.off, 75,408 triangles)
#   cadFSIZE   the same on a CAD part, the fandisk (fandisk.off: flat and curved faces)
#   cadCSIZE   the same on the cube [-1,1]^3 (cube.off): its faces come out of the sampler's
#              sums in three ulp-thin layers, the case of NOTES.md Q57
# The scan meshes come from CGAL's data, /usr/share/doc/libcgal-demo/data.tar.gz (Debian
# package libcgal-demo; or the tarball $BENCH_CGAL_DATA names), extracted into
# bench/data/meshes/; without it (or without a built gigatet for the gigatet-made families)
# the input is skipped with a message saying why.
# Default: u1M u4M g100; --big adds u10M; --quick uses u100k and g20 instead (development);
# --issue18 uses the inputs of issue 18: u1M u4M sph1M par1M clu1M mix1M scanA1M scanB1M.
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
# HXT with 2 threads is not run on the paraboloid (parSIZE: at 1M it ran past a 300 s limit in
# both runs of bench/results/2026-11-25-0727.tsv, where its 1 thread took 35-49 s of CPU)
# unless BENCH_HXT_ALL=1; the skip is printed and the report has no such row.
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
    --issue18) inputs="u1M u4M sph1M par1M clu1M mix1M scanA1M scanB1M"; shift ;;
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
mesh_tarball=${BENCH_CGAL_DATA:-/usr/share/doc/libcgal-demo/data.tar.gz}  # the CGAL data tarball
count_of() {  # "200k" -> 200000, "1M" -> 1000000, "50" -> 50; fails on anything else
  case "$1" in
    *[!0-9kM]*|"") return 1 ;;
    *k) [[ ${1%k} =~ ^[0-9]+$ ]] && echo $(( ${1%k} * 1000 )) ;;
    *M) [[ ${1%M} =~ ^[0-9]+$ ]] && echo $(( ${1%M} * 1000000 )) ;;
    *) [[ $1 =~ ^[0-9]+$ ]] && echo "$1" ;;
  esac
}
scan_mesh() {  # scanA / scanB / cadF / cadC -> the mesh file of CGAL's data
  case "$1" in
    scanA) echo armadillo.off ;; scanB) echo bunny00.off ;;
    cadF) echo fandisk.off ;; cadC) echo cube.off ;;
  esac
}
# The command writing input $1 to the file $2 (format by extension), as the array gen_cmd;
# fails with a message on stderr when the input cannot be made here.
input_cmd() {
  local in=$1 outf=$2 fam size n mesh
  fam=$(sed -E 's/^(u|g|clu|mix|sph|par|scanA|scanB|cadF|cadC)[0-9]+[kM]?$/\1/' <<< "$in")
  size=${in#"$fam"}
  if [ "$fam" = "$in" ] || ! n=$(count_of "$size"); then
    echo "bench/run.sh: unknown input $in" >&2; exit 1
  fi
  case "$fam" in
    u) gen_cmd=(python3 "$gen" uniform "$n" --seed 1 -o "$outf") ;;
    g) gen_cmd=(python3 "$gen" grid "$n" --seed 1 -o "$outf") ;;
    clu) gen_cmd=(python3 "$gen" halfcube "$n" --seed 1 -o "$outf") ;;
    mix) gen_cmd=(python3 "$gen" mixed "$n" --seed 1 -o "$outf") ;;
    sph|par|scanA|scanB|cadF|cadC)
      if [ ! -x "$build/gigatet" ]; then
        echo "bench: skipping $in: it is made by $build/gigatet generate, which is not built" >&2
        return 1
      fi
      case "$fam" in
        sph) gen_cmd=("$build/gigatet" generate sphere "$n" --seed 1 -q -o "$outf") ;;
        par) gen_cmd=("$build/gigatet" generate paraboloid "$n" --seed 1 -q -o "$outf") ;;
        *)
          mesh=$(scan_mesh "$fam")
          if [ ! -s "$data/meshes/$mesh" ]; then
            if [ ! -r "$mesh_tarball" ]; then
              echo "bench: skipping $in: its mesh $mesh (CGAL's data) comes from $mesh_tarball," \
                   "which is missing (Debian package libcgal-demo: apt-get install libcgal-demo)" >&2
              return 1
            fi
            mkdir -p "$data/meshes"
            tar xzf "$mesh_tarball" -O "data/meshes/$mesh" > "$data/meshes/$mesh.tmp" &&
              mv "$data/meshes/$mesh.tmp" "$data/meshes/$mesh" ||
              { echo "bench: skipping $in: $mesh is not in $mesh_tarball" >&2; rm -f "$data/meshes/$mesh.tmp"; return 1; }
          fi
          gen_cmd=("$build/gigatet" generate surface "$n" --mesh "$data/meshes/$mesh" --seed 1 -q -o "$outf") ;;
      esac ;;
  esac
}
kept=""
for in in $inputs; do
  ok=1
  for ext in bin node; do
    f="$data/$in.$ext"
    if [ ! -s "$f" ]; then
      input_cmd "$in" "$data/$in.tmp.$ext" || { ok=0; break; }
      echo "bench: generating $f: ${gen_cmd[*]}" >&2
      "${gen_cmd[@]}" && mv "$data/$in.tmp.$ext" "$f" ||
        { echo "bench: skipping $in: generating it failed" >&2; rm -f "$data/$in.tmp.$ext"; ok=0; break; }
    fi
  done
  [ "$ok" = 1 ] && kept="$kept $in"
done
inputs=$kept
[ -n "$inputs" ] || { echo "bench: no input to run" >&2; exit 1; }

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
skip_pair() {  # tool input -> true (with a message, once a run) when the pair is not run
  case "$1:$2:${BENCH_HXT_ALL:-0}" in
    hxt2:par*:0)
      [ "$r" != 1 ] || echo "bench: skipping $1 on $2 (HXT with 2 threads ran past 300 s on" \
        "the 1M paraboloid; BENCH_HXT_ALL=1 runs it)" >&2
      return 0 ;;
  esac
  return 1
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
      if skip_pair "$t" "$in"; then continue; fi
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
