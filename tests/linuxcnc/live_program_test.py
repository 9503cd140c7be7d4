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
import lcnc  # noqa: E402
import live_run  # noqa: E402
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
    with machine:
        capture = live_run.start(machine)
        phase = 0
        for model in ("vmc-xyfz-21.json", "vmc-xyfz-21-true.json"):
            name = model[:-5]
            program_phase = live_run.run(machine, volcompd, os.path.join(examples, model), work,
                                         name, program, phase, failures)
            report["runs"][name] = {"program_phase": program_phase}
            phase = program_phase + 1
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
