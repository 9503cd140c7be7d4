#!/bin/sh
# The installed unit points at installed documentation and does not restart a bad configuration:
# install the build into a temporary DESTDIR, then check every Documentation= file:// target
# exists there, RestartPreventExitStatus=2, and TimeoutStopSec equals the daemon's default
# stop_timeout_s (the number the limiter's ramp-out is checked against).
# Usage: installed_unit_test.sh BUILD_DIR EXPECTED_TIMEOUT_STOP_SEC
set -eu
build=$1
timeout=$2
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
DESTDIR="$dest" cmake --install "$build" >/dev/null
unit=$(find "$dest" -name volcompd.service -path '*systemd*' | head -n 1)
test -n "$unit" || { echo "no volcompd.service installed under $dest"; exit 1; }
docs=$(sed -n 's/^Documentation=//p' "$unit")
test -n "$docs" || { echo "no Documentation= in $unit"; exit 1; }
for url in $docs; do
  case $url in
    file://*) file=${url#file://}
              test -f "$dest$file" || { echo "Documentation= $url is not installed ($dest$file)"; exit 1; } ;;
    *) echo "Documentation= $url is not a file:// URL"; exit 1 ;;
  esac
done
grep -qx 'RestartPreventExitStatus=2' "$unit" || { echo "no RestartPreventExitStatus=2 in $unit"; exit 1; }
grep -qx "TimeoutStopSec=${timeout}s" "$unit" || { echo "TimeoutStopSec is not ${timeout}s in $unit"; exit 1; }
schema=$(find "$dest" -name volcomp-model-1.schema.json | head -n 1)
test -n "$schema" || { echo "the model schema is not installed"; exit 1; }
echo "ok: $docs"
