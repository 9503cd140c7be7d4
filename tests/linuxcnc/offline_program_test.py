#!/usr/bin/python3
"""The offline NC path meets the live one on LinuxCNC 2.9 (test label `linuxcnc`).

The same G-code program runs on the same headless LinuxCNC (the VMC-850 of config/examples, the
shipped HAL snippet, see live_program_test.py) twice per model: once unchanged while volcompd
compensates it live through the LinuxCNC adapter, once compensated offline by `volcomp nc` with
the same model and run with no daemon at all. A realtime sampler records LinuxCNC's commanded
positions and applied external offsets every servo period, the same capture for both. The error
of both runs is measured the same way: the tool tip of the TRUE machine at the recorded axis
positions against the original program's path (contour error, `volcomp-sim nc-run --positions`).
The uncompensated figure is the live run's commanded path itself (the offsets left out). Both
runs start at rest on the program's start point as compensated (live: volcompd's offset there;
offline: the compensated program's first rapid, moved to by MDI before the program).

The program is programs/part.ngc with `G64 P0.0001` after its first line: LinuxCNC's default path
mode (G64 without P) rounds corners by as much as the speed needs, differently for the original
and for the compensated program (whose lines are split into pieces), so both runs are told to keep
within 0.1 um of their programmed paths.

Asserted, for the hand-made example model (vmc-xyfz-21.json) and for the true one: the offline
run applies no external offset; it reaches the live run's accuracy: RMS contour error at most the
live one + 0.5 um and maximum at most the live one + 1 um + 0.1 um. The offline path's own error
is the splitting within `--tolerance` (1 um, its default: the compensated polyline deviates at
most 1 um from the ideal compensated curve, about 0.4 um RMS on a part like this one, docs/nc.md),
plus G64's 0.1 um; the live path's is its latency (the offset is computed from the position a
cycle or two earlier: at 200 mm/s and ~0.03 um/mm of offset gradient, below 0.1 um) and the 0.1 um
count quantum. Both must also be at least 90 % below the uncompensated RMS.

usage: offline_program_test.py VOLCOMPD VOLCOMP VOLCOMP_SIM EXAMPLES_DIR HAL_DIR PROGRAM WORK
Writes WORK/report.json (figures for the README). Exit status 0 when every check holds.
"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "harness"))
import checks  # noqa: E402
import lcnc  # noqa: E402
import live_run  # noqa: E402
import vmc  # noqa: E402

PATH_TOLERANCE_MM = 0.0001  # G64 P: LinuxCNC keeps within this of the programmed path
NC_TOLERANCE_UM = 1.0       # volcomp nc's default --tolerance
RMS_ALLOWANCE_UM = 0.5
MAX_ALLOWANCE_UM = NC_TOLERANCE_UM + 1000 * PATH_TOLERANCE_MM


def tight_program(program, out):
    """`program` with G64 P after its first G21 line (units first: P is in program units)."""
    with open(program) as f:
        lines = f.read().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("G21"))
    lines.insert(at + 1, "G64 P%.4f" % PATH_TOLERANCE_MM)
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    return out


def compensate(volcomp, model, program, out):
    done = subprocess.run([volcomp, "nc", model, program, "--out", out, "--tolerance",
                           "%g" % (NC_TOLERANCE_UM / 1000)], capture_output=True, text=True)
    sys.stdout.write(done.stderr)
    if done.returncode != 0:
        lcnc.die("volcomp nc failed (%d)" % done.returncode)
    return out


def first_rapid(program):
    """The first G0 line's words (the compensated start point), as an MDI command."""
    with open(program) as f:
        return next(line.split("(")[0].strip() for line in f if line.startswith("G0 "))


def contour_error(sim, record, reference, true_model):
    done = subprocess.run([sim, "nc-run", "--positions", record, "--reference", reference,
                           "--model", true_model], capture_output=True, text=True)
    if done.returncode != 0:
        lcnc.die("volcomp-sim nc-run failed: " + done.stderr)
    return json.loads(done.stdout)


