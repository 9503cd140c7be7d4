"""One compensated program run on LinuxCNC with volcompd beside it (the live adapter), shared by the
tests that run programs: start volcompd with a model, wait until it is active and settled, run the
program, SIGTERM, and check that the offsets ramped out and the joints are back on the nominal
positions. The samples of each step are marked with their phase (checks.set_phase)."""
import os

import checks
import daemon as vd
import lcnc
import vmc


def start(machine):
    """On a started LinuxCNC: the capture of checks.CAPTURE_PINS running, the machine on, homed,
    metric, absolute, at the programs' start point. Returns the capture."""
    print("LinuxCNC up in %.1f s" % machine.startup_s, flush=True)
    capture = machine.capture(checks.CAPTURE_PINS)
    machine.on_and_home()
    machine.mdi("G21 G90 G0 X80 Y60 Z-40")
    return capture


def run(machine, volcompd, model, work, name, program, phase, failures):
    """Runs `program` (absolute path) while volcompd compensates with `model`; the phases
    phase+1 (daemon starting), phase+2 (the program), phase+3 (SIGTERM) are used. Returns the
    program's phase."""
    config = os.path.join(work, name + ".volcompd.json")
    vd.write_config(config, model, vmc.TRANSPORT, cycle_ms=vmc.CYCLE_MS,
                    max_offset=vmc.MAX_OFFSET, max_rate=vmc.MAX_RATE)
    daemon = vd.Daemon(volcompd, config, os.path.join(work, name + ".log")).start()
    checks.set_phase(phase + 1)  # daemon starting, settling
    lcnc.wait_for(lambda: "volcomp" in vd.component_names(), "volcompd's component", 30)
    vd.wait_status(machine, "volcomp",
                   lambda s: s & vd.STATUS_ACTIVE and not s & vd.STATUS_LIMITED,
                   "volcompd active and settled")
    run_program(machine, program, phase + 2)
    checks.set_phase(phase + 3)  # SIGTERM
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
                       "%s: after SIGTERM joint %d is on the nominal position (%.6f vs %.6f)"
                       % (name, k, joint, cmd))
    return phase + 2


def run_program(machine, program, phase, start="G0 X80 Y60 Z-40"):
    """Moves to `start` by MDI, then marks the samples with `phase` and runs `program` to its end.
    (LinuxCNC 2.9 stalls a program started again right after it ended; the MDI move in between
    avoids that.)"""
    machine.mdi(start)
    checks.set_phase(phase)
    machine.run_program(program)
    machine.wait_program()
