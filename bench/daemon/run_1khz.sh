#!/usr/bin/env bash
# volcompd at 1 kHz against the empty-loop baseline in ONE run, under the same conditions: BLOCKS
# alternating blocks of BLOCK_S seconds, first cyclictest (rt-tests: an empty cycle woken every
# 1 ms on absolute deadlines), then volcompd at 1 kHz against volcomp-sim over Modbus TCP
# loopback, both on the same CPU with the same scheduling policy, while the simulator runs
# throughout on its own CPU. Both are counted with one metric, missed deadlines: deadlines at
# which no cycle started within one period (a wake-up a period or more late, or a deadline
# skipped: a whole period past when the thread woke up or the cycle before it ended). Then every
# write the simulated controller received during the whole run is checked against the limiter
# (max_offset, max_rate over the controller's time between writes, no step larger than one
# limiter step); the harness exits 1 if one is not.
#
# Usage: bench/daemon/run_1khz.sh              (after ./scripts/build.sh)
# Environment: BUILD_DIR (default ./build; or VOLCOMPD and VOLCOMP_SIM, the executables),
#   CPU (the CPU of both loops, default the last), SERVER_CPU (the simulator's, default 0),
#   BLOCKS (default 6), BLOCK_S (whole seconds, default 10), POLICY (fifo or other; default fifo
#   where permitted, else other), KEEP_DIR (keep the raw files there: cyclictest JSON, volcompd
#   logs, the simulator's report and record).
# Exit status: 0 figures produced and every write within the limits, 1 a write broke them,
#   2 the set-up failed. A daemon above the baseline is reported, not an error: the platform's
#   share varies from block to block, which is what the interleaving shows.
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${BUILD_DIR:-$root/build}"
examples="$root/config/examples"
sim="${VOLCOMP_SIM:-$build/tools/sim/volcomp-sim}"
daemon="${VOLCOMPD:-$build/daemon/volcompd/volcompd}"
cpu="${CPU:-$(($(nproc) - 1))}"
server_cpu="${SERVER_CPU:-0}"
blocks="${BLOCKS:-6}"
block_s="${BLOCK_S:-10}"
period_us=1000
# The limits of the check: the example daemon's limiter, the register map's resolution, and the
# simulator's allowance for the jitter between the daemon's and the controller's clocks.
max_offset_mm=0.1
max_rate_mm_s=0.5
quantum_mm=0.0001
rate_tolerance_ms=1
watchdog_ms=500

fail() {
  echo "run_1khz: $*" >&2
  exit 2
}
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
  exit 0
fi
for v in cpu server_cpu blocks block_s; do
  [[ "${!v}" =~ ^[0-9]+$ ]] || fail "${v^^} must be a whole number, not '${!v}'"
done
if [ "$blocks" -lt 1 ] || [ "$block_s" -lt 1 ]; then fail "BLOCKS and BLOCK_S must be at least 1"; fi
for exe in "$sim" "$daemon"; do
  [ -x "$exe" ] || fail "$exe not built (run ./scripts/build.sh)"
done
command -v cyclictest > /dev/null || fail "cyclictest not found (Debian package rt-tests; scripts/setup-debian.sh)"

policy="${POLICY:-}"
if [ -z "$policy" ]; then
  if chrt -f 50 true 2> /dev/null; then policy=fifo; else policy=other; fi
fi
case "$policy" in
  fifo) run_as=(chrt -f 50) ct_policy=(--policy=fifo -p 50) ;;
  other) run_as=() ct_policy=(--policy=other) ;;
  *) fail "POLICY must be fifo or other, not '$policy'" ;;
esac

work="$(mktemp -d)"
sim_pid=""
daemon_pid=""
cleanup() {
  for p in $daemon_pid $sim_pid; do kill "$p" 2> /dev/null || true; done
  wait 2> /dev/null || true
  if [ -n "${KEEP_DIR:-}" ]; then mkdir -p "$KEEP_DIR" && cp -r "$work"/. "$KEEP_DIR"/; fi
  rm -rf "$work"
}
trap cleanup EXIT

