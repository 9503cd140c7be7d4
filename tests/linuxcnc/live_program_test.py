#!/usr/bin/python3
"""volcompd compensates a real G-code program on LinuxCNC 2.9 through the LinuxCNC adapter
(test label `linuxcnc`).

A headless LinuxCNC simulates the VMC-850 of config/examples (XYZ, its travel, perfect servos)
with the shipped HAL snippet (config/linuxcnc/volcomp.hal) and OFFSET_AV_RATIO; volcompd runs
beside it as systemd would run it (transport "linuxcnc"). Twice, with LinuxCNC running throughout:
volcompd with the calibrated example model (vmc-xyfz-21.json, which differs from the truth as a
real calibration does), then with the true one (vmc-xyfz-21-true.json); each time LinuxCNC runs
programs/part.ngc while volcompd compensates, and volcompd is then stopped with SIGTERM.

Every servo period a realtime sampler records LinuxCNC's commanded positions (axis.L.pos-cmd),
the external offsets it applies (axis.L.eoffset), the joints, the counts volcompd writes and its
heartbeat. The true tool-tip error along the path (volcomp-tooltip-error with the TRUE model)
must drop by at least 90 % RMS with the calibrated model and 95 % with the true one. Throughout:
every write of volcompd moves the counts by at most one limiter step, the applied offsets never
move faster than OFFSET_AV_RATIO allows nor exceed max_offset, the joints are always the commanded
positions plus the applied offsets; after SIGTERM volcompd exits 0 with the offsets ramped to zero
and the joints back on the commanded (nominal) positions.

usage: live_program_test.py VOLCOMPD TOOLTIP_ERROR EXAMPLES_DIR HAL_DIR PROGRAM WORK
Writes WORK/report.json (figures for the README). Exit status 0 when every check holds.
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "harness"))
import daemon as vd  # noqa: E402
import lcnc  # noqa: E402
import vmc  # noqa: E402
from vmc import CYCLE_MS, MAX_OFFSET, MAX_RATE, OFFSET_AV_RATIO  # noqa: E402
import checks  # noqa: E402



def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    volcompd, tooltip, examples, hal_dir, program, work = (os.path.abspath(a) for a in sys.argv[1:])
    failures = checks.Failures()
    machine = vmc.machine(work, hal_dir)
    report = {"cycle_period_ms": CYCLE_MS, "max_rate_mm_s": MAX_RATE, "max_offset_mm": MAX_OFFSET,
              "offset_av_ratio": OFFSET_AV_RATIO, "runs": {}}
    transport = vmc.TRANSPORT
    with machine:
        print("LinuxCNC up in %.1f s" % machine.startup_s, flush=True)
        capture = machine.capture(checks.CAPTURE_PINS)
        machine.on_and_home()
        machine.mdi("G21 G90 G0 X80 Y60 Z-40")
        phase = 0
        for model in ("vmc-xyfz-21.json", "vmc-xyfz-21-true.json"):
            name = model[:-5]
            config = os.path.join(work, name + ".volcompd.json")
            vd.write_config(config, os.path.join(examples, model), transport, cycle_ms=CYCLE_MS,
                            max_offset=MAX_OFFSET, max_rate=MAX_RATE)
            daemon = vd.Daemon(volcompd, config, os.path.join(work, name + ".log")).start()
            phase += 1
            checks.set_phase(phase)  # daemon starting, settling
            lcnc.wait_for(lambda: "volcomp" in vd.component_names(), "volcompd's component", 30)
            vd.wait_status(machine, "volcomp",
                           lambda s: s & vd.STATUS_ACTIVE and not s & vd.STATUS_LIMITED,
                           "volcompd active and settled")
            phase += 1
            checks.set_phase(phase)  # the program runs
            program_phase = phase
            # (LinuxCNC 2.9 stalls a program started again right after it ended; an MDI move
            # in between avoids that.)
            machine.mdi("G0 X80 Y60 Z-40")
            machine.run_program(program)
            machine.wait_program()
            phase += 1
            checks.set_phase(phase)  # SIGTERM
            rc = daemon.terminate()
            failures.check(rc == 0, "%s: volcompd exits 0 after SIGTERM (got %s)" % (name, rc))
            failures.check("stopping -> finished" in daemon.text(),
                           "%s: volcompd ramped out and finished" % name)
            # The watchdog's clear follows the silence; nothing may move after the ramp.
            lcnc.wait_for(lambda: machine.get("volcomp-eoffset-clear"), "the watchdog's clear", 5)
            for k, axis in enumerate("xyz"):
                eo = machine.get("axis.%s.eoffset" % axis)
                failures.check(abs(eo) < 1e-6, "%s: after SIGTERM the %s offset is zero (%.3g mm)"
                               % (name, axis.upper(), eo))
                joint = machine.get("joint.%d.pos-fb" % k)
                cmd = machine.get("axis.%s.pos-cmd" % axis)
                failures.check(abs(joint - cmd) < 1e-6,
                               "%s: after SIGTERM joint %d is on the nominal position (%.6f vs "
                               "%.6f)" % (name, k, joint, cmd))
            report["runs"][name] = {"program_phase": program_phase}
        phase += 1
        checks.set_phase(phase)
        rows = capture.stop()
    failures.check(lcnc.check_gapless(rows), "the capture has no gap (%d samples)" % len(rows))

    limits = vmc.limits()
    report["rates"] = checks.check_rates(rows, limits, failures)
    for name, run in report["runs"].items():
        selected = [r for r in rows if int(r[checks.COL_PHASE]) == run["program_phase"]]
        stats = checks.tooltip_error(tooltip, os.path.join(examples, "vmc-xyfz-21-true.json"),
                                     selected, os.path.join(work, name + ".record.csv"))
        reduction = 1.0 - stats["rms_compensated_um"] / stats["rms_uncompensated_um"]
        run.update(stats)
        run["reduction"] = reduction
        target = 0.95 if name.endswith("-true") else 0.90
        print("%s: %d samples, RMS %.2f -> %.2f um (%.1f %%), max %.2f -> %.2f um" % (
            name, stats["samples"], stats["rms_uncompensated_um"], stats["rms_compensated_um"],
            100 * reduction, stats["max_uncompensated_um"], stats["max_compensated_um"]))
        failures.check(reduction >= target, "%s: RMS reduction %.1f %% >= %.0f %%"
                       % (name, 100 * reduction, 100 * target))
    with open(os.path.join(work, "report.json"), "w") as f:
        json.dump(report, f, indent=2)
    failures.finish()


if __name__ == "__main__":
    main()
