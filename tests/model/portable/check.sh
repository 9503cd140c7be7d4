#!/usr/bin/env bash
# Builds the model library and its tests (tests/model/portable/CMakeLists.txt) twice with Clang
# (or $PORTABLE_CXX) and runs the tests of each build:
#   dispatch: the run-time dispatch on (baseline and, on x86-64, AVX2 code, chosen by the CPU);
#   baseline: VOLCOMP_MODEL_DISPATCH=OFF, the baseline code alone (no target attribute, no CPU
#             detection), as on a CPU or compiler without a second target.
# Release builds (no -g), so that ccache serves the second build's test sources from the first.
# Usage: check.sh [WORK_DIR] (default: build/model-portable). Run by CTest (model_portable).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
work="${1:-$here/../../../build/model-portable}"
mkdir -p "$work"

build_and_test() {
  local name=$1 compiler=$2
  shift 2
  echo "== $name: $compiler $*"
  cmake -S "$here" -B "$work/$name" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_COMPILER="$compiler" "$@" >"$work/$name.configure.log" ||
    { cat "$work/$name.configure.log"; return 1; }
  cmake --build "$work/$name" -j2
  ctest --test-dir "$work/$name" --output-on-failure -j2
}

compiler="${PORTABLE_CXX:-clang++}"
build_and_test dispatch "$compiler"
build_and_test baseline "$compiler" -DVOLCOMP_MODEL_DISPATCH=OFF