# Writes a JSON file from an example with edits: edit_json SRC DST PYTHON-STATEMENTS (on `d`).
edit_json() {
  python3 "$root/bench/daemon/edit_json.py" "$@"
}

echo "machine: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p'), $(nproc) CPUs, kernel $(uname -r)"
echo "both loops on CPU $cpu under SCHED_${policy^^}${run_as:+ 50}, the simulator on CPU $server_cpu;" \
  "$blocks blocks of $block_s s each, alternating"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"

# ---- the simulated controller, for the whole run -------------------------------------------
edit_json "$examples/sim-vmc.json" "$work/sim.json" "
d['model'] = '$examples/vmc-xyfz-21-true.json'
d['heartbeat_timeout_ms'] = $watchdog_ms
d['limits'].update(max_offset_mm=$max_offset_mm, max_rate_mm_s=$max_rate_mm_s,
                   cycle_ms=$period_us // 1000, rate_tolerance_ms=$rate_tolerance_ms)"
# Its stdout through a FIFO: the LISTENING line is awaited with a timeout, then the rest (the
# final report) is copied to sim.out.
mkfifo "$work/sim.fifo"
taskset -c "$server_cpu" "${run_as[@]}" "$sim" --config "$work/sim.json" --port 0 \
  --record "$work/sim-writes.csv" > "$work/sim.fifo" 2> "$work/sim.err" < /dev/null &
sim_pid=$!
exec 3< "$work/sim.fifo"
port=""
while IFS= read -r -t 20 line <&3; do
  if [[ "$line" == "LISTENING tcp"* ]]; then
    port="$(awk '{print $4}' <<< "$line")"
    break
  fi
done
[ -n "$port" ] || fail "the simulator did not start: $(cat "$work/sim.err")"
cat <&3 > "$work/sim.out" &
exec 3<&-

edit_json "$examples/volcompd-modbus-tcp.json" "$work/volcompd.json" "
d['model'] = '$examples/vmc-xyfz-21.json'
d['transport']['port'] = $port
d['cycle_period_ms'] = $period_us // 1000
d['limiter'].update(max_offset_mm=$max_offset_mm, max_rate_mm_s=$max_rate_mm_s)
d['log_level'] = 'info'"

# ---- the blocks ----------------------------------------------------------------------------
for n in $(seq "$blocks"); do
  # The baseline: cyclictest's histogram (whole microseconds up to 100 ms) gives each wake-up's
  # lateness; --default-system leaves /dev/cpu_dma_latency alone and no -m (mlockall), as volcompd.
  taskset -c "$cpu" cyclictest -q --default-system -a "$cpu" -t 1 "${ct_policy[@]}" \
    -i "$period_us" -D "$block_s" -h 100000 --json="$work/cyclictest-$n.json" \
    > /dev/null 2> "$work/cyclictest-$n.err" || fail "cyclictest failed: $(cat "$work/cyclictest-$n.err")"
  taskset -c "$cpu" "${run_as[@]}" "$daemon" --config "$work/volcompd.json" \
    2> "$work/volcompd-$n.err" < /dev/null &
  daemon_pid=$!
  sleep "$block_s" # the measurement's duration, not a synchronisation
  kill -TERM "$daemon_pid"
  status=0
  wait "$daemon_pid" || status=$?
  daemon_pid=""
  [ "$status" = 0 ] || fail "volcompd exited with status $status in block $n: $(tail -5 "$work/volcompd-$n.err")"
  echo "block $n done, load average $(cut -d' ' -f1-3 /proc/loadavg)"
done

kill -TERM "$sim_pid"
wait "$sim_pid" || fail "the simulator exited with an error: $(tail -5 "$work/sim.err")"
sim_pid=""
wait # the copy of the simulator's stdout

echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 "$root/bench/daemon/khz_report.py" "$work" "$blocks" "$period_us" "$max_offset_mm" \
  "$max_rate_mm_s" "$quantum_mm" "$rate_tolerance_ms" "$(awk "BEGIN {print $watchdog_ms / 1000}")"
