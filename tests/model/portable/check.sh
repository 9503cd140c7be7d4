#!/usr/bin/env bash
# Builds the model library and its tests (tests/model/portable/CMakeLists.txt) twice and runs the
# tests of each build:
#   clang:    Clang with the run-time dispatch (baseline + AVX2 code on x86, chosen by Highway);
#   baseline: the dispatch off (VOLCOMP_MODEL_DISPATCH=OFF): the baseline code alone, as on a CPU
#             or compiler without a second target; built with GCC, or $BASELINE_CXX.
# Usage: check.sh [WORK_DIR] (default: build/model-portable). Run by CTest (model_portable).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
work="${1:-$here/../../../build/model-portable}"
mkdir -p "$work"

build_and_test() {
  local name=$1 compiler=$2
  shift 2
  echo "== $name: $compiler $*"
  cmake -S "$here" -B "$work/$name" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER="$compiler" "$@" >"$work/$name.configure.log" ||
    { cat "$work/$name.configure.log"; return 1; }
  cmake --build "$work/$name" -j2
  ctest --test-dir "$work/$name" --output-on-failure -j2
}

build_and_test clang "${CLANG_CXX:-clang++}"
build_and_test baseline "${BASELINE_CXX:-g++}" -DVOLCOMP_MODEL_DISPATCH=OFF
