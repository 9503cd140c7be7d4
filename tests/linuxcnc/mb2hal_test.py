#!/usr/bin/python3
"""mb2hal drives LinuxCNC 2.9 against volcompd's Modbus server role (test label `linuxcnc`).

A headless LinuxCNC simulates the VMC-850 of config/examples with the shipped mb2hal snippet
(config/linuxcnc/volcomp-mb2hal.hal, volcomp-mb2hal-link.hal, mb2hal.ini): mb2hal, a Modbus
master of 16-bit registers, writes each axis's commanded position as the two words of an int32 and
reads the offsets as int16 that HAL sign-extends and applies as external offsets. volcompd runs
with role "server" (volcompd-mb2hal.json, the calibrated example model) on a port chosen at run
time. LinuxCNC runs programs/part.ngc while volcompd compensates; every servo period a realtime
sampler records the commanded positions and the applied offsets, and the true tool-tip error
along the path (the TRUE example model) must drop by at least 90 % RMS. The offsets never exceed
max_offset and the counts move no faster than the daemon's limiter allows.

Then volcompd is restarted: mb2hal does not reconnect by itself (its transactions keep failing,
num_errors climbs); the documented recovery (unloadusr mb2hal, halcmd -f
volcomp-mb2hal-link.hal) brings the compensation back.

usage: mb2hal_test.py VOLCOMPD TOOLTIP_ERROR EXAMPLES_DIR HAL_DIR PROGRAM WORK
Writes WORK/report.json. Exit status 0 when every check holds.
"""
import json
import os
import shutil
import socket
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "harness"))
import daemon as vd  # noqa: E402
import lcnc  # noqa: E402
import vmc  # noqa: E402
import checks  # noqa: E402

STATUS_ACTIVE = 1
STATUS_LIMITED = 1 << 3
MAX_OFFSET = 0.1
MAX_RATE = 0.5
CYCLE_S = 0.010
COUNT_MM = 1e-4
SERVO_S = 0.001
PINS = (["axis.%s.pos-cmd" % a for a in "xyz"] +           # 1..3 (tooltip_error's columns)
        ["axis.%s.eoffset" % a for a in "xyz"] +           # 4..6
        ["volcomp-%s-eoffset-counts" % a for a in "xyz"] +  # 7..9
        ["test-phase", "volcomp-status", "volcomp-mb-errors"])  # 10..12
COL_COUNTS = 7
COL_PHASE = 10


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_daemon(volcompd, config, log):
    daemon = vd.Daemon(volcompd, config, log).start()
    lcnc.wait_for(lambda: "listening on tcp" in daemon.text(), "volcompd listening", 30)
    return daemon


