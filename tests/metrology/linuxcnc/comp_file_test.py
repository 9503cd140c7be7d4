#!/usr/bin/python3
"""LinuxCNC loads the COMP_FILEs `volcomp export --format linuxcnc` writes and moves each joint by
the table's amount (test label `linuxcnc`).

For COMP_FILE_TYPE 0 and 1 in turn: export the model's joint tables, start a headless LinuxCNC 2.9
(simulated XYZ machine, perfect servos) whose [JOINT_n] sections name them, home, then move all
three joints to sampled positions, approaching once from below (every joint moving +: LinuxCNC
uses the forward column) and once from above (moving -: the reverse column). At rest, the motor
command minus the commanded joint position (what LinuxCNC adds to the joint) must equal
  - the trim read from the file, interpolated linearly (type 0: nominal - forward/reverse,
    type 1: the columns themselves), and
  - the correction the model asks for, -e(q): for this XYFZ model +EXX, +EYY on the workpiece-side
    X and Y and -EZZ on the tool-side Z, read from `volcomp export --format csv`, per direction.

usage: comp_file_test.py VOLCOMP MODEL.json WORKDIR
The caller holds the LinuxCNC lock (flock /tmp/volcomp-linuxcnc.lock). Needs /usr/bin/python3
with Debian's linuxcnc-uspace (the linuxcnc and hal modules). Exit status 0 when every check holds.
"""
import csv
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "linuxcnc", "harness"))
import lcnc as harness  # noqa: E402  (the LinuxCNC harness: one INI for every LinuxCNC test)

HERE = os.path.dirname(os.path.abspath(__file__))
AXES = "XYZ"
# Travel of the model (config/examples/vmc-xyfz-21.json) and where the test samples it: table nodes,
# points between nodes, and the ends.
TRAVEL = {"X": (0.0, 850.0), "Y": (0.0, 500.0), "Z": (-500.0, 0.0)}
SAMPLES = [
    (37.5, 212.3, -455.0),
    (300.0, 100.0, -250.0),
    (611.1, 333.3, -77.7),
    (849.0, 499.0, -1.0),
    (5.0, 2.5, -498.5),
]
APPROACH_MM = 20.0  # distance of the approach point before each sample
TOLERANCE_MM = 2e-6  # LinuxCNC keeps trims and slopes as float: ~1e-9 mm on these values

failures = []


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message, flush=True)
    if not condition:
        failures.append(message)


def run(cmd, **kw):
    result = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if result.returncode != 0:
        sys.exit("command failed (%d): %s\n%s%s" % (result.returncode, " ".join(cmd),
                                                     result.stdout, result.stderr))
    return result.stdout


def read_comp(path):
    rows = []
    with open(path) as f:
        for line in f:
            rows.append(tuple(float(v) for v in line.split()))
    return rows


def interpolate(xs, ys, x):
    if x <= xs[0]:
        return ys[0]
    if x >= xs[-1]:
        return ys[-1]
    for i in range(len(xs) - 1):
        if xs[i] <= x <= xs[i + 1]:
            t = (x - xs[i]) / (xs[i + 1] - xs[i])
            return ys[i] + t * (ys[i + 1] - ys[i])
    raise ValueError(x)


def file_trim(rows, comp_type, q, forward):
    nominal = [r[0] for r in rows]
    column = [r[1] if forward else r[2] for r in rows]
    if comp_type == 0:
        column = [n - c for n, c in zip(nominal, column)]  # what usrmotLoadComp does
    return interpolate(nominal, column, q)


def model_correction(volcomp, model, axis, work):
    """-e(q) of the axis' positioning component per direction, from the model's own table."""
    name = "E" + axis + axis
    path = os.path.join(work, name + ".csv")
    run([volcomp, "export", model, "--format", "csv", "--component", name, "--out", path,
         "--step", "0.5"])
    with open(path) as f:
        rows = list(csv.DictReader(f))
    positions = [float(r["position_mm"]) for r in rows]
    up = [float(r["value_um"]) * 1e-3 for r in rows]
    down = [float(r.get("value_negative_um") or r["value_um"]) * 1e-3 for r in rows]
    # X and Y carry the workpiece in XYFZ: e = -EKK, correction = +EKK. Z carries the tool.
    sign = 1.0 if axis in "XY" else -1.0
    return positions, [sign * v for v in up], [sign * v for v in down]


def write_ini(path, comp_dir, comp_type):
    """The LinuxCNC harness's configuration (tests/linuxcnc/harness/lcnc.py) with every joint's
    COMP_FILE and COMP_FILE_TYPE, and 30 mm of travel beyond the model's on each side."""
    joint_extra = {j: "COMP_FILE = %s\nCOMP_FILE_TYPE = %d\n"
                      % (os.path.join(comp_dir, "joint%d.comp" % j), comp_type)
                   for j in range(len(AXES))}
    axes = {axis: (TRAVEL[axis][0] - 30, TRAVEL[axis][1] + 30) for axis in AXES}
    machine = harness.Machine(os.path.dirname(path), axes, max_velocity=400, max_acceleration=4000,
                              joint_extra=joint_extra, name="volcomp-comp-file-test")
    with open(path, "w") as f:
        f.write(machine.ini_text())


