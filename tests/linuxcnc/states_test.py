#!/usr/bin/python3
"""volcompd through the LinuxCNC adapter while LinuxCNC changes state under it (test label
`linuxcnc`).

A headless LinuxCNC (the VMC-850's travel, perfect servos, the shipped HAL snippet) stands at a
point where the true example model asks for a clearly visible offset, and volcompd (true model)
compensates. Then, each from a settled, compensating daemon:

  machine off, machine on      LinuxCNC drops count changes while off and zeroes its request at
                               machine-on; volcompd resumes from what is applied, in limiter steps;
  unhome, home                 LinuxCNC holds the applied offset while not homed; volcompd holds
                               its counts and resumes when homed;
  E-stop, reset, on, home      as machine off/on;
  SIGKILL                      the HAL snippet's watchdog clears: LinuxCNC ramps the offsets to
                               zero at its own limits and the joints end on the commanded
                               (nominal) position; a new volcompd takes over (the dead one's HAL
                               component stays, the new one registers beside it) and compensates
                               again;
  SIGTERM                      the offsets ramp out, volcompd exits 0.

Every servo period is recorded. Throughout: no joint ever moves by more than LinuxCNC's own
limits allow (no jump: the machine stands still, so the only motion is the offsets'), the applied
offsets never exceed max_offset nor move faster than OFFSET_AV_RATIO allows, each write of
volcompd moves the counts by at most one limiter step, and LinuxCNC applies no change of the
offsets while it is off or not homed.

usage: states_test.py VOLCOMPD EXAMPLES_DIR HAL_DIR WORK
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "harness"))
import checks  # noqa: E402
import daemon as vd  # noqa: E402
import lcnc  # noqa: E402
import vmc  # noqa: E402
from vmc import CYCLE_MS, MAX_OFFSET, MAX_RATE, MAX_VELOCITY, OFFSET_AV_RATIO  # noqa: E402

# The far corner, where the example machine's offsets are largest. The joints home where they
# stand (immediate homing) and take position 0 there: after homing again the test goes back to
# the corner (phase "return", the only commanded motion after the start).
WHERE = "G0 X780 Y440 Z-420"


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    volcompd, examples, hal_dir, work = (os.path.abspath(a) for a in sys.argv[1:])
    failures = checks.Failures()
    machine = vmc.machine(work, hal_dir)
    transport = vmc.TRANSPORT
    config = os.path.join(work, "volcompd.json")
    vd.write_config(config, os.path.join(examples, "vmc-xyfz-21-true.json"), transport,
                    cycle_ms=CYCLE_MS, max_offset=MAX_OFFSET, max_rate=MAX_RATE)
    log = os.path.join(work, "volcompd.log")
    phases = {}

    def phase(name):
        n = len(phases) + 1
        phases[name] = n
        checks.set_phase(n)
        print("-- %s" % name, flush=True)

    def status():
        return int(machine.get("volcomp-status"))

    def settled():
        s = status()
        return s & vd.STATUS_ACTIVE and not s & vd.STATUS_LIMITED

    def applied():
        return [machine.get("axis.%s.eoffset" % a) for a in "xyz"]

    def wait_settled(what):
        lcnc.wait_for(settled, what, 60, poll=0.01)
        # Settled in the daemon; LinuxCNC follows within its own ramp.
        try:
            lcnc.wait_for(lambda: all(abs(a - o) < 2e-4 for a, o in
                                      zip(applied(), [machine.get("volcomp-%s-offset" % x)
                                                      for x in "xyz"])),
                          what + " (applied by LinuxCNC)", 10, poll=0.01)
        except TimeoutError:
            print(lcnc.halcmd("show", "sig", "volcomp"), flush=True)
            raise

    with machine:
        capture = machine.capture(checks.CAPTURE_PINS)
        machine.on_and_home()
        machine.mdi(WHERE)
        phase("start")
        daemon = vd.Daemon(volcompd, config, log).start()
        wait_settled("volcompd compensating")
        reference = applied()
        failures.check(max(abs(v) for v in reference) > 0.005,
                       "a visible offset at the far corner (%s mm)" % fmt(reference))

        phase("machine off")
        machine.off()
        lcnc.wait_for(lambda: status() & vd.STATUS_DISABLED, "volcompd disabled", 10)
        lcnc.wait_for(lambda: all(c == 0 for c in counts_unchanged_since(machine, 0.1)),
                      "volcompd holding its counts", 10)
        failures.check(all(abs(a - r) < 2e-4 for a, r in zip(applied(), reference)),
                       "machine off: LinuxCNC keeps the applied offsets (%s mm)" % fmt(applied()))
        phase("machine on")
        machine.on_and_home()
        wait_settled("compensating again after machine on")

        phase("unhome")
        held = applied()
        machine.unhome()
        lcnc.wait_for(lambda: status() & vd.STATUS_DISABLED, "volcompd disabled", 10)
        failures.check(all(abs(a - h) < 2e-4 for a, h in zip(applied(), held)),
                       "unhomed: LinuxCNC holds the applied offsets (%s mm)" % fmt(applied()))
        phase("home")
        machine.home()
        lcnc.wait_for(lambda: status() & vd.STATUS_ACTIVE, "compensating again after homing", 30)
        phase("return")
        machine.mdi(WHERE)
        phase("at the corner")
        wait_settled("compensating at the corner again")

        phase("E-stop")
        machine.estop()
        lcnc.wait_for(lambda: status() & vd.STATUS_DISABLED, "volcompd disabled", 10)
        phase("reset")
        machine.on_and_home()
        wait_settled("compensating again after E-stop")

        phase("SIGKILL")
        daemon.kill()
        lcnc.wait_for(lambda: machine.get("volcomp-eoffset-clear"), "the watchdog's clear", 5)
        try:
            lcnc.wait_for(lambda: all(abs(a) < 1e-6 for a in applied()),
                          "LinuxCNC ramping the offsets out", 10)
        except TimeoutError:
            print(lcnc.halcmd("show", "pin", "axis."), lcnc.halcmd("show", "pin", "motion.eoffset"),
                  flush=True)
            raise
        def off_nominal():
            return max(abs(machine.get("joint.%d.pos-fb" % k) -
                           machine.get("axis.%s.pos-cmd" % a)) for k, a in enumerate("xyz"))
        # The joints follow the offset's last servo periods a little later.
        try:
            lcnc.wait_for(lambda: off_nominal() < 1e-6, "the joints on the nominal position", 2)
        except TimeoutError:
            pass  # the check below says by how much
        for k, axis in enumerate("xyz"):
            joint = machine.get("joint.%d.pos-fb" % k)
            cmd = machine.get("axis.%s.pos-cmd" % axis)
            failures.check(abs(joint - cmd) < 1e-6, "after SIGKILL joint %d stands on the "
                           "nominal position (%.6f vs %.6f)" % (k, joint, cmd))
        phase("restart")
        daemon = vd.Daemon(volcompd, config, log).start()
        lcnc.wait_for(lambda: "volcomp-2" in vd.component_names(), "the new component", 30)
        wait_settled("the restarted volcompd compensating")
        failures.check(all(abs(a - r) < 5e-4 for a, r in zip(applied(), reference)),
                       "the restarted volcompd applies the same offsets (%s vs %s mm)"
                       % (fmt(applied()), fmt(reference)))
        failures.check("left by a volcompd that is gone" in daemon.text(),
                       "the restarted volcompd says it replaced a dead predecessor")

        phase("SIGTERM")
        rc = daemon.terminate()
        failures.check(rc == 0, "volcompd exits 0 after SIGTERM (got %s)" % rc)
        lcnc.wait_for(lambda: all(abs(a) < 1e-6 for a in applied()), "offsets at zero", 10)
        phase("end")
        rows = capture.stop()

    failures.check(lcnc.check_gapless(rows), "the capture has no gap (%d samples)" % len(rows))
    # From the first phase on nothing moves but the offsets (before it the machine homed and went
    # to the corner). (The capture starts before machine-on: loading the sampler later has been
    # seen to leave task ignoring state commands in this LinuxCNC.)
    rows = [r for r in rows if int(r[checks.COL_PHASE]) >= 1]
    limits = vmc.limits()
    checks.check_rates(rows, limits, failures)
    check_no_jump(rows, phases, failures)
    check_frozen_while_not_accepting(rows, failures)
    failures.finish()


# The joints as recorded (the sampler takes at most 20 channels, all used by the common columns;
# with perfect servos the joints' commanded positions are where they stand).
COL_FB = checks.COL_JOINT


def fmt(values):
    return ", ".join("%.4f" % v for v in values)


def counts_unchanged_since(machine, seconds):
    """Count changes on the three axes across `seconds` (0 = the daemon holds them)."""
    import time
    before = [int(machine.get("volcomp-%s-eoffset-counts" % a)) for a in "xyz"]
    deadline = time.monotonic() + seconds
    lcnc.wait_for(lambda: time.monotonic() >= deadline, "a pause", seconds + 1)
    return [int(machine.get("volcomp-%s-eoffset-counts" % a)) - b
            for a, b in zip("xyz", before)]


def check_no_jump(rows, phases, failures):
    """Nothing is commanded to move (but the G0 back to the corner after homing): each joint moves
    by at most what the offsets may do in one servo period (OFFSET_AV_RATIO * MAX_VELOCITY), never
    a jump."""
    limit = OFFSET_AV_RATIO * MAX_VELOCITY * 0.001 * 1.001 + 1e-9
    worst = 0.0
    for prev, row in zip(rows, rows[1:]):
        if not (row[checks.COL_HOMED] and prev[checks.COL_HOMED]):
            continue  # homing sets the coordinates where the joints stand: nothing moves
        if phases["return"] in (int(prev[checks.COL_PHASE]), int(row[checks.COL_PHASE])):
            continue  # the G0 back to the corner
        for k in range(3):
            worst = max(worst, abs(row[COL_FB + k] - prev[COL_FB + k]))
    failures.check(worst <= limit, "no joint jumps: largest move per servo period %.3g mm "
                   "(OFFSET_AV_RATIO allows %.3g)" % (worst, limit))


def check_frozen_while_not_accepting(rows, failures):
    """LinuxCNC applies no offset change while the machine is off or not homed."""
    moved = 0
    samples = 0
    for prev, row in zip(rows, rows[1:]):
        if row[checks.COL_MACHINE_ON] and row[checks.COL_HOMED]:
            continue
        if not (prev[checks.COL_MACHINE_ON] == row[checks.COL_MACHINE_ON] == 0 or
                prev[checks.COL_HOMED] == row[checks.COL_HOMED] == 0):
            continue
        samples += 1
        if any(abs(row[checks.COL_REQUEST + k] - prev[checks.COL_REQUEST + k]) > 1e-12
               for k in range(3)):
            moved += 1
    failures.check(samples > 0 and moved == 0,
                   "while off or not homed the requested offsets never change (%d of %d servo "
                   "periods)" % (moved, samples))


if __name__ == "__main__":
    main()