def check_counts(rows, failures):
    """|applied offset| <= max_offset; the counts volcompd's offsets become move by at most
    max_rate over the time between two changes plus one daemon cycle (mb2hal reads about every
    7 ms, so a change may carry several cycles). Returns the worst change as a fraction of its
    allowance."""
    largest = max(abs(r[4 + k]) for r in rows for k in range(3))
    failures.check(largest <= MAX_OFFSET + COUNT_MM,
                   "applied offsets within max_offset (largest %.4f mm)" % largest)
    worst = 0.0
    for k in range(3):
        last_value = rows[0][COL_COUNTS + k] * COUNT_MM
        last_at = rows[0][0] * SERVO_S
        for r in rows[1:]:
            value, at = r[COL_COUNTS + k] * COUNT_MM, r[0] * SERVO_S
            if value == last_value:
                continue
            allowed = MAX_RATE * (at - last_at + CYCLE_S) + COUNT_MM
            worst = max(worst, abs(value - last_value) / allowed)
            last_value, last_at = value, at
    failures.check(worst <= 1.0 + 1e-9, "every change of the counts within the limiter's rate "
                   "(worst %.2f of the allowance)" % worst)
    return worst


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    volcompd, tooltip, examples, hal_dir, program, work = (os.path.abspath(a) for a in sys.argv[1:])
    failures = checks.Failures()
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)
    port = free_port()
    with open(os.path.join(hal_dir, "volcompd-mb2hal.json")) as f:
        config = json.load(f)
    config["model"] = os.path.join(examples, "vmc-xyfz-21.json")
    config["transport"]["port"] = port
    config_path = os.path.join(work, "volcompd.json")
    with open(config_path, "w") as f:
        json.dump(config, f, indent=2)
    with open(os.path.join(hal_dir, "mb2hal.ini")) as f:
        ini = f.read().replace("TCP_PORT=1502", "TCP_PORT=%d" % port)
    machine = lcnc.Machine(work, vmc.TRAVEL, max_velocity=vmc.MAX_VELOCITY,
                           max_acceleration=vmc.MAX_ACCELERATION,
                           offset_av_ratio=vmc.OFFSET_AV_RATIO,
                           hal_files=["volcomp-mb2hal.hal", "volcomp-mb2hal-link.hal", "test.hal"])
    machine.prepare()
    with open(os.path.join(work, "mb2hal.ini"), "w") as f:
        f.write(ini)
    for name in ("volcomp-mb2hal.hal", "volcomp-mb2hal-link.hal"):
        shutil.copy(os.path.join(hal_dir, name), work)
    with open(os.path.join(work, "test.hal"), "w") as f:
        f.write("newsig test-phase s32\n")
    report = {"port": port}
    # volcompd first: mb2hal connects when it loads (it retries while nothing listens).
    daemon = start_daemon(volcompd, config_path, os.path.join(work, "volcompd-1.log"))
    try:
        with machine:
            print("LinuxCNC up in %.1f s" % machine.startup_s, flush=True)
            capture = machine.capture(PINS)
            machine.on_and_home()
            machine.mdi("G21 G90 G0 X80 Y60 Z-40")
            status = lambda: int(machine.get("volcomp-status"))  # noqa: E731
            lcnc.wait_for(lambda: status() & STATUS_ACTIVE and not status() & STATUS_LIMITED,
                          "volcompd active and settled through mb2hal", 30)
            checks.set_phase(1)
            machine.mdi("G0 X80 Y60 Z-40")
            machine.run_program(program)
            machine.wait_program()
            checks.set_phase(2)
            # A restarted volcompd: mb2hal keeps its dead connection.
            rc = daemon.terminate()
            failures.check(rc == 0, "volcompd exits 0 after SIGTERM (got %s)" % rc)
            daemon = start_daemon(volcompd, config_path, os.path.join(work, "volcompd-2.log"))
            heartbeat = int(machine.get("volcomp-heartbeat"))
            lcnc.wait_for(lambda: int(machine.get("volcomp-mb-errors")) > 100,
                          "mb2hal failing against the restarted server", 10)
            failures.check(int(machine.get("volcomp-heartbeat")) == heartbeat,
                           "mb2hal does not reconnect by itself (%d failed reads in a row, the "
                           "heartbeat frozen)" % int(machine.get("volcomp-mb-errors")))
            # The documented recovery: reload mb2hal and link its pins again.
            lcnc.halcmd("unloadusr", "mb2hal")
            subprocess.run(["halcmd", "-f", "volcomp-mb2hal-link.hal"], cwd=work, check=True,
                           start_new_session=True)
            back = lcnc.wait_for(lambda: int(machine.get("volcomp-mb-errors")) == 0 and
                                 status() & STATUS_ACTIVE,
                                 "compensation back after reloading mb2hal", 30)
            failures.check(bool(back), "reloading mb2hal restores the compensation")
            checks.set_phase(3)
            rows = capture.stop()
    finally:
        if daemon.running():
            daemon.terminate()
    failures.check(lcnc.check_gapless(rows), "the capture has no gap (%d samples)" % len(rows))
    program_rows = [r for r in rows if int(r[COL_PHASE]) == 1]
    report["rate_worst_fraction"] = check_counts(program_rows, failures)
    stats = checks.tooltip_error(tooltip, os.path.join(examples, "vmc-xyfz-21-true.json"),
                                 program_rows, os.path.join(work, "record.csv"))
    reduction = 1.0 - stats["rms_compensated_um"] / stats["rms_uncompensated_um"]
    report.update(stats)
    report["reduction"] = reduction
    print("mb2hal, calibrated model: %d samples, RMS %.2f -> %.2f um (%.1f %%), max %.2f -> %.2f um"
          % (stats["samples"], stats["rms_uncompensated_um"], stats["rms_compensated_um"],
             100 * reduction, stats["max_uncompensated_um"], stats["max_compensated_um"]))
    failures.check(reduction >= 0.90, "RMS reduction %.1f %% >= 90 %%" % (100 * reduction))
    with open(os.path.join(work, "report.json"), "w") as f:
        json.dump(report, f, indent=2)
    failures.finish()


if __name__ == "__main__":
    main()
