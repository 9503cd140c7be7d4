#!/usr/bin/env bash
# The daemon's CAN cycle on vcan against the simulator's node, and the codec alone, measured by
# bench_can_cycle inside the QEMU guest of tests/can/run_vcan_tests.sh (this machine's kernel has
# no CAN); the codec alone also on the host, which gives the guest's emulation slowdown.
#
#   bench/can/run_cycle_bench.sh BUILD_DIR [REPETITIONS]
#
# The guest runs under TCG software emulation: its absolute times are pessimistic; divide them by
# the codec's guest/host ratio for an estimate of native speed.
set -euo pipefail
build="$(readlink -f "${1:?usage: $0 BUILD_DIR [REPETITIONS]}")"
reps="${2:-3}"
here="$(cd "$(dirname "$0")" && pwd)"
src="$(cd "$here/../.." && pwd)"
exe="$build/bench/can/bench_can_cycle"
[ -x "$exe" ] || { echo "run_cycle_bench: build bench_can_cycle first" >&2; exit 1; }

echo "== host: codec alone (pinned to CPU 1)"
taskset -c 1 "$exe" --benchmark_filter=canCodecCycle --benchmark_repetitions="$reps" \
  --benchmark_report_aggregates_only=true --benchmark_color=false

echo "== QEMU guest (TCG): cycle on vcan0 and codec alone"
"$src/tests/can/run_vcan_tests.sh" --mode qemu --cache "$build/vm-cache" \
  --data "$src/config/examples" "$exe" --benchmark_repetitions="$reps" --benchmark_color=false
