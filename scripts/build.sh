#!/usr/bin/env bash
# Configures and builds volcomp into ${BUILD_DIR:-build}. Extra arguments go to cmake's configure
# step.
#
#   build.sh          everything: the programs, the tests, the benchmarks, the Debian packages
#   build.sh --demo   only what the demo runs: volcomp, volcompd and volcomp-sim
#
# Objects go through ccache with paths relative to the checkout, so that another clone of the
# same sources (in another folder) finds them in the cache. Debug information is line tables
# only (-g1): enough for backtraces and sanitizer reports, a fifth less compile time than -g.
# The product's libraries and programs are unity builds (VOLCOMP_UNITY_BUILD: half the compile
# time of a clean build; what the demo builds is what the tests test and the packages ship).
# Pass -DVOLCOMP_UNITY_BUILD=OFF when editing one source at a time.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$here}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi

targets=()
what=(-DVOLCOMP_BUILD_TESTS=ON -DVOLCOMP_BUILD_BENCH=ON -DVOLCOMP_BUILD_PACKAGE=ON
      -DVOLCOMP_LINUXCNC=AUTO)
if [ "${1:-}" = "--demo" ]; then
  shift
  targets=(--target volcomp volcompd volcomp-sim)
  what=(-DVOLCOMP_BUILD_TESTS=OFF -DVOLCOMP_BUILD_BENCH=OFF -DVOLCOMP_BUILD_PACKAGE=OFF
        -DVOLCOMP_LINUXCNC=OFF)
fi
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DVOLCOMP_WERROR="$werror" \
  -DVOLCOMP_UNITY_BUILD=ON "${what[@]}" \
  "$@" >/dev/null
cmake --build "$build" -j "$(nproc)" "${targets[@]}"
