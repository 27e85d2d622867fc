#!/usr/bin/env bash
# tests/extra-jobs.sh -- the CI jobs beyond the main build's ctest (`./dev test` runs this
# after it).  Run from the repository root; each job prints what it does and one line
#   extra-jobs: <job>: PASS | FAIL (...)
# and the script exits non-zero when any job failed (all jobs run regardless).
#
#   asan   gcc, -DGTET_SANITIZE=ON (ASan + UBSan, no recovery) -DGTET_WERROR=ON, build-asan:
#          the whole ctest suite except the CGAL differential tests (GTET_CGAL_TESTS=OFF: CGAL
#          under ASan compiles for minutes; they run in the plain build) -- fuzz corpus replays
#          included; the out-of-memory CLI test skips itself (ulimit -v means nothing under ASan).
#   tsan   clang-14, -DGTET_TSAN=ON (-fsanitize=thread), LLVM's libomp (-fopenmp=libomp, not
#          libgomp) with the Archer OMPT tool so TSan understands OpenMP's barriers, build-tsan:
#          test_parallel_determinism (sanitized sizes: 10k-40k random, grid and co-spherical
#          points at 1-4 threads, every round split across threads) and test_parallel_balance
#          (first passes forced to rebalance, on Moore slices and on slabs: NOTES.md E186, E258;
#          ~1 min) must run with zero reports, and tests/parallel_race_canary.c, a deliberately racy loop, must be
#          flagged (ctest tsan_flags_a_deliberate_data_race): the job can fail.
#   clang  clang-14 / clang++-14, -DGTET_WERROR=ON -DGTET_BENCH=ON, build-clang: configures and
#          builds every target once (library, CLI, tests, the CGAL differential programs, the
#          fuzz corpus replays, bench/sort_bench and the bench peers), runs nothing: gcc's
#          build runs the tests, this job keeps the tree compiling under the second compiler.
#   fuzz   clang-14, -DGTET_FUZZ=ON, build-fuzz: each fuzz/fuzz_* target replays its corpus
#          (fuzz/corpus/<target>/, -runs=0) and then fuzzes for FUZZ_SECONDS (default 30) on a
#          scratch copy of the corpus; a finding is saved as build-fuzz/findings/crash-* .
# Select jobs with EXTRA_JOBS="asan tsan clang fuzz" (default: all four).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=$(nproc 2>/dev/null || echo 2)
selected=${EXTRA_JOBS:-"asan tsan clang fuzz"}
fuzz_seconds=${FUZZ_SECONDS:-30}
failed=()

say() { printf 'extra-jobs: %s\n' "$*"; }
result() {  # result JOB STATUS [why]
    if [ "$2" -eq 0 ]; then say "$1: PASS"; else say "$1: FAIL${3:+ ($3)}"; failed+=("$1"); fi
}
run() { say "+ $*" >&2; "$@"; }

job_asan() {
    # GTET_CGAL_TESTS=OFF: CGAL's headers under ASan take minutes to compile
    # and test CGAL's C++, not gigatet (the plain build runs them); bench/ is not needed here.
    run cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DGTET_SANITIZE=ON \
        -DGTET_CGAL_TESTS=OFF -DGTET_BENCH=OFF -DGTET_WERROR=ON >/dev/null || return 1
    # every target: the tests need the CLI, the shared library (install_consumers) and the
    # MPI programs (mpi_*) besides the test tree
    run cmake --build build-asan -j "$jobs" >/dev/null || return 1
    # proofs_check (Gappa) and its self-test do not run our code: the plain build runs them
    (cd build-asan && run ctest --output-on-failure -j "$jobs" -E '^proofs_check')
}

