#!/usr/bin/env bash
# The README's test command: installs what is needed, builds, and runs every test.
#
# Two passes, each test kind (tests/labels.cmake) where it finds the most:
#   1. GCC, the build that ships: the unit tests (in process) and the system tests (LinuxCNC,
#      its rs274, SocketCAN in a QEMU guest, headless Chromium, the Debian packages, systemd).
#   2. Clang with AddressSanitizer and UndefinedBehaviorSanitizer (scripts/robustness.sh): the
#      unit tests again, the process tests (volcompd, volcomp-sim and volcomp as processes: a
#      memory error in a program shows there, and nowhere else), the model built without its
#      run-time dispatch, and every parser fuzzed for a bounded time.
# Tests run side by side (ctest -j); those that need the machine to themselves say so
# (RUN_SERIAL, RESOURCE_LOCK). Each phase's time is printed at the end.
# Extra arguments go to both ctest runs (e.g. -R NAME).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
jobs="${VOLCOMP_TEST_JOBS:-$(nproc)}"
phases=()
phase() {
  local name="$1" start status=0
  shift
  start=$(date +%s)
  echo "== $name"
  "$@" || status=$?
  phases+=("$(printf '%-34s %5d s' "$name" $(($(date +%s) - start)))")
  return "$status"
}
report() {
  echo "== phases"
  printf '%s\n' "${phases[@]}"
}
trap report EXIT

phase "setup (apt)" "$here/scripts/setup-debian.sh"
phase "build (GCC)" "$here/scripts/build.sh"
phase "tests (GCC): unit, system" ctest --test-dir "$build" --output-on-failure --timeout 900 \
  -j "$jobs" -L '^(unit|system)$' "$@"
phase "build (clang, sanitizers)" "$here/scripts/robustness.sh" --build-only
phase "tests (clang): unit, process, fuzzing" "$here/scripts/robustness.sh" --test-only "$@"
