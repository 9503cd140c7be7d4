#!/usr/bin/env bash
# The README's test command: installs what is needed, builds, and runs every test (all labels).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/setup-debian.sh"
"$here/scripts/build.sh"
cd "${BUILD_DIR:-$here/build}"
ctest --output-on-failure --timeout 900 "$@"
