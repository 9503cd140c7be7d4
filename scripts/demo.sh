#!/usr/bin/env bash
# The volcomp demo: a simulated VMC (volcomp-sim, Modbus TCP on a free loopback port) with its
# TRUE error (config/examples/vmc-xyfz-21-true.json), compensated live by volcompd with the
# calibrated model (vmc-xyfz-21.json) and the example configuration. Shows progress once a second
# (cycle rate, offsets, error), then stops both and prints the error without and with
# compensation. Ends by writing the HTML report of the run (`volcomp report`: the daemon's model,
# the error without and with compensation, the offsets written) and printing its path.
# Exit status 0 when compensation at least halved the RMS error with no limiter violation and a
# clean daemon stop, 1 otherwise, 2 when something could not start.
#
# Usage: ./scripts/demo.sh [SECONDS]      (default 10). It first runs ./scripts/setup-debian.sh
#        --demo and ./scripts/build.sh --demo (what the demo needs and runs, nothing else;
#        BUILD_DIR as for build.sh); DEMO_NO_BUILD=1 skips both.
#        The report goes to DEMO_REPORT (default: BUILD_DIR/demo-report.html).
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
if [ "${DEMO_NO_BUILD:-}" != 1 ]; then
  "$root/scripts/setup-debian.sh" --demo
  "$root/scripts/build.sh" --demo
fi
build="${BUILD_DIR:-$root/build}"
examples="$root/config/examples"
seconds="${1:-10}"
sim="$build/tools/sim/volcomp-sim"
daemon="$build/daemon/volcompd/volcompd"
cli="$build/tools/cli/volcomp"
report_file="$(realpath -m "${DEMO_REPORT:-$build/demo-report.html}")"

for exe in "$sim" "$daemon" "$cli"; do
  if [ ! -x "$exe" ]; then
    echo "demo: $exe is missing: run ./scripts/setup-debian.sh --demo and ./scripts/build.sh --demo first" >&2
    exit 2
  fi
done
command -v python3 >/dev/null || { echo "demo: python3 is needed (scripts/setup-debian.sh)" >&2; exit 2; }

