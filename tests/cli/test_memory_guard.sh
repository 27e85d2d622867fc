#!/usr/bin/env bash
# test_memory_guard.sh -- out of memory is never a kill: gigatet triangulate estimates its
# peak before any big allocation and, when a limit cannot give it, exits 4 at once with "needs
# about X, Y available (LIMIT)" and writes nothing (src/api/memory.c).
#   - the estimate against the measured peak RSS at 200k points, one and two threads
#     (--stats: estimated_peak_bytes vs max_rss_bytes): never more than 3% below, at most
#     60% above (fixed overheads weigh at this size; bench/memory_estimate.py for large n);
#   - --memory-limit: 1M refuses even a small input, --check counts, off and a large value override the guard
#     (under ulimit -v the run then reaches the allocation failure: exit 4 without the guard's
#     message, no crash), bad values are usage errors (exit 1);
#   - ulimit -v the input cannot fit: the guard names RLIMIT_AS, no output file;
#   - a mesh that outgrows the estimate (co-spherical points) under ulimit -v: the second check
#     refuses its growth with its own message;
#   - a cgroup v2 memory.max the input cannot fit, when this machine lets root create one
#     (else skipped with a message; the cgroup files are parsed by tests/test_api_memory.c).
# The ulimit and RSS parts are skipped under sanitizers (ASan/TSan map terabytes, and their
# shadow memory is not the library's).
. "$(dirname "$0")/common.sh"
cd "$W"
sanitized=0
case "${GTET_SANITIZE:-OFF}${GTET_TSAN:-OFF}" in *ON*|*1*|*TRUE*|*true*) sanitized=1 ;; esac
"$G" generate uniform 200000 --seed 3 -o mid.bin -q || fail "generate 200k"
"$G" generate uniform 1000 --seed 3 -o small.bin -q || fail "generate 1k"

