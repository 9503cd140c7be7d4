#!/usr/bin/env bash
# The README's test command: installs what is needed, builds, and runs every test (all labels);
# then the robustness pass (scripts/robustness.sh): a clang build with AddressSanitizer and
# UndefinedBehaviorSanitizer that runs the unit, modbus and calibration labels again and fuzzes
# every parser for a bounded time. Extra arguments go to the first ctest run.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/setup-debian.sh"
"$here/scripts/build.sh"
(cd "${BUILD_DIR:-$here/build}" && ctest --output-on-failure --timeout 900 "$@")
"$here/scripts/robustness.sh"