work="$(mktemp -d)"
daemon_pid=""
listener_pid=""
cleanup() {
  for p in "$daemon_pid" "$listener_pid" "${SIM_PID:-}"; do
    if [ -n "$p" ]; then kill "$p" 2>/dev/null || true; fi
  done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# ---- the simulated machine ------------------------------------------------------------------
# Its stdin takes commands ("status", "quit"); its stdout gives LISTENING, STATUS and the report.
coproc SIM { exec "$sim" --config "$examples/sim-vmc.json" \
  --model "$examples/vmc-xyfz-21-true.json" --port 0 --record "$work/writes.csv" \
  2> "$work/sim.err"; }
sim_out="${SIM[0]}"
sim_in="${SIM[1]}"
if ! read -r -t 10 -u "$sim_out" listening || [[ "$listening" != "LISTENING tcp "* ]]; then
  echo "demo: the simulator did not start:" >&2
  cat "$work/sim.err" >&2
  exit 2
fi
port="${listening##* }"

# ---- the daemon -----------------------------------------------------------------------------
# The example configuration, pointed at the simulator's port; the model path made absolute
# (a configuration's relative paths are resolved against its own directory).
python3 - "$examples/volcompd-modbus-tcp.json" "$work/volcompd.json" "$examples" "$port" <<'EOF'
import json, os, sys
source, target, examples, port = sys.argv[1:5]
d = json.load(open(source))
d["model"] = os.path.join(examples, d["model"])
d["transport"]["port"] = int(port)
json.dump(d, open(target, "w"), indent=2)
EOF
# A stand-in for systemd's notify socket: keeps the daemon's last STATUS= line in a file.
python3 - "$work/notify.sock" "$work/status.txt" <<'EOF' &
import socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(sys.argv[1])
while True:
    for line in s.recv(4096).decode(errors="replace").split("\n"):
        if line.startswith("STATUS="):
            with open(sys.argv[2] + ".new", "w") as f:
                f.write(line[7:] + "\n")
            __import__("os").replace(sys.argv[2] + ".new", sys.argv[2])
EOF
listener_pid=$!
for _ in $(seq 100); do [ -S "$work/notify.sock" ] && break; sleep 0.05; done

echo "volcomp demo: simulated VMC-850 on 127.0.0.1:$port, raster at 6 m/min"
echo "  true error model:   config/examples/vmc-xyfz-21-true.json"
echo "  daemon model:       config/examples/vmc-xyfz-21.json (what a calibration measured)"
echo "  daemon:             config/examples/volcompd-modbus-tcp.json (10 ms cycle, max 0.1 mm, 0.5 mm/s)"
echo
NOTIFY_SOCKET="$work/notify.sock" "$daemon" --config "$work/volcompd.json" 2> "$work/volcompd.log" &
daemon_pid=$!
for _ in $(seq 100); do
  grep -q "ready: first good cycle" "$work/volcompd.log" && break
  if ! kill -0 "$daemon_pid" 2>/dev/null; then
    echo "demo: volcompd exited:" >&2
    cat "$work/volcompd.log" >&2
    exit 2
  fi
  sleep 0.1
done
grep -q "ready: first good cycle" "$work/volcompd.log" || { cat "$work/volcompd.log" >&2; exit 2; }

sim_status() {
  echo status >&"$sim_in"
  local line
  while read -r -t 5 -u "$sim_out" line; do
    if [[ "$line" == "STATUS "* ]]; then
      echo "${line#STATUS }"
      return 0
    fi
  done
  return 1
}

# ---- progress, once a second ------------------------------------------------------------------
previous="$(sim_status)"
for ((t = 1; t <= seconds; t++)); do
  sleep 1  # display pacing only
  current="$(sim_status)"
  python3 - "$t" "$previous" "$current" "$work/status.txt" <<'EOF'
import json, math, sys
t, a, b, status_file = int(sys.argv[1]), json.loads(sys.argv[2]), json.loads(sys.argv[3]), sys.argv[4]
def rms_between(key):
    n1, n2 = a["samples"], b["samples"]
    if n2 <= n1:
        return float("nan")
    return math.sqrt(max(0.0, n2 * b[key] ** 2 - n1 * a[key] ** 2) / (n2 - n1))
rate = (b["writes"] - a["writes"]) / max(1e-9, b["duration_s"] - a["duration_s"])
o = b["applied_offset_mm"]
try:
    daemon = open(status_file).read().strip().split(", fault cycles")[0]
except OSError:
    daemon = "(no STATUS yet)"
print(f"t={t:2d}s  {rate:5.0f} writes/s  offsets X {o[0]*1000:+6.1f} Y {o[1]*1000:+6.1f} "
      f"Z {o[2]*1000:+6.1f} um  error (last s) {rms_between('rms_uncompensated_um'):5.2f} -> "
      f"{rms_between('rms_compensated_um'):5.2f} um RMS")
print(f"       volcompd: {daemon}")
EOF
  previous="$current"
done

# ---- stop: the daemon ramps the offsets out and writes zero, then the simulator reports --------
# The error statistics are taken while compensating (before the ramp-out); the final report
# adds the ramp-out's writes and the offsets left applied.
compensating="$(sim_status)"
kill -TERM "$daemon_pid"
daemon_rc=0
wait "$daemon_pid" || daemon_rc=$?
daemon_pid=""
echo quit >&"$sim_in"
report=""
while read -r -t 10 -u "$sim_out" line; do
  if [[ "$line" == "{"* ]]; then report="$line"; break; fi
done
[ -n "$report" ] || { echo "demo: no report from the simulator" >&2; cat "$work/sim.err" >&2; exit 2; }

status=0
python3 - "$report" "$daemon_rc" "$work/volcompd.log" "$compensating" "$work/run.json" <<'EOF' || status=$?
import json, re, sys
r, rc = json.loads(sys.argv[1]), int(sys.argv[2])
log = open(sys.argv[3]).read()
e = json.loads(sys.argv[4])
print()
print(f"summary over {e['duration_s']:.1f} s while compensating, {e['samples']} samples of the "
      f"tool-tip error (position semantics {r['position_semantics']})")
print(f"  {'':8}{'RMS before':>12}{'RMS after':>12}{'max before':>12}{'max after':>12}{'reduction':>11}")
rows = [("X", e["axes"]["X"]), ("Y", e["axes"]["Y"]), ("Z", e["axes"]["Z"]), ("|e|", e)]
for name, a in rows:
    red = 100.0 * (1.0 - a["rms_compensated_um"] / a["rms_uncompensated_um"]) if a["rms_uncompensated_um"] > 0 else 0.0
    print(f"  {name:8}{a['rms_uncompensated_um']:9.2f} um{a['rms_compensated_um']:9.2f} um"
          f"{a['max_uncompensated_um']:9.2f} um{a['max_compensated_um']:9.2f} um{red:9.1f} %")
m = re.search(r"stopped after (\d+) cycles \((\d+) overruns\)", log)
print(f"  writes {r['writes']} ({r['partial_writes']} partial), limiter violations {r['limiter_violations']}, "
      f"sessions {r['sessions']}, applied offsets at the end {r['applied_offset_mm']} mm")
if m:
    print(f"  volcompd: {m.group(1)} cycles, {m.group(2)} overruns, exit status {rc}")
# For the report: the simulator's final line, its snapshot while compensating, the daemon's end.
run = dict(r, compensating=e, daemon={"exit_status": rc})
if m:
    run["daemon"].update(cycles=int(m.group(1)), overruns=int(m.group(2)))
json.dump(run, open(sys.argv[5], "w"), indent=1)
ok = (e["rms_compensated_um"] <= 0.5 * e["rms_uncompensated_um"] and r["limiter_violations"] == 0
      and rc == 0 and all(o == 0 for o in r["applied_offset_mm"]))
print("result: " + ("compensation works" if ok else "FAILED (see above)"))
sys.exit(0 if ok else 1)
EOF

# ---- the report of this run ---------------------------------------------------------------------
# From the checkout's root, so that the report names the model as config/examples/....
if (cd "$root" && "$cli" report config/examples/vmc-xyfz-21.json --run "$work/run.json" \
    --writes "$work/writes.csv" --machine "VMC-850 (simulated, demo run)" --out "$report_file") \
    > "$work/report.out" 2> "$work/report.err"; then
  echo "report: $report_file"
else
  echo "demo: the report could not be written:" >&2
  cat "$work/report.err" >&2
  status=1
fi
exit "$status"
