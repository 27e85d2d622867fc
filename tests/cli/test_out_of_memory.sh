#!/usr/bin/env bash
# test_out_of_memory.sh -- under an address-space limit (ulimit -v) running out of memory is
# exit code 4 with a message, and leaves no output.  Two cases: the reader cannot allocate
# the points (does not need the kernel), and the kernel cannot allocate its mesh (needs the
# kernel: 1M points need well over 150 MB of tets, the input only 24 MB).
# Skipped loudly under sanitizers: ASan/TSan reserve terabytes of address space.
. "$(dirname "$0")/common.sh"
cd "$W"
case "${GTET_SANITIZE:-OFF}${GTET_TSAN:-OFF}" in
    *ON*|*1*|*TRUE*|*true*) skip_loudly "sanitizer build: ulimit -v cannot limit an ASan/TSan process" ;;
esac
"$G" generate uniform 1000000 --seed 2 -o big.bin -q || fail "generate 1M"
(ulimit -v 200000 && "$G" --version >/dev/null) || skip_loudly "the binary does not even start under ulimit -v 200000"

# the reader: 24 MB of points under a 16 MB limit (the binary itself starts in less)
lim=16000
(ulimit -v "$lim" && "$G" --version >/dev/null) || lim=20000
expect 4 "big.bin: out of memory for 1000000 points" -- bash -c "ulimit -v $lim && exec \"$G\" triangulate big.bin -o out.ele"
[ ! -e out.ele ] && [ ! -e out.node ] || fail "an out-of-memory run left output"

# the kernel: enough for the input, not for 6.5M tets (the memory guard off, so that the
# allocation itself fails: tests/cli/test_memory_guard.sh tests the guard)
expect 4 "out of memory" -- bash -c "ulimit -v 150000 && exec \"$G\" triangulate big.bin -t 1 -o out.ele --memory-limit off"
! grep -qF "needs about" "$T/err" || fail "the guard ran with --memory-limit off"
[ -z "$(ls -A | grep -v '^big.bin$')" ] || fail "an out-of-memory run left: $(listing .)"
# a file read whole that is larger than the memory left (NOTES.md E161): refused before the
# allocation with the limit named, for a regular text file and for an endless device (without
# the check the device was read until the allocation failed, or with overcommit until the OOM
# killer's SIGKILL)
head -c 120000000 /dev/zero | tr '\0' '1' > wide.xyz
expect 4 "wide.xyz: out of memory: the file (0.11 GiB) is read whole, and" -- bash -c "ulimit -v 100000 && exec \"$G\" triangulate wide.xyz -o out.ele"
grep -qF "(RLIMIT_AS, ulimit -v)" "$T/err" || fail "the limit is not named: $(cat "$T/err")"
ln -s /dev/zero endless.xyz
expect 4 "endless.xyz: out of memory: the input (not a regular file" -- bash -c "ulimit -v 300000 && exec \"$G\" triangulate endless.xyz -o out.ele"
grep -qF "(RLIMIT_AS, ulimit -v)" "$T/err" || fail "the limit is not named: $(cat "$T/err")"
rm -f wide.xyz endless.xyz
[ -z "$(ls -A | grep -v '^big.bin$')" ] || fail "an out-of-memory run left: $(listing .)"
finish