def main():
    if len(sys.argv) != 8:
        sys.exit(__doc__)
    volcompd, volcomp, sim, examples, hal_dir, program, work = (
        os.path.abspath(a) for a in sys.argv[1:])
    failures = checks.Failures()
    machine = vmc.machine(work, hal_dir)
    program = tight_program(program, os.path.join(work, "part.ngc"))
    true_model = os.path.join(examples, "vmc-xyfz-21-true.json")
    models = {"vmc-xyfz-21": os.path.join(examples, "vmc-xyfz-21.json"),
              "vmc-xyfz-21-true": true_model}
    offline = {name: compensate(volcomp, model, program, os.path.join(work, name + ".ngc"))
               for name, model in models.items()}
    phases = {}
    with machine:
        capture = live_run.start(machine)
        phase = 0
        for name, model in models.items():
            live = live_run.run(machine, volcompd, model, work, name + "-live", program, phase,
                                failures)
            phase = live + 2
            # Offline, no daemon, from the program's compensated start point (where the live
            # run stood too: at the start point plus the offset volcompd applied there).
            live_run.run_program(machine, offline[name], phase, first_rapid(offline[name]))
            phases[name] = (live, phase)
        checks.set_phase(phase + 1)
        rows = capture.stop()
    failures.check(lcnc.check_gapless(rows), "the capture has no gap (%d samples)" % len(rows))

    report = {"path_tolerance_mm": PATH_TOLERANCE_MM, "nc_tolerance_um": NC_TOLERANCE_UM,
              "rms_allowance_um": RMS_ALLOWANCE_UM, "max_allowance_um": MAX_ALLOWANCE_UM,
              "models": {}}
    for name, (live_phase, offline_phase) in phases.items():
        def selected(p):
            return [r for r in rows if int(r[checks.COL_PHASE]) == p]

        live_rows, offline_rows = selected(live_phase), selected(offline_phase)
        applied = max(abs(r[checks.COL_EOFFSET + k]) for r in offline_rows for k in range(3))
        failures.check(applied < 1e-9, "%s offline: no external offset applied (max %.3g mm)"
                       % (name, applied))
        record = os.path.join(work, name + "%s.csv")
        figures = {
            "uncompensated": contour_error(sim, checks.write_record(
                record % "-uncompensated", live_rows, with_offsets=False), program, true_model),
            "live": contour_error(sim, checks.write_record(record % "-live", live_rows), program,
                                  true_model),
            "offline": contour_error(sim, checks.write_record(record % "-offline", offline_rows),
                                     program, true_model),
        }
        report["models"][name] = figures
        before = figures["uncompensated"]["rms_um"]
        for run in ("uncompensated", "live", "offline"):
            f = figures[run]
            print("%s %s: %d samples over %.0f mm, contour error RMS %.3f um, max %.3f um" % (
                name, run, f["samples"], f["path_mm"], f["rms_um"], f["max_um"]), flush=True)
        live, off = figures["live"], figures["offline"]
        for run, f in (("live", live), ("offline", off)):
            failures.check(f["rms_um"] <= 0.10 * before, "%s %s: RMS %.3f um is at least 90 %% "
                           "below %.3f um" % (name, run, f["rms_um"], before))
        failures.check(off["rms_um"] <= live["rms_um"] + RMS_ALLOWANCE_UM,
                       "%s: offline RMS %.3f um <= live %.3f um + %.1f um" % (
                           name, off["rms_um"], live["rms_um"], RMS_ALLOWANCE_UM))
        failures.check(off["max_um"] <= live["max_um"] + MAX_ALLOWANCE_UM,
                       "%s: offline max %.3f um <= live %.3f um + %.1f um" % (
                           name, off["max_um"], live["max_um"], MAX_ALLOWANCE_UM))
    with open(os.path.join(work, "report.json"), "w") as f:
        json.dump(report, f, indent=2)
    failures.finish()


if __name__ == "__main__":
    main()
