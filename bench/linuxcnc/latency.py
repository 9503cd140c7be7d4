#!/usr/bin/python3
"""Latency of the LinuxCNC adapter: from a position change on HAL to the offset LinuxCNC applies.

A headless LinuxCNC (the VMC-850 of config/examples with the shipped HAL snippet, as the tests of
label `linuxcnc` run it: tests/linuxcnc/harness) moves X at constant feed while volcompd
compensates with a ramp model: EXX grows linearly by 0.1 um per mm (85 um over the travel), so that
the offset changes by one count (0.1 um) every millimetre of X, every 5 ms at 200 mm/s. The realtime
sampler records every servo period (1 ms) LinuxCNC's commanded X (`axis.x.pos-cmd`), the offset
volcompd requested (`axis.x.eoffset-request`, counts x scale) and the one LinuxCNC applies
(`axis.x.eoffset`).

For every new requested value r: t0 is the first servo period in which the commanded X had
reached the position where the model's offset (`volcomp eval --points` on the recorded positions)
rounds to r, i.e. the position change that calls for it; t1 the first period with the request at r,
t2 the first with the applied offset at r. t1 - t0 is the adapter's latency (the daemon's cycle
sampling, its work, HAL); t2 - t0 adds LinuxCNC's pick-up and ramp. Resolution: one servo period.

usage: cmake --build build --target bench-linuxcnc-latency, or
       flock /tmp/volcomp-linuxcnc.lock python3 bench/linuxcnc/latency.py \\
           build/daemon/volcompd/volcompd-linuxcnc build/tools/cli/volcomp config/linuxcnc WORK
Prints the figures and writes WORK/latency.json.
"""
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "linuxcnc", "harness"))
import checks  # noqa: E402
import daemon as vd  # noqa: E402
import lcnc  # noqa: E402
import vmc  # noqa: E402

UM_PER_MM = 0.1
PINS = ["axis.x.pos-cmd", "axis.x.eoffset-request", "axis.x.eoffset", "test-phase"]


def ramp_model(examples, path):
    with open(os.path.join(examples, "vmc-xyfz-21-true.json")) as f:
        model = json.load(f)
    model["name"] = "latency ramp: EXX %.1f um per mm" % UM_PER_MM
    model["components"] = {"EXX": {"positions": [0, 850], "values": [0, 850 * UM_PER_MM],
                                   "interpolation": "linear"}}
    model["grids"] = []
    with open(path, "w") as f:
        json.dump(model, f, indent=2)
    return path


def model_offsets(volcomp, model, xs, work):
    points = os.path.join(work, "points.csv")
    with open(points, "w") as f:
        f.write("x,y,z\n")
        for x in xs:
            f.write("%.9f,250,-250\n" % x)
    out = os.path.join(work, "offsets.csv")
    subprocess.run([volcomp, "eval", model, "--points", points, "--out", out], check=True,
                   capture_output=True)
    with open(out) as f:
        next(f)
        return [float(line.split(",")[9]) for line in f]


def percentile(values, p):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(p / 100 * (len(ordered) - 1))))]


def latencies(rows, offsets, quantum):
    """Per new request value: (t1 - t0, t2 - t0) in servo periods."""
    request, applied = [r[2] for r in rows], [r[3] for r in rows]
    out = []
    for i in range(1, len(rows)):
        if request[i] == request[i - 1]:
            continue
        r = request[i]
        # The first period whose commanded position calls for r (the model offset rounds to it).
        t0 = next((j for j in range(len(rows))
                   if round(offsets[j] / quantum) == round(r / quantum)), None)
        if t0 is None or t0 == 0:
            continue
        t2 = next((j for j in range(i, len(rows)) if abs(applied[j] - r) < quantum / 100), None)
        if t2 is None:
            continue
        out.append((i - t0, t2 - t0))
    return out


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    volcompd, volcomp, hal_dir, work = (os.path.abspath(a) for a in sys.argv[1:])
    examples = os.path.join(HERE, "..", "..", "config", "examples")
    machine = vmc.machine(work, hal_dir)
    model = ramp_model(examples, os.path.join(work, "ramp.json"))
    config = os.path.join(work, "volcompd.json")
    vd.write_config(config, model, vmc.TRANSPORT, cycle_ms=vmc.CYCLE_MS,
                    max_offset=vmc.MAX_OFFSET, max_rate=vmc.MAX_RATE)
    with machine:
        capture = machine.capture(PINS, name="latency-capture")
        machine.on_and_home()
        machine.mdi("G21 G90 G0 X20 Y250 Z-250")
        daemon = vd.Daemon(volcompd, config, os.path.join(work, "volcompd.log")).start()
        lcnc.wait_for(lambda: "volcomp" in vd.component_names(), "volcompd's component", 30)
        vd.wait_status(machine, "volcomp",
                       lambda s: s & vd.STATUS_ACTIVE and not s & vd.STATUS_LIMITED,
                       "volcompd active and settled")
        checks.set_phase(1)
        machine.mdi("G1 F12000 X830")
        checks.set_phase(2)
        machine.mdi("G1 F12000 X20")
        checks.set_phase(3)
        rc = daemon.terminate()
        rows = capture.stop()
    load = os.getloadavg()
    if rc != 0 or not lcnc.check_gapless(rows):
        lcnc.die("volcompd exit %s, capture gapless %s" % (rc, lcnc.check_gapless(rows)))
    quantum = 1.0 / vmc.COUNTS_PER_MM
    result = {"servo_period_ms": 1.0, "daemon_cycle_ms": vmc.CYCLE_MS,
              "load_average": load, "runs": {}}
    for phase, name in ((1, "X+"), (2, "X-")):
        selected = [r for r in rows if int(r[4]) == phase]
        offsets = model_offsets(volcomp, model, [r[1] for r in selected], work)
        pairs = latencies(selected, offsets, quantum)
        request = [a for a, _ in pairs]
        applied = [b for _, b in pairs]
        result["runs"][name] = {
            "changes": len(pairs),
            "request_ms": {"median": statistics.median(request), "p90": percentile(request, 90),
                           "p99": percentile(request, 99), "max": max(request),
                           "min": min(request)},
            "applied_ms": {"median": statistics.median(applied), "p90": percentile(applied, 90),
                           "p99": percentile(applied, 99), "max": max(applied),
                           "min": min(applied)},
        }
        print("%s: %d offset changes; position change -> request median %s ms (p90 %s, p99 %s, "
              "max %s); -> applied median %s ms (p90 %s, p99 %s, max %s)" % (
                  name, len(pairs), result["runs"][name]["request_ms"]["median"],
                  percentile(request, 90), percentile(request, 99), max(request),
                  result["runs"][name]["applied_ms"]["median"], percentile(applied, 90),
                  percentile(applied, 99), max(applied)), flush=True)
    print("load average %.1f %.1f %.1f" % load)
    with open(os.path.join(work, "latency.json"), "w") as f:
        json.dump(result, f, indent=2)


if __name__ == "__main__":
    main()
