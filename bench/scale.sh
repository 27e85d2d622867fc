#!/usr/bin/env bash
# bench/scale.sh -- gigatet's cost per point as the input grows (issue 19), split into what the
# code spends (CPU) and what the machine makes it wait for (fresh memory).
#
#   bench/scale.sh [--sizes "1M 50M"] [--threads T] [--runs N] [--build DIR] [--probe-mib M]
#
# Uniform points (`gigatet generate uniform N --seed 1`, made once into bench/data/uSIZE.bin).
# Each repetition runs every size, the smallest first and again after the others (so each big
# run has small runs next to it), and before each run bench/touch_probe (built here with cc)
# measures how long the machine takes to hand out M MiB of fresh memory (default 1024).  Per
# run it prints: the --stats kernel and insert seconds, the process's user and system CPU
# seconds, peak RSS and minor page faults (/usr/bin/time), the probe's seconds per GiB and the load average.  At
# the end, per size, the medians in microseconds a point and the ratio of each size's median to
# the smallest size's (the issue's figure is the kernel's, at the same thread count).
# On a virtual machine whose host takes freed memory back (free page reporting), each new page
# can cost a host fault: the probe's first-touch figure then moves by 40x from minute to minute
# (NOTES.md, issue 19), and a run's wall time with it, while its user CPU does not.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)
sizes="1M 50M"; threads=2; runs=3; build="$root/build"; probe_mib=1024
while (($#)); do
  case "$1" in
    --sizes) sizes=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --probe-mib) probe_mib=$2; shift 2 ;;
    -h|--help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "bench/scale.sh: unknown argument $1" >&2; exit 1 ;;
  esac
done
g="$build/gigatet"
[ -x "$g" ] || { echo "bench/scale.sh: $g is not built (cmake --build $build --target gigatet_cli)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench/scale.sh: /usr/bin/time is missing: apt-get install time" >&2; exit 1; }
probe="$build/touch_probe"
if [ ! -x "$probe" ] || [ "$here/touch_probe.c" -nt "$probe" ]; then
  cc -O2 -std=c17 -Wall -Wextra -o "$probe" "$here/touch_probe.c"
fi
count_of() {
  case "$1" in
    *k) echo $(( ${1%k} * 1000 )) ;; *M) echo $(( ${1%M} * 1000000 )) ;;
    *[!0-9]*|"") echo "bench/scale.sh: bad size $1 (use 200k, 1M, 50M, ...)" >&2; return 1 ;;
    *) echo "$1" ;;
  esac
}
mkdir -p "$here/data"
for s in $sizes; do
  f="$here/data/u$s.bin"
  if [ ! -s "$f" ]; then
    n=$(count_of "$s")
    "$g" generate uniform "$n" --seed 1 -q -o "${f%.bin}.tmp.bin" && mv "${f%.bin}.tmp.bin" "$f"
  fi
done
small=${sizes%% *}
raw=$(mktemp)
trap 'rm -f "$raw"' EXIT
one() {  # size
  local f="$here/data/u$1.bin" pr load tf out
  pr=$("$probe" "$probe_mib" | awk '{print $2}')
  load=$(cut -d' ' -f1 /proc/loadavg)
  tf=$(mktemp)
  if ! out=$(/usr/bin/time -f "%U %S %M %R" -o "$tf" "$g" triangulate "$f" -t "$threads" --stats); then
    echo "bench/scale.sh: gigatet failed on $f" >&2; rm -f "$tf"; exit 1
  fi
  out=$(tail -1 <<< "$out")
  /usr/bin/python3 - "$1" "$pr" "$load" "$(cat "$tf")" "$out" <<'EOF' | tee -a "$raw"
import json, sys
size, probe, load, tm, out = sys.argv[1:6]
d = json.loads(out); s = d["seconds"]; u, sy, rss, mf = tm.split()
print(f"{size}\t{d['points']}\t{s['kernel']:.3f}\t{s['insert']:.3f}\t{u}\t{sy}\t{int(rss)//1024}\t{probe}\t{load}\t{mf}")
EOF
  rm -f "$tf"
}
echo -e "size\tpoints\tkernel_s\tinsert_s\tuser_s\tsys_s\tpeak_MiB\tprobe_s_per_GiB\tload\tminor_faults"
for r in $(seq "$runs"); do
  for s in $sizes; do one "$s"; done
  [ "$small" = "${sizes##* }" ] || one "$small"
done
/usr/bin/python3 - "$raw" "$small" <<'EOF'
import statistics as st, sys
rows = [l.split("\t") for l in open(sys.argv[1]) if l.strip()]
by = {}
for r in rows:
    by.setdefault(r[0], []).append(r)
def med(rs, i): return st.median(float(r[i]) / float(r[1]) * 1e6 for r in rs)
base = by[sys.argv[2]]
print("\nmedians, microseconds a point (ratio to %s)" % sys.argv[2])
print("size\truns\tkernel\tinsert\tuser+sys CPU\tsys CPU")
for size, rs in by.items():
    cpu = st.median((float(r[4]) + float(r[5])) / float(r[1]) * 1e6 for r in rs)
    cpu0 = st.median((float(r[4]) + float(r[5])) / float(r[1]) * 1e6 for r in base)
    print(f"{size}\t{len(rs)}\t{med(rs,2):.3f} ({med(rs,2)/med(base,2):.2f})\t"
          f"{med(rs,3):.3f} ({med(rs,3)/med(base,3):.2f})\t{cpu:.3f} ({cpu/cpu0:.2f})\t{med(rs,5):.3f}")
EOF
