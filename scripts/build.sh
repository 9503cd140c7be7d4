#!/usr/bin/env bash
# Configures and builds volcomp into ${BUILD_DIR:-build}. Extra arguments go to cmake's configure step.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVOLCOMP_WERROR="$werror" "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
