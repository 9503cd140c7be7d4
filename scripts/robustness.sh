#!/usr/bin/env bash
# The clang pass of the test command (scripts/test.sh, docs/robustness.md): a build with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer into ${SANITIZE_BUILD_DIR:-build-sanitize} of
# what this pass runs (no benchmarks, packages, system tests or LinuxCNC program; the model once
# more with its run-time dispatch off), then the unit and process tests and every fuzz target
# fuzzing for ${VOLCOMP_FUZZ_SECONDS:-30} s from its committed corpus, side by side. Any sanitizer report,
# fuzz finding or failed test fails the pass. Extra arguments go to ctest.
#
#   robustness.sh [CTEST_ARGS...]          build, then test
#   robustness.sh --build-only | --test-only [CTEST_ARGS...]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${SANITIZE_BUILD_DIR:-$here/build-sanitize}"
seconds="${VOLCOMP_FUZZ_SECONDS:-30}"
# One test per core: a fuzz target then has a core of its own for its seconds, as it had when
# they ran one after the other.
jobs="${VOLCOMP_TEST_JOBS:-$(nproc)}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$here}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
steps=(build test)
case "${1:-}" in
  --build-only) steps=(build); shift ;;
  --test-only) steps=(test); shift ;;
esac

for step in "${steps[@]}"; do
  if [ "$step" = build ]; then
    CC=clang CXX=clang++ cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DVOLCOMP_WERROR="$werror" \
      -DVOLCOMP_SANITIZE=ON -DVOLCOMP_FUZZ=ON -DVOLCOMP_BUILD_BENCH=OFF -DVOLCOMP_BUILD_PACKAGE=OFF \
      -DVOLCOMP_SYSTEM_TESTS=OFF -DVOLCOMP_MODEL_BASELINE_VARIANT=ON -DVOLCOMP_LINUXCNC=OFF \
      -DVOLCOMP_FUZZ_SECONDS="$seconds" >/dev/null
    cmake --build "$build" -j "$(nproc)"
  else
    # A report aborts the process that made it (the test fails), with a stack; leaks are reports
    # too.
    export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    rm -f "$build/fuzz/summary.txt"
    status=0
    ctest --test-dir "$build" --output-on-failure --timeout 900 -j "$jobs" \
      -L '^(unit|process|fuzzing)$' "$@" || status=$?
    if [ -f "$build/fuzz/summary.txt" ]; then cat "$build/fuzz/summary.txt"; fi
    [ "$status" -eq 0 ] || exit "$status"
  fi
done
