"""A headless LinuxCNC 2.9 for tests (Debian's linuxcnc-uspace): a simulated XYZ machine with
perfect servos, started and stopped per test, driven through the `linuxcnc` python module, read
and recorded through HAL.

Used by the tests of label `linuxcnc` (tests/linuxcnc, tests/metrology/linuxcnc). LinuxCNC allows
one instance per machine: the caller holds the machine-wide lock for the whole run
(`flock /tmp/volcomp-linuxcnc.lock`, which CTest does). Needs /usr/bin/python3 (the linuxcnc and
hal modules exist only for Debian's python). As root, rtapi_app needs a non-zero fallback uid and
a socket path that uid can create (RTAPI_UID, RTAPI_FIFO_PATH): environment() sets both.

    machine = Machine(work, axes={"X": (0, 850), ...}, extra_ini=..., hal_files=[...])
    machine.start()                      # returns once the display (headless.py) is up
    machine.on_and_home(); machine.mdi("G0 X10"); machine.run_program(path); ...
    capture = machine.capture(["axis.x.pos-cmd", ...]); ...; rows = capture.stop()
    machine.stop()
"""
import os
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
LOCK_FILE = "/tmp/volcomp-linuxcnc.lock"
# The headless "display" the metrology tests' LinuxCNC uses too.
HEADLESS = os.path.join(HERE, "..", "..", "metrology", "linuxcnc", "headless.py")


def environment():
    """Environment for LinuxCNC and its tools: no X display; as root a fallback uid for rtapi_app."""
    os.environ.pop("DISPLAY", None)
    if os.getuid() == 0:
        os.environ.setdefault("RTAPI_UID", "65534")
        os.environ.setdefault("RTAPI_FIFO_PATH", "/tmp/volcomp-rtapi-fifo.%d" % os.getpid())


def wait_for(predicate, what, timeout=30.0, poll=0.005):
    """Polls `predicate` until it is true; raises TimeoutError naming `what`."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise TimeoutError("timeout (%.0f s) waiting for %s" % (timeout, what))
        time.sleep(poll)


def halcmd(*args, check=True):
    """Runs halcmd in its own session (children of a process that blocks SIGTERM could not be
    unloaded) and returns its stdout."""
    result = subprocess.run(["halcmd"] + [str(a) for a in args], capture_output=True, text=True,
                            start_new_session=True)
    if check and result.returncode != 0:
        raise RuntimeError("halcmd %s failed (%d): %s%s" % (" ".join(map(str, args)),
                                                             result.returncode, result.stdout,
                                                             result.stderr))
    return result.stdout


SIM_HAL = """# Simulated machine: motion controller, trivial kinematics, perfect servos (motor-pos-cmd looped
# back to motor-pos-fb), E-stop and tool-change loops closed.
loadrt [KINS]KINEMATICS
loadrt [EMCMOT]EMCMOT servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS
addf motion-command-handler servo-thread
addf motion-controller      servo-thread
net j0pos joint.0.motor-pos-cmd => joint.0.motor-pos-fb
net j1pos joint.1.motor-pos-cmd => joint.1.motor-pos-fb
net j2pos joint.2.motor-pos-cmd => joint.2.motor-pos-fb
net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in
net tool-prep-loop iocontrol.0.tool-prepare => iocontrol.0.tool-prepared
net tool-change-loop iocontrol.0.tool-change => iocontrol.0.tool-changed
"""


class Machine:
    """One headless LinuxCNC in `work` (created empty)."""

    def __init__(self, work, axes, max_velocity=50.0, max_acceleration=500.0,
                 offset_av_ratio=None, axis_extra=None, joint_extra=None, hal_files=(),
                 name="volcomp-test"):
        self.work = os.path.abspath(work)
        self.axes = axes
        self.max_velocity = max_velocity
        self.max_acceleration = max_acceleration
        self.offset_av_ratio = offset_av_ratio
        self.axis_extra = axis_extra or {}
        self.joint_extra = joint_extra or {}
        self.hal_files = list(hal_files)
        self.name = name
        self.proc = None
        self._c = self._s = self._e = None
        self._probe = None

    # -- configuration --------------------------------------------------------------------------
    def ini_text(self):
        sections = []
        for j, axis in enumerate("XYZ"):
            low, high = self.axes[axis]
            ratio = ("OFFSET_AV_RATIO = %g\n" % self.offset_av_ratio
                     if self.offset_av_ratio else "")
            sections.append("[AXIS_%s]\nMAX_VELOCITY = %g\nMAX_ACCELERATION = %g\nMIN_LIMIT = %g\n"
                            "MAX_LIMIT = %g\n%s%s\n" % (axis, self.max_velocity,
                                                        self.max_acceleration, low, high, ratio,
                                                        self.axis_extra.get(axis, "")))
            sections.append("[JOINT_%d]\nTYPE = LINEAR\nMAX_VELOCITY = %g\nMAX_ACCELERATION = %g\n"
                            "MIN_LIMIT = %g\nMAX_LIMIT = %g\nHOME_SEQUENCE = 0\n%s\n"
                            % (j, self.max_velocity, self.max_acceleration, low, high,
                               self.joint_extra.get(j, "")))
        halfiles = "".join("HALFILE = %s\n" % f for f in ["sim.hal"] + self.hal_files)
        return """[EMC]
