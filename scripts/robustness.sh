#!/usr/bin/env bash
# The robustness pass of the test command (docs/robustness.md): a second build with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer into ${SANITIZE_BUILD_DIR:-build-sanitize}, in
# which the unit, modbus and calibration labels run again, and every fuzz target (fuzz/) fuzzes
# for ${VOLCOMP_FUZZ_SECONDS:-30} s from its committed corpus. Any sanitizer report, fuzz finding
# or failed test fails the pass. Extra arguments go to ctest.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${SANITIZE_BUILD_DIR:-$here/build-sanitize}"
seconds="${VOLCOMP_FUZZ_SECONDS:-30}"
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
start=$(date +%s)

CC=clang CXX=clang++ cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DVOLCOMP_WERROR="$werror" -DVOLCOMP_SANITIZE=ON -DVOLCOMP_FUZZ=ON -DVOLCOMP_BUILD_BENCH=OFF \
  -DVOLCOMP_FUZZ_SECONDS="$seconds" >/dev/null
cmake --build "$build" -j "$(nproc)"
built=$(date +%s)

# A report aborts the process that made it (the test fails), with a stack; leaks are reports too.
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
rm -f "$build/fuzz/summary.txt"
cd "$build"
status=0
ctest --output-on-failure --timeout 900 -L 'unit|modbus|calibration|fuzz' "$@" || status=$?
end=$(date +%s)
if [ -f fuzz/summary.txt ]; then cat fuzz/summary.txt; fi
echo "robustness pass: build $((built - start)) s, tests and fuzzing $((end - built)) s"
exit "$status"
