#!/usr/bin/env python3
"""Latency compensation, measured with whole processes: volcompd against volcomp-sim over Modbus
TCP (loopback), the same model on both sides (config/examples/vmc-xyfz-21.json, bidirectional X),
on fast paths, with latency compensation off and on, runs interleaved so that both see the same
load. Prints per path and mode the medians over the runs of the simulator's motion-induced error
(the compensated error minus what the ideal zero-latency offset would leave at the same instant;
docs/daemon.md "Latency compensation"), its steady part (outside the three cycles after a
reversal), the total compensated residual and the limiter violations.

Usage: bench/daemon/latency_compensation.py [--runs 5] [--duration 8] [--paths line,circle,...]
  [--controller-latency-ms 0] [--position-scan-ms 0] [--timestamp] [--period-ms 10]
  [--sim-cpu 0] [--daemon-cpu 1] [--json FILE]
(after ./scripts/build.sh; BUILD_DIR overrides ./build)."""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("BUILD_DIR", os.path.join(ROOT, "build"))
EXAMPLES = os.path.join(ROOT, "config", "examples")
SIM = os.path.join(BUILD, "tools", "sim", "volcomp-sim")
DAEMON = os.path.join(BUILD, "daemon", "volcompd", "volcompd")
MODEL = os.path.join(EXAMPLES, "vmc-xyfz-21.json")

# 400 mm/s = 24 m/min. "line": a body diagonal of the travel, back and forth (a reversal of every
# axis at each end, 1.9 s apart); "reversals": X zig-zags of 40 mm (a reversal every 0.1 s, Y and
# Z stepping); "circle": r = 100 mm in XY (each of X and Y reverses twice per 1.57 s turn, braked
# at v^2/r = 1.6 m/s^2). The polylines are driven as a CNC drives them in exact stop, braking at
# ACCEL_MM_S2 into every point (0.5 g, a common VMC figure); the "-unbraked" variants turn at full
# feed (an infinite deceleration no machine has: the worst case, no turn can be seen coming);
# "stops": X in steps of 40 mm with an exact stop at each point and on in the same direction,
# 200 mm back in one move (4 stops and 2 reversals per lap: a stop is braked like a reversal, and
# the compensation cannot tell them apart until the axis rests).
ACCEL_MM_S2 = 5000
LINE = [[100, 100, -300], [750, 400, -100]]
ZIGZAG = [[300, 100, -200], [340, 150, -200], [300, 200, -180],
          [340, 250, -180], [300, 300, -160], [340, 350, -160]]
PATHS = {
    "line": {"type": "points", "feed_mm_min": 24000, "points": LINE,
             "accel_mm_s2": ACCEL_MM_S2},
    "reversals": {"type": "points", "feed_mm_min": 24000, "points": ZIGZAG,
                  "accel_mm_s2": ACCEL_MM_S2},
    "circle": {"type": "circle", "center": [400, 250, -200], "radius_mm": 100,
               "feed_mm_min": 24000},
    "stops": {"type": "points", "feed_mm_min": 24000, "accel_mm_s2": ACCEL_MM_S2,
              "points": [[300 + 40 * i, 250, -200] for i in range(6)]},
    "line-unbraked": {"type": "points", "feed_mm_min": 24000, "points": LINE},
    "reversals-unbraked": {"type": "points", "feed_mm_min": 24000, "points": ZIGZAG},
}


# The controller's latch time: one register after the example map's heartbeat, 10 us ticks.
TIMESTAMP = {"address": 22, "tick_us": 10}


def load(name):
    with open(os.path.join(EXAMPLES, name)) as f:
        return json.load(f)