VERSION = 1.1
MACHINE = %s

[DISPLAY]
DISPLAY = ./headless.py

[TASK]
TASK = milltask
CYCLE_TIME = 0.001

[RS274NGC]
PARAMETER_FILE = sim.var

[EMCMOT]
EMCMOT = motmod
COMM_TIMEOUT = 4.0
SERVO_PERIOD = 1000000

[EMCIO]
EMCIO = io
CYCLE_TIME = 0.100
TOOL_TABLE = sim.tbl

[HAL]
%s
[TRAJ]
COORDINATES = XYZ
LINEAR_UNITS = mm
ANGULAR_UNITS = degree
DEFAULT_LINEAR_VELOCITY = %g
MAX_LINEAR_VELOCITY = %g

[KINS]
JOINTS = 3
KINEMATICS = trivkins coordinates=XYZ

""" % (self.name, halfiles, self.max_velocity, self.max_velocity * 2) + "".join(sections)

    def prepare(self):
        """Writes the configuration into `work` (created, or emptied of a previous run's files)."""
        os.makedirs(self.work, exist_ok=True)
        os.chmod(self.work, 0o755)  # readable for the fallback uid rtapi_app runs as
        shutil.copy(HEADLESS, self.work)
        os.chmod(os.path.join(self.work, "headless.py"), 0o755)
        with open(os.path.join(self.work, "sim.hal"), "w") as f:
            f.write(SIM_HAL)
        with open(os.path.join(self.work, "sim.tbl"), "w") as f:
            f.write("T1 P1 D0 Z0 ;\n")
        with open(os.path.join(self.work, "sim.ini"), "w") as f:
            f.write(self.ini_text())
        for name in ("lcnc.ready", "lcnc.stop"):
            if os.path.exists(os.path.join(self.work, name)):
                os.unlink(os.path.join(self.work, name))

    # -- life cycle -----------------------------------------------------------------------------
    def start(self, timeout=60.0):
        environment()
        self.prepare()
        self.log = open(os.path.join(self.work, "lcnc.out"), "w")
        t0 = time.monotonic()
        self.proc = subprocess.Popen(["linuxcnc", "-r", "sim.ini"], cwd=self.work, stdout=self.log,
                                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                     start_new_session=True)
        ready = os.path.join(self.work, "lcnc.ready")
        deadline = time.monotonic() + timeout
        while not os.path.exists(ready):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.log.flush()
                raise RuntimeError("LinuxCNC did not come up:\n" +
                                   open(os.path.join(self.work, "lcnc.out")).read())
            time.sleep(0.05)
        self.startup_s = time.monotonic() - t0
        import hal
        import linuxcnc
        self._c = linuxcnc.command()
        self._s = linuxcnc.stat()
        self._e = linuxcnc.error_channel()
        # hal.get_value() needs a component of this process.
        self._probe = hal.component("volcomp-test-probe-%d" % os.getpid())
        self._probe.ready()
        return self

    def stop(self, timeout=60.0):
        """Orderly stop: the display exits and LinuxCNC shuts everything down."""
        if self.proc is None:
            return
        if self._probe is not None:
            self._probe.exit()
            self._probe = None
        open(os.path.join(self.work, "lcnc.stop"), "w").close()
        try:
            self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGTERM)
            self.proc.wait(timeout=30)
        self.log.close()
        self.proc = None

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()

    # -- NML ------------------------------------------------------------------------------------
    @property
    def stat(self):
        self._s.poll()
        return self._s

    def errors(self):
        messages = []
        while True:
            m = self._e.poll()
            if not m:
                return messages
            messages.append(m[1])

    def wait(self, predicate, what, timeout=30.0):
        def check():
            self._s.poll()
            return predicate(self._s)
        return wait_for(check, what, timeout)

    def mode(self, m):
        if self.stat.task_mode != m:
            self._c.mode(m)
            self._c.wait_complete()
            self.wait(lambda s: s.task_mode == m, "mode %d" % m)

    def _state(self, state, predicate, what, timeout=30.0):
        """Sends a task state command until `predicate(stat)` holds. Under load task has been seen
        to drop a state command sent soon after start-up or after another one (no error message,
        the state just stays): it is sent again every 2 s."""
        deadline = time.monotonic() + timeout
        while True:
            self._c.state(state)
            self._c.wait_complete()
            try:
                return self.wait(predicate, what, min(2.0, max(0.0, deadline - time.monotonic())))
            except TimeoutError as e:
                if time.monotonic() >= deadline:
                    st = self.stat
                    raise TimeoutError("%s (task_state %d, enabled %d, task_mode %d, exec_state %d,"
                                       " interp_state %d, errors %s)" % (
                                           e, st.task_state, st.enabled, st.task_mode,
                                           st.exec_state, st.interp_state, self.errors())) from None

    def on(self):
        import linuxcnc
        if self.stat.task_state == linuxcnc.STATE_ESTOP:
            self._state(linuxcnc.STATE_ESTOP_RESET, lambda s: s.task_state != linuxcnc.STATE_ESTOP,
                        "E-stop reset")
        self._state(linuxcnc.STATE_ON, lambda s: s.task_state == linuxcnc.STATE_ON, "machine on")

    def off(self):
        import linuxcnc
        # Task reports a machine switched off as STATE_ESTOP_RESET (2.9).
        self._state(linuxcnc.STATE_OFF,
                    lambda s: s.task_state != linuxcnc.STATE_ON and not s.enabled, "machine off")

    def estop(self):
        import linuxcnc
        self._state(linuxcnc.STATE_ESTOP, lambda s: s.task_state == linuxcnc.STATE_ESTOP, "E-stop")

    def home(self):
        import linuxcnc
        self.mode(linuxcnc.MODE_MANUAL)
        self._c.teleop_enable(False)
        self._c.wait_complete()
        self._c.home(-1)
        self._c.wait_complete()
        self.wait(lambda s: all(s.homed[:s.joints]), "homing")

    def unhome(self):
        import linuxcnc
        self.mode(linuxcnc.MODE_MANUAL)
        self._c.teleop_enable(False)
        self._c.wait_complete()
        self._c.unhome(-1)
        self._c.wait_complete()
        self.wait(lambda s: not any(s.homed[:s.joints]), "unhoming")

    def on_and_home(self):
        self.on()
        if not all(self.stat.homed[:self.stat.joints]):
            self.home()

    def mdi(self, command, timeout=60.0):
        """Runs one MDI line and waits until motion has stopped."""
        import linuxcnc
        self.mode(linuxcnc.MODE_MDI)
        self._c.mdi(command)
        self._c.wait_complete()

        def done(s):
            return (s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos and
                    s.current_vel == 0)
        try:
            self.wait(done, "MDI " + command, timeout)
        except TimeoutError as e:
            s = self.stat
            raise TimeoutError("%s (task_state %d, task_mode %d, interp_state %d, queue %d, inpos "
                               "%d, current_vel %g, position %s, errors %s)" % (
                                   e, s.task_state, s.task_mode, s.interp_state, s.queue, s.inpos,
                                   s.current_vel, s.position[:3], self.errors())) from None

    def run_program(self, path):
        """Starts a program (absolute path) in AUTO mode; does not wait for its end."""
        import linuxcnc
        self.mode(linuxcnc.MODE_AUTO)
        self._c.program_open(path)
        self._c.wait_complete()
        self._c.auto(linuxcnc.AUTO_RUN, 0)  # no wait_complete(): it blocks for its timeout
        self.wait(lambda s: s.interp_state != linuxcnc.INTERP_IDLE, "program start", 10)

    def program_done(self):
        import linuxcnc
        s = self.stat
        return s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0

    def wait_program(self, timeout=300.0):
        return wait_for(self.program_done, "the program to end", timeout, poll=0.02)

    # -- HAL ------------------------------------------------------------------------------------
    @staticmethod
    def get(name):
        import hal
        return hal.get_value(name)

    def capture(self, pins, name="volcomp-capture", depth=20000):
        """Records `pins` every servo period (realtime sampler + halsampler) until stop()."""
        return Capture(self.work, pins, name, depth)