job_tsan() {
    local archer=/usr/lib/llvm-14/lib/libarcher.so
    if [ ! -f "$archer" ]; then say "tsan: $archer missing (apt-get install libomp-14-dev)"; return 1; fi
    run cmake -S . -B build-tsan -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
        -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGTET_TSAN=ON -DGTET_CGAL_TESTS=OFF \
        -DGTET_WERROR=ON >/dev/null || return 1
    if ! grep -q 'OpenMP_C_FLAGS:STRING=-fopenmp=libomp' build-tsan/CMakeCache.txt; then
        say "tsan: OpenMP is not LLVM's libomp: $(grep OpenMP_C_FLAGS: build-tsan/CMakeCache.txt)"
        return 1
    fi
    run cmake --build build-tsan -j "$jobs" --target test_parallel_determinism \
        test_parallel_balance test_check_threads parallel_race_canary >/dev/null || return 1
    # halt_on_error: the first report fails the run; Archer is loaded through OMPT.
    (cd build-tsan &&
        OMP_TOOL_LIBRARIES=$archer \
        TSAN_OPTIONS="ignore_noninstrumented_modules=1 halt_on_error=1" \
        run ctest --output-on-failure -R '^(test_parallel_determinism|test_parallel_balance|test_check_threads|tsan_flags_a_deliberate_data_race)$') \
        || return 1
    # belt and braces: the canary must have been registered and run (not silently skipped)
    grep -q 'tsan_flags_a_deliberate_data_race' build-tsan/Testing/Temporary/LastTest.log || {
        say "tsan: the race canary did not run"; return 1; }
}

job_clang() {
    run cmake -S . -B build-clang -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
        -DCMAKE_BUILD_TYPE=Release -DGTET_WERROR=ON -DGTET_BENCH=ON >/dev/null || return 1
    run cmake --build build-clang -j "$jobs" >build-clang/build.log 2>&1 ||
        { tail -n 40 build-clang/build.log; return 1; }
}

job_fuzz() {
    run cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
        -DCMAKE_BUILD_TYPE=Release -DGTET_FUZZ=ON -DBUILD_TESTING=OFF -DGTET_CGAL_TESTS=OFF \
        -DGTET_WERROR=ON >/dev/null || return 1
    local targets=(fuzz_predicates fuzz_triangulate fuzz_readers fuzz_mesh_check) t rc=0
    run cmake --build build-fuzz -j "$jobs" --target "${targets[@]}" >/dev/null || return 1
    mkdir -p build-fuzz/findings
    for t in "${targets[@]}"; do
        local bin=build-fuzz/fuzz/$t work=build-fuzz/corpus-work/$t
        run "$bin" -runs=0 -rss_limit_mb=2048 fuzz/corpus/$t/ 2>&1 | tail -n 2 || { say "fuzz: $t corpus replay failed"; rc=1; continue; }
        rm -rf "$work" && mkdir -p "$work" && cp fuzz/corpus/$t/* "$work"/
        if run "$bin" -max_total_time="$fuzz_seconds" -rss_limit_mb=2048 -timeout=60 \
               -print_final_stats=1 -artifact_prefix=build-fuzz/findings/$t- "$work" \
               >build-fuzz/$t.log 2>&1; then
            say "fuzz: $t: $(grep -E 'DONE|stat::number_of_executed_units' build-fuzz/$t.log | tr '\n' ' ')"
        else
            say "fuzz: $t FAILED; the end of build-fuzz/$t.log:"
            tail -n 40 build-fuzz/$t.log
            rc=1
        fi
    done
    return $rc
}

for j in $selected; do
    case $j in
        asan|tsan|clang|fuzz)
            say "=== $j ==="
            start=$SECONDS
            set +e; ( set -e; "job_$j" ); rc=$?; set -e
            say "$j took $((SECONDS - start)) s"
            result "$j" "$rc" ;;
        *) say "unknown job $j"; failed+=("$j") ;;
    esac
done

if ((${#failed[@]})); then
    say "FAILED: ${failed[*]}"
    exit 1
fi
say "all extra jobs passed: $selected"