# --memory-limit values
expect 4 "needs about" -- "$G" triangulate small.bin --memory-limit 1M -o out.ele
grep -qF "1.0 MiB available (the memory_limit option)" "$T/err" || fail "names the option: $(cat "$T/err")"
[ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a refused run left: $(listing .)"
expect 0 "" -- "$G" triangulate small.bin --memory-limit off -q
expect 0 "" -- "$G" triangulate small.bin --memory-limit=64G -q
expect 0 "" -- "$G" triangulate small.bin --memory-limit auto -q
expect 0 "" -- "$G" triangulate small.bin --memory-limit 512MiB -q
expect 0 "" -- "$G" triangulate small.bin --memory-limit 1073741824 -q
for bad in 0 12X 1.5G -5 G 16GG "" 99999999999999999999 17179869184T; do
    expect 1 "invalid memory limit '$bad'" -- "$G" triangulate small.bin --memory-limit "$bad"
done
expect 1 "needs a size" -- "$G" triangulate small.bin --memory-limit
# --check runs after the kernel and needs more (about 2.3x): the CLI asks the guard with it
expect 0 "" -- "$G" triangulate mid.bin --memory-limit 100M -t 1 -q
expect 4 "100.0 MiB available (the memory_limit option)" -- "$G" triangulate mid.bin --memory-limit 100M -t 1 --check -o out.vtu
[ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a refused run left: $(listing .)"

if [ "$sanitized" = 1 ]; then
    echo "SKIPPED (LOUDLY): sanitizer build: the RSS and ulimit -v parts" >&2
    finish
fi

# the estimate against the measured peak
for t in 1 2; do
    "$G" triangulate mid.bin -t $t --stats >"$T/out" 2>"$T/err" || fail "200k -t $t: $(cat "$T/err")"
    tail -1 "$T/out" | tr ',' '\n' | awk -F: -v t=$t '
        /"max_rss_bytes"/ { rss = $2 } /"estimated_peak_bytes"/ { est = $2 }
        END { r = est / rss; printf "200k -t %d: rss %d est %d ratio %.3f\n", t, rss, est, r;
              exit !(rss > 0 && r >= 0.97 && r <= 1.6) }' || fail "estimate off at 200k -t $t"
done

# ulimit -v: 1M points (24 MB) fit, their mesh (about 330 MB) does not
"$G" generate uniform 1000000 --seed 2 -o big.bin -q || fail "generate 1M"
(ulimit -v 150000 && "$G" --version >/dev/null) || skip_loudly "the binary does not start under ulimit -v 150000"
expect 4 "needs about" -- bash -c "ulimit -v 150000 && exec \"$G\" triangulate big.bin -t 1 -o out.ele"
grep -qF "of address space" "$T/err" && grep -qF "(RLIMIT_AS, ulimit -v)" "$T/err" || fail "names RLIMIT_AS: $(cat "$T/err")"
[ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a refused run left: $(listing .)"
# overridden, the run goes on and meets the allocation failure: still exit 4, no crash
# (--memory-limit off likewise: cli_out_of_memory)
for lim in 64G; do
    expect 4 "out of memory" -- bash -c "ulimit -v 150000 && exec \"$G\" triangulate big.bin -t 1 -o out.ele --memory-limit $lim"
    ! grep -qF "needs about" "$T/err" || fail "--memory-limit $lim: the guard still ran"
done
[ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a failed run left: $(listing .)"
# a generous limit: the guard lets it run
expect 0 "" -- bash -c "ulimit -v 4000000 && exec \"$G\" triangulate mid.bin -t 1 -o out.ele -q"
[ -e out.ele ] || fail "no output under a generous limit"
rm -f out.ele out.node

# the second check: points on one sphere make ~19 tets a point against the 7 estimated; under a
# limit the estimate fits but the grown mesh does not, the growth is refused with its own
# message (not the allocator's failure), nothing written; with the guard off the allocation
# fails instead (still exit 4); a limit with room enough lets the mesh grow and finish
"$G" generate cospherical 300000 -o cosph.bin -q || fail "generate cospherical"
expect 4 "the mesh outgrew the estimate" -- bash -c "ulimit -v 200000 && exec \"$G\" triangulate cosph.bin -t 1 -o out.ele"
grep -qF "(RLIMIT_AS, ulimit -v)" "$T/err" || fail "names RLIMIT_AS: $(cat "$T/err")"
[ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a refused run left: $(listing .)"
expect 4 "out of memory" -- bash -c "ulimit -v 200000 && exec \"$G\" triangulate cosph.bin -t 1 -o out.ele --memory-limit off"
! grep -qF "outgrew" "$T/err" || fail "--memory-limit off: the second check still ran"
expect 0 "" -- bash -c "ulimit -v 400000 && exec \"$G\" triangulate cosph.bin -t 1 -q"

# cgroup v2: a child cgroup with memory.max = 64 MiB, this subshell moved into it
cg_skip=""
if [ "$(id -u)" != 0 ]; then cg_skip="not root"
elif ! grep -qw memory /sys/fs/cgroup/cgroup.controllers 2>/dev/null; then
    cg_skip="no cgroup v2 memory controller at /sys/fs/cgroup (this machine: $(stat -fc %T /sys/fs/cgroup 2>/dev/null))"
elif ! grep -qw memory /sys/fs/cgroup/cgroup.subtree_control 2>/dev/null; then
    cg_skip="the memory controller is not enabled for child cgroups of /sys/fs/cgroup"
else
    CG=/sys/fs/cgroup/gtet-test-$$
    if mkdir "$CG" 2>/dev/null && echo $((64 << 20)) >"$CG/memory.max" 2>/dev/null; then
        expect 4 "(cgroup memory limit)" -- bash -c "echo \$\$ > $CG/cgroup.procs && exec \"$G\" triangulate big.bin -t 1 -o out.ele"
        [ -z "$(ls -A | grep -v '\.bin$')" ] || fail "a refused run left: $(listing .)"
    else
        cg_skip="cannot create a cgroup with memory.max under /sys/fs/cgroup"
    fi
    rmdir "$CG" 2>/dev/null
fi
[ -n "$cg_skip" ] && echo "SKIPPED the cgroup part: $cg_skip"
finish
