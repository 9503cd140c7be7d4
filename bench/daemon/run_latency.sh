#!/usr/bin/env bash
# Latency of volcompd's cycle against a loopback Modbus TCP server (volcomp-sim), beside the bare
# libmodbus FC03+FC16 transaction against the same server in the same run (both processes pinned
# to one CPU). volcompd at 1 kHz against the empty-loop baseline is bench/daemon/run_1khz.sh.
#
# Usage: bench/daemon/run_latency.sh            (after ./scripts/build.sh)
# Environment: BUILD_DIR (default ./build), CPU (the CPU of the run, default the last),
#   SAMPLES (default 20000), RT=1 to run both under SCHED_FIFO 50 (chrt; needs the privilege).
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${BUILD_DIR:-$root/build}"
examples="$root/config/examples"
sim="$build/tools/sim/volcomp-sim"
harness="$build/bench/daemon/volcomp-bench-cycle"
cpu="${CPU:-$(($(nproc) - 1))}"
samples="${SAMPLES:-20000}"
prio=()
if [ "${RT:-0}" = "1" ]; then prio=(chrt -f 50); fi

for exe in "$sim" "$harness"; do
  [ -f "$exe" ] && [ -x "$exe" ] || { echo "run_latency: $exe not built (run ./scripts/build.sh)" >&2; exit 2; }
done

work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# Starts the simulator with config $1 on CPU $2, output in $3.out; sets sim_pid and port.
start_sim() {
  local config="$1" on_cpu="$2" tag="$3"
  taskset -c "$on_cpu" "${prio[@]}" "$sim" --config "$config" --port 0 \
    > "$work/$tag.out" 2> "$work/$tag.err" < /dev/null &
  sim_pid=$!
  pids+=("$sim_pid")
  for _ in $(seq 200); do
    if grep -q '^LISTENING tcp' "$work/$tag.out" 2>/dev/null; then
      port="$(awk '/^LISTENING tcp/ {print $4; exit}' "$work/$tag.out")"
      return 0
    fi
    sleep 0.05
  done
  echo "run_latency: the simulator did not start: $(cat "$work/$tag.err")" >&2
  return 1
}

# Writes a JSON file from an example with edits: edit_json SRC DST PYTHON-STATEMENTS (on `d`).
edit_json() {
  python3 "$root/bench/daemon/edit_json.py" "$@"
}

echo "machine: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p'), $(nproc) CPUs, kernel $(uname -r)"
echo "pinning: server and client on CPU $cpu${RT:+, RT=$RT}"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"

# ---- 1. cycle latency vs bare transaction -------------------------------------------------
edit_json "$examples/sim-vmc.json" "$work/sim.json" "
d['model'] = '$examples/vmc-xyfz-21.json'
d['heartbeat_timeout_ms'] = 0"
start_sim "$work/sim.json" "$cpu" sim1
edit_json "$examples/volcompd-modbus-tcp.json" "$work/volcompd.json" "
d['model'] = '$examples/vmc-xyfz-21.json'
d['transport']['port'] = $port
d['log_level'] = 'warn'"
result="$(taskset -c "$cpu" "${prio[@]}" "$harness" --config "$work/volcompd.json" \
  --samples "$samples" --rounds 10 --period-us 1000)"
kill "$sim_pid"; wait "$sim_pid" 2>/dev/null || true; pids=()
python3 - "$result" <<'EOF'
import json, sys
r = json.loads(sys.argv[1])
print(f"\ncycle latency, {r['daemon_cycle']['n']} cycles each, paced at {r['period_us']} us, "
      f"FC03 {r['read_registers']} + FC16 {r['write_registers']} registers, model '{r['model']}'")
print(f"{'':28}{'median':>10}{'p99':>10}{'p99.9':>10}{'max':>10}  (us)")
for name, key in (("volcompd cycle (step)", "daemon_cycle"), ("bare libmodbus FC03+FC16", "bare_fc03_fc16")):
    s = r[key]
    print(f"{name:28}{s['median_us']:10.1f}{s['p99_us']:10.1f}{s['p99_9_us']:10.1f}{s['max_us']:10.1f}")
w = r["wake_late"]
print(f"{'wake-up lateness (pacing)':28}{w['median_us']:10.1f}{w['p99_us']:10.1f}{w['p99_9_us']:10.1f}{w['max_us']:10.1f}")
print(f"ratio cycle/bare: median {r['ratio_median']:.3f}, p99 {r['ratio_p99']:.3f} (target <= 1.2)")
if r['cycles_not_active'] or r['bare_errors']:
    print(f"note: {r['cycles_not_active']} cycles not active, {r['bare_errors']} bare errors")
EOF

echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