def run_once(work, path_name, latency_on, args, tag):
    sim = load("sim-vmc.json")
    sim["model"] = MODEL
    sim["path"] = PATHS[path_name]
    sim["settle_ms"] = 500
    sim["limits"]["cycle_ms"] = args.period_ms
    sim["controller_latency_ms"] = args.controller_latency_ms
    sim["position_scan_ms"] = args.position_scan_ms
    if args.timestamp:
        sim["transport"]["registers"]["timestamp"] = TIMESTAMP
    sim_file = os.path.join(work, tag + "-sim.json")
    with open(sim_file, "w") as f:
        json.dump(sim, f)
    sim_proc = subprocess.Popen(
        ["taskset", "-c", str(args.sim_cpu), SIM, "--config", sim_file, "--port", "0",
         "--duration", str(args.duration)] + getattr(args, "extra", []),
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL, text=True)
    line = sim_proc.stdout.readline().split()
    if len(line) < 4 or line[0] != "LISTENING":
        sim_proc.kill()
        raise RuntimeError("the simulator did not start: " + " ".join(line))
    daemon = load("volcompd-modbus-tcp.json")
    daemon["model"] = MODEL
    daemon["transport"]["port"] = int(line[3])
    daemon["log_level"] = "warn"
    daemon["cycle_period_ms"] = args.period_ms
    daemon["latency_compensation"] = {"enabled": latency_on,
                                      "controller_latency_ms": args.controller_latency_ms}
    if args.timestamp:
        daemon["transport"]["registers"]["timestamp"] = TIMESTAMP
    daemon_file = os.path.join(work, tag + "-volcompd.json")
    with open(daemon_file, "w") as f:
        json.dump(daemon, f)
    daemon_proc = subprocess.Popen(
        ["taskset", "-c", str(args.daemon_cpu), DAEMON, "--config", daemon_file],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
    report = None
    for text in sim_proc.stdout:
        text = text.strip()
        if text.startswith("{"):
            report = json.loads(text)
    sim_proc.wait()
    daemon_proc.terminate()
    try:
        daemon_proc.wait(timeout=20)
    except subprocess.TimeoutExpired:
        daemon_proc.kill()
        daemon_proc.wait()
    if report is None:
        raise RuntimeError("no report from the simulator")
    return report


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--duration", type=float, default=8.0)
    parser.add_argument("--paths", default=",".join(PATHS))
    parser.add_argument("--controller-latency-ms", type=float, default=0.0,
                        help="the simulated controller's delay from receiving an offset to "
                        "applying it at the axes, and volcompd's latency_compensation."
                        "controller_latency_ms (told the truth)")
    parser.add_argument("--position-scan-ms", type=float, default=0.0,
                        help="the simulated controller latches the positions once per scan of "
                        "this length and serves them until the next (0: fresh at every read)")
    parser.add_argument("--timestamp", action="store_true",
                        help="map a timestamp register (the latch time, 10 us ticks) in the "
                        "simulator and in volcompd")
    parser.add_argument("--period-ms", type=float, default=10.0,
                        help="volcompd's cycle_period_ms (and the simulator's cycle_ms)")
    parser.add_argument("--sim-cpu", type=int, default=0)
    parser.add_argument("--daemon-cpu", type=int, default=min(1, os.cpu_count() - 1))
    parser.add_argument("--json", help="also write every run's figures to this file")
    args = parser.parse_args()
    for exe in (SIM, DAEMON):
        if not os.access(exe, os.X_OK):
            sys.exit(f"latency_compensation: {exe} not built (run ./scripts/build.sh)")
    paths = args.paths.split(",")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs; "
          f"simulator on CPU {args.sim_cpu}, volcompd on CPU {args.daemon_cpu}; "
          f"{args.runs} runs x {args.duration} s per path and mode; controller latency "
          f"{args.controller_latency_ms:g} ms; position scan {args.position_scan_ms:g} ms; "
          f"timestamp register {'mapped' if args.timestamp else 'not mapped'}", flush=True)
    print(f"load average before: {open('/proc/loadavg').read().split()[:3]}", flush=True)
    results = {p: {"off": [], "on": []} for p in paths}
    with tempfile.TemporaryDirectory() as work:
        for run in range(args.runs):
            for p in paths:
                for mode in ("off", "on"):
                    r = run_once(work, p, mode == "on", args, f"{p}-{mode}-{run}")
                    results[p][mode].append(r)
                    print(f"  run {run + 1} {p:18} {mode:3}: motion RMS {r['rms_motion_um']:.3f} "
                          f"max {r['max_motion_um']:.2f} um, steady RMS "
                          f"{r['rms_motion_steady_um']:.3f} um, residual RMS "
                          f"{r['rms_compensated_um']:.3f} um, violations "
                          f"{r['limiter_violations']}", file=sys.stderr, flush=True)
    print(f"load average after: {open('/proc/loadavg').read().split()[:3]}")
    print(f"\n{'path':18} {'mode':4} {'motion RMS':>11} {'motion max':>11} {'steady RMS':>11} "
          f"{'residual RMS':>13} {'uncomp. RMS':>12} {'violations':>11}   (um, medians of "
          f"{args.runs}; period {args.period_ms:g} ms)")
    summary = {}
    for p in paths:
        for mode in ("off", "on"):
            rs = results[p][mode]
            med = {k: statistics.median(r[k] for r in rs)
                   for k in ("rms_motion_um", "max_motion_um", "rms_motion_steady_um",
                             "rms_compensated_um", "rms_uncompensated_um")}
            med["violations"] = sum(r["limiter_violations"] for r in rs)
            summary.setdefault(p, {})[mode] = med
            print(f"{p:18} {mode:4} {med['rms_motion_um']:11.3f} {med['max_motion_um']:11.2f} "
                  f"{med['rms_motion_steady_um']:11.3f} {med['rms_compensated_um']:13.3f} {med['rms_uncompensated_um']:12.2f} "
                  f"{med['violations']:11d}")
        def cut(key):
            return 100.0 * (1.0 - summary[p]["on"][key] / summary[p]["off"][key])
        print(f"{p:18} reduced by: motion-induced RMS {cut('rms_motion_um'):.0f} %, steady part "
              f"{cut('rms_motion_steady_um'):.0f} %")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"summary": summary, "runs": results}, f, indent=1)


if __name__ == "__main__":
    main()
