#!/usr/bin/env bash
# Latency of volcompd's cycle against a loopback Modbus TCP server (volcomp-sim), beside the bare
# libmodbus FC03+FC16 transaction against the same server in the same run (both processes pinned
# to one CPU), then the wake-up lateness of an empty 1 kHz cycle on volcompd's CPU (cyclictest from
# rt-tests: the platform's share of any overrun), then volcompd itself at 1 kHz for SUSTAIN_S
# seconds counting overruns.
#
# Usage: bench/daemon/run_latency.sh            (after ./scripts/build.sh)
# Environment: BUILD_DIR (default ./build), CPU (the CPU of the latency run, default the last),
#   SERVER_CPU (the simulator's CPU in the sustained run, default 0), SAMPLES (default 20000),
#   SUSTAIN_S (default 60), RT=1 to run both under SCHED_FIFO 50 (chrt; needs the privilege),
#   PACING_S (seconds of the cyclictest baseline, default 10; 0 skips it).
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${BUILD_DIR:-$root/build}"
examples="$root/config/examples"
sim="$build/tools/sim/volcomp-sim"
daemon="$build/daemon/volcompd/volcompd"
harness="$build/bench/daemon/volcomp-bench-cycle"
cpu="${CPU:-$(($(nproc) - 1))}"
server_cpu="${SERVER_CPU:-0}"
samples="${SAMPLES:-20000}"
sustain="${SUSTAIN_S:-60}"
pacing_s="${PACING_S:-10}"
prio=()
if [ "${RT:-0}" = "1" ]; then prio=(chrt -f 50); fi

for exe in "$sim" "$daemon" "$harness"; do
  [ -f "$exe" ] && [ -x "$exe" ] || { echo "run_latency: $exe not built (run ./scripts/build.sh)" >&2; exit 2; }
done
if [ "$pacing_s" != "0" ] && ! command -v cyclictest > /dev/null; then
  echo "run_latency: cyclictest not found (Debian package rt-tests; scripts/setup-debian.sh)" >&2
  exit 2
fi

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
  python3 - "$1" "$2" "$3" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(d, open(sys.argv[2], "w"), indent=2)
EOF
}

echo "machine: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p'), $(nproc) CPUs, kernel $(uname -r)"
echo "pinning: latency run on CPU $cpu (server and client); sustained run: volcompd on CPU $cpu, server on CPU $server_cpu${RT:+, RT=$RT}"
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

# ---- 2. the platform's pacing baseline on volcompd's CPU: cyclictest ----------------------
# An empty cycle woken every 1 ms on absolute deadlines (clock_nanosleep), at volcompd's priority;
# --default-system leaves /dev/cpu_dma_latency alone, as volcompd does. Its lateness is the
# platform's share of any overrun; wake-ups more than 1 ms late (the histogram's overflows) are
# the deadlines an empty cycle would miss.
if [ "$pacing_s" != "0" ]; then
  ct_policy=(--policy=other)
  if [ "${RT:-0}" = "1" ]; then ct_policy=(--policy=fifo -p 50); fi
  if ! cyclictest -q -m --default-system -a "$cpu" -t 1 "${ct_policy[@]}" -i 1000 \
    -D "$pacing_s" -h 1000 --json="$work/cyclictest.json" > /dev/null 2> "$work/cyclictest.err"; then
    echo "run_latency: cyclictest failed: $(cat "$work/cyclictest.err")" >&2
    exit 1
  fi
  python3 - "$work/cyclictest.json" "$pacing_s" <<'EOF'
import json, sys
t = json.load(open(sys.argv[1]))["thread"]["0"]
counts = sorted((int(us), n) for us, n in t["histogram"].items())
def percentile(p):
    want, seen = p * t["cycles"], 0
    for us, n in counts:
        seen += n
        if seen >= want:
            return f"{us}"
    return "> 1000"
late = t["cycles"] - sum(n for _, n in counts)
print(f"\ncyclictest, empty 1 kHz cycle for {sys.argv[2]} s on CPU {t['cpu']}: {t['cycles']} wake-ups, "
      f"lateness median {percentile(0.5)} us, p99 {percentile(0.99)} us, "
      f"p99.9 {percentile(0.999)} us, max {t['max']} us; {late} more than 1 ms late")
EOF
fi

# ---- 3. volcompd at 1 kHz for $sustain s ---------------------------------------------------
edit_json "$examples/sim-vmc.json" "$work/sim1k.json" "
d['model'] = '$examples/vmc-xyfz-21.json'
d['limits']['cycle_ms'] = 1
d['limits']['rate_tolerance_ms'] = 1"
start_sim "$work/sim1k.json" "$server_cpu" sim2
edit_json "$examples/volcompd-modbus-tcp.json" "$work/volcompd1k.json" "
d['model'] = '$examples/vmc-xyfz-21.json'
d['transport']['port'] = $port
d['cycle_period_ms'] = 1
d['log_level'] = 'info'"
taskset -c "$cpu" "${prio[@]}" "$daemon" --config "$work/volcompd1k.json" 2> "$work/volcompd1k.err" &
daemon_pid=$!
pids+=("$daemon_pid")
echo
echo "volcompd at 1 kHz for $sustain s ..."
sleep "$sustain"   # the measurement's duration, not a synchronisation
kill -TERM "$daemon_pid"
daemon_rc=0
wait "$daemon_pid" || daemon_rc=$?
kill -TERM "$sim_pid"
wait "$sim_pid" 2>/dev/null || true
pids=()
stopped="$(grep -o 'stopped after [0-9]* cycles ([0-9]* overruns).*' "$work/volcompd1k.err" || true)"
skipped="$(grep -o '([0-9]* deadlines skipped in total)' "$work/volcompd1k.err" | tail -1 || true)"
report="$(grep '^{' "$work/sim2.out" | tail -1)"
python3 - "$sustain" "$stopped" "$skipped" "$report" "$daemon_rc" <<'EOF'
import json, re, sys
sustain, stopped, skipped, report, rc = sys.argv[1:6]
m = re.search(r"after (\d+) cycles \((\d+) overruns\)", stopped)
cycles, overruns = (int(m.group(1)), int(m.group(2))) if m else (None, None)
missed = re.search(r"\((\d+) deadlines", skipped)
late = re.search(r"latest start (\d+) us after", stopped)
r = json.loads(report) if report else {}
print(f"cycles {cycles} in {sustain} s (expected {int(float(sustain) * 1000)}), overruns {overruns}, "
      f"deadlines skipped {missed.group(1) if missed else 0}, latest cycle start "
      f"{late.group(1) + ' us' if late else '?'} after its deadline, exit status {rc}")
if r:
    print(f"controller saw {r['writes']} writes, {r['limiter_violations']} limiter violations, "
          f"{r['requests_unanswered']} unanswered requests; error RMS "
          f"{r['rms_uncompensated_um']:.2f} -> {r['rms_compensated_um']:.3f} um")
EOF
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