_TYPE_CODES = {"float": "f", "bit": "b", "s32": "s", "u32": "u"}


def hal_type(name):
    """HAL type of a pin or signal ("float", "bit", "s32", "u32")."""
    for command in ("ptype", "stype"):
        out = halcmd(command, name, check=False).strip()
        if out in _TYPE_CODES:
            return out
    raise RuntimeError("no HAL pin or signal named " + name)


def signal_of(pin):
    """The signal a pin is linked to, the name itself when it is a signal, else None."""
    for line in halcmd("show", "pin", pin).splitlines():
        parts = line.split()
        if pin in parts:
            i = parts.index(pin)
            if i + 2 < len(parts) and parts[i + 1] in ("==>", "<==", "<=>"):
                return parts[i + 2]
            return None
    if halcmd("stype", pin, check=False).strip() in _TYPE_CODES:
        return pin
    raise RuntimeError("no HAL pin or signal named " + pin)


class Capture:
    """A realtime `sampler` on the servo thread fed by `pins` (pins or signals), read by
    `halsampler -t` into a file. One per LinuxCNC start (its component stays loaded)."""

    def __init__(self, work, pins, name, depth):
        self.pins = list(pins)
        self.path = os.path.join(work, name + ".txt")
        types = [hal_type(p) for p in self.pins]
        halcmd("loadrt", "sampler", "depth=%d" % depth,
               "cfg=%s" % "".join(_TYPE_CODES[t] for t in types))
        for i, pin in enumerate(self.pins):
            signal_name = signal_of(pin)
            if signal_name is None:
                signal_name = "%s-%d" % (name, i)
                halcmd("net", signal_name, pin)
            halcmd("net", signal_name, "sampler.0.pin.%d" % i)
        halcmd("addf", "sampler.0", "servo-thread")
        self.out = open(self.path, "w")
        self.proc = subprocess.Popen(["halsampler", "-t"], stdout=self.out,
                                     stderr=subprocess.DEVNULL, start_new_session=True)

    def stop(self):
        """Stops recording once halsampler has drained the FIFO; returns the rows as lists of
        floats (sample number first)."""
        halcmd("setp", "sampler.0.enable", "0")
        wait_for(lambda: int(Machine.get("sampler.0.curr-depth")) == 0, "the sampler to drain", 10)
        self.proc.send_signal(signal.SIGTERM)
        self.proc.wait(timeout=10)
        self.out.close()
        halcmd("delf", "sampler.0", "servo-thread", check=False)
        rows = []
        with open(self.path) as f:
            for line in f:
                parts = line.split()
                if len(parts) == len(self.pins) + 1:
                    rows.append([float(v) for v in parts])
        return rows


def check_gapless(rows):
    """True when the sample numbers of a capture are consecutive (no overrun of the FIFO)."""
    return all(int(b[0]) - int(a[0]) == 1 for a, b in zip(rows, rows[1:]))


def die(message):
    print("FAIL " + message, flush=True)
    sys.exit(1)