class LinuxCnc:
    """A headless LinuxCNC in `work`, started and stopped as the notes in docs/export.md say."""

    def __init__(self, work):
        self.work = work
        for name in ("lcnc.ready", "lcnc.stop"):
            if os.path.exists(os.path.join(work, name)):
                os.unlink(os.path.join(work, name))
        self.log = open(os.path.join(work, "lcnc.out"), "w")
        self.proc = subprocess.Popen(["linuxcnc", "-r", "sim.ini"], cwd=work, stdout=self.log,
                                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                     start_new_session=True)
        deadline = time.monotonic() + 60
        while not os.path.exists(os.path.join(work, "lcnc.ready")):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.log.flush()
                sys.exit("LinuxCNC did not come up:\n" +
                         open(os.path.join(work, "lcnc.out")).read())
            time.sleep(0.05)

    def stop(self):
        open(os.path.join(self.work, "lcnc.stop"), "w").close()
        try:
            self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGTERM)
            self.proc.wait(timeout=30)
        self.log.close()


def drive_and_check(comp_type, comp_dir, corrections):
    import hal
    import linuxcnc

    c = linuxcnc.command()
    s = linuxcnc.stat()
    errors = linuxcnc.error_channel()
    component = hal.component("volcomp_comp_test_%d" % comp_type)
    component.ready()

    def wait(predicate, what, timeout=30.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            s.poll()
            if predicate():
                return
            message = errors.poll()
            if message:
                print("  LinuxCNC:", message[1])
            time.sleep(0.005)
        raise TimeoutError("timeout waiting for " + what)

    def set_mode(m):
        s.poll()
        if s.task_mode != m:
            c.mode(m)
            c.wait_complete()
            wait(lambda: s.task_mode == m, "mode %d" % m)

    c.state(linuxcnc.STATE_ESTOP_RESET)
    c.wait_complete()
    c.state(linuxcnc.STATE_ON)
    c.wait_complete()
    wait(lambda: s.task_state == linuxcnc.STATE_ON, "machine on")
    set_mode(linuxcnc.MODE_MANUAL)
    c.teleop_enable(False)
    c.wait_complete()
    c.home(-1)
    c.wait_complete()
    wait(lambda: all(s.homed[:s.joints]), "homing")
    set_mode(linuxcnc.MODE_MDI)

    def move(x, y, z):
        c.mdi("G90 G21 G0 X%.6f Y%.6f Z%.6f" % (x, y, z))
        c.wait_complete()
        wait(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos
             and s.current_vel == 0, "move to %g %g %g" % (x, y, z))
        # inpos holds within a tolerance; the planner's last steps land exactly on the target.
        wait(lambda: all(abs(hal.get_value("joint.%d.pos-cmd" % j) - q) < 1e-9
                         for j, q in enumerate((x, y, z))), "the joints to reach the target")
        # The trim ramps (backlash-filt follows backlash-corr): wait until it has arrived.
        wait(lambda: all(abs(hal.get_value("joint.%d.backlash-filt" % j) -
                             hal.get_value("joint.%d.backlash-corr" % j)) < 1e-12
                         for j in range(3)), "the trims to settle")

    rows = [read_comp(os.path.join(comp_dir, "joint%d.comp" % j)) for j in range(3)]
    checked = 0
    for sample in SAMPLES:
        for forward in (True, False):
            step = -APPROACH_MM if forward else APPROACH_MM
            move(*[q + step for q in sample])
            move(*sample)
            for j, axis in enumerate(AXES):
                commanded = hal.get_value("joint.%d.pos-cmd" % j)
                motor = hal.get_value("joint.%d.motor-pos-cmd" % j)
                moved = motor - commanded
                expected = file_trim(rows[j], comp_type, sample[j], forward)
                positions, up, down = corrections[axis]
                model = interpolate(positions, up if forward else down, sample[j])
                where = "type %d, joint %d (%s) at %g %s" % (
                    comp_type, j, axis, sample[j], "moving +" if forward else "moving -")
                check(abs(commanded - sample[j]) < 1e-6,
                      "%s: commanded joint position %.6f" % (where, commanded))
                check(abs(moved - expected) < TOLERANCE_MM,
                      "%s: LinuxCNC moved the joint by %.7f mm, the file says %.7f" %
                      (where, moved, expected))
                check(abs(moved - model) < 1e-5,
                      "%s: the model's correction is %.7f mm (file grid vs model: %.2g mm)" %
                      (where, model, moved - model))
                checked += 1
    print("type %d: %d joint positions checked" % (comp_type, checked))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    volcomp, model, work = (os.path.abspath(a) for a in sys.argv[1:])
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)
    for name in ("headless.py", "sim.hal", "sim.tbl"):
        shutil.copy(os.path.join(HERE, name), work)
    os.chmod(os.path.join(work, "headless.py"), 0o755)
    os.chmod(work, 0o755)  # readable for the fallback uid rtapi_app runs as
    os.environ.pop("DISPLAY", None)
    if os.getuid() == 0:
        # rtapi_app refuses root without a fallback uid and a socket path that uid can create.
        os.environ.setdefault("RTAPI_UID", "65534")
        os.environ.setdefault("RTAPI_FIFO_PATH", "/tmp/volcomp-rtapi-fifo.%d" % os.getpid())
    corrections = {axis: model_correction(volcomp, model, axis, work) for axis in AXES}
    for comp_type in (0, 1):
        comp_dir = os.path.join(work, "comp%d" % comp_type)
        print(run([volcomp, "export", model, "--format", "linuxcnc", "--out", comp_dir,
                   "--comp-type", str(comp_type)]).splitlines()[0])
        write_ini(os.path.join(work, "sim.ini"), comp_dir, comp_type)
        lcnc = LinuxCnc(work)
        try:
            drive_and_check(comp_type, comp_dir, corrections)
        finally:
            lcnc.stop()
    if failures:
        sys.exit("%d check(s) failed" % len(failures))
    print("all checks passed")


if __name__ == "__main__":
    main()
