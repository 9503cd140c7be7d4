"""What the LinuxCNC tests record every servo period and the checks they make on it."""
import json
import subprocess
import sys

import lcnc

# The sampler's columns (after the sample number): signals of the shipped HAL snippet where one
# carries the value, plus the test's own (test.hal).
CAPTURE_PINS = (
    ["volcomp-%s-pos-cmd" % a for a in "xyz"] +              # 1..3   commanded positions
    ["volcomp-%s-eoffset" % a for a in "xyz"] +              # 4..6   applied external offsets
    ["joint.%d.pos-cmd" % j for j in range(3)] +             # 7..9   joints (commanded)
    ["volcomp-%s-eoffset-counts" % a for a in "xyz"] +       # 10..12 counts volcompd writes
    ["volcomp-heartbeat", "volcomp-machine-on", "volcomp-homed", "test-phase"] +  # 13..16
    ["volcomp-%s-eoffset-request" % a for a in "xyz"] +      # 17..19 requested offsets
    ["volcomp-status"]                                       # 20
)
COL_POS = 1
COL_EOFFSET = 4
COL_JOINT = 7
COL_COUNTS = 10
COL_HEARTBEAT = 13
COL_MACHINE_ON = 14
COL_HOMED = 15
COL_PHASE = 16
COL_REQUEST = 17
COL_STATUS = 20

TEST_HAL = """# Signals the test records besides the shipped snippet's: volcompd's heartbeat, status and
# offsets after its limiter (its optional outputs) and the test's phase marker.
newsig volcomp-heartbeat s32
newsig volcomp-status s32
newsig volcomp-x-offset float
newsig volcomp-y-offset float
newsig volcomp-z-offset float
newsig test-phase s32
# This machine is shared and loaded: volcompd (not real-time here) can stall for more than the
# snippet's 0.1 s, after which the watchdog would clear the offsets.
setp volcomp-alive.width 0.5
"""


def write_test_hal(path):
    with open(path, "w") as f:
        f.write(TEST_HAL)


def set_phase(n):
    """Marks the samples from now on with phase `n`."""
    lcnc.halcmd("sets", "test-phase", n)


class Failures:
    def __init__(self):
        self.failed = []

    def check(self, condition, message):
        print(("ok   " if condition else "FAIL ") + message, flush=True)
        if not condition:
            self.failed.append(message)
        return condition

    def finish(self):
        if self.failed:
            sys.exit("%d check(s) failed" % len(self.failed))
        print("all checks passed")


class Limits:
    def __init__(self, max_offset, max_rate, cycle_ms, counts_per_mm, lcnc_rate,
                 servo_s=0.001):
        self.max_offset = max_offset
        self.max_rate = max_rate
        self.cycle_ms = cycle_ms
        self.counts_per_mm = counts_per_mm
        self.lcnc_rate = lcnc_rate
        self.servo_s = servo_s

    @property
    def step_counts(self):
        """One limiter step in counts: max_rate * period."""
        return self.max_rate * self.cycle_ms * 1e-3 * self.counts_per_mm


def check_rates(rows, limits, failures, label=""):
    """Per write, the counts move by at most one limiter step (plus a count of rounding); the
    applied offsets stay within max_offset and never move faster than LinuxCNC's own limit; the
    joints are the commanded positions plus the applied offsets. Returns figures."""
    worst_step = 0.0  # largest counts change per write, in limiter steps
    worst_applied_rate = 0.0
    worst_offset = 0.0
    worst_joint = 0.0
    writes = 0
    bad_step = None
    for i, (prev, row) in enumerate(zip(rows, rows[1:])):
        writes_between = (int(row[COL_HEARTBEAT]) - int(prev[COL_HEARTBEAT])) % 65536
        same_daemon = 0 <= writes_between < 1000 and int(row[COL_PHASE]) == int(prev[COL_PHASE])
        # At machine-on LinuxCNC zeroes the external offsets and takes what was applied into the
        # position (nothing moves; the joints' record shows it): not a move of the offset.
        machine_on = prev[COL_MACHINE_ON] == 0 and row[COL_MACHINE_ON] != 0
        for k in range(3):
            eo = row[COL_EOFFSET + k]
            worst_offset = max(worst_offset, abs(eo))
            if not machine_on:
                rate = abs(eo - prev[COL_EOFFSET + k]) / limits.servo_s
                worst_applied_rate = max(worst_applied_rate, rate)
            # The joints lag the planned positions by a couple of servo periods while they move:
            # compare where commanded position and offset have been still for a while.
            # (Not while homing: it sets the joints' coordinates before the commanded ones.)
            if i >= 8 and row[COL_HOMED] and all(rows[i + 1 - j][COL_POS + k] == row[COL_POS + k] and
                              rows[i + 1 - j][COL_EOFFSET + k] == eo for j in range(1, 8)):
                worst_joint = max(worst_joint, abs(row[COL_JOINT + k] - row[COL_POS + k] - eo))
            if not same_daemon:
                continue
            change = abs(int(row[COL_COUNTS + k]) - int(prev[COL_COUNTS + k]))
            if change == 0:
                continue
            # volcompd sets the counts before the heartbeat, and the servo thread may sample
            # between the two: a sample can show a write's counts before its heartbeat.
            allowed = max(writes_between, 1) * (limits.step_counts + 1.0)
            if writes_between > 0:
                worst_step = max(worst_step, change / (writes_between * limits.step_counts))
            if change > allowed and bad_step is None:
                bad_step = "sample %d axis %d: counts moved %d in %d write(s)" % (
                    int(row[0]), k, change, writes_between)
        writes += writes_between if same_daemon else 0
    failures.check(bad_step is None, "%severy write moves the counts by at most one limiter step "
                   "(worst %.3f steps)%s" % (label, worst_step, "" if bad_step is None
                                              else ": " + bad_step))
    failures.check(worst_offset <= limits.max_offset + 1e-9,
                   "%sapplied offsets within max_offset (%.4f mm)" % (label, worst_offset))
    failures.check(worst_applied_rate <= limits.lcnc_rate * 1.001 + 1e-6,
                   "%sapplied offsets never faster than OFFSET_AV_RATIO allows (%.3f <= %.3f mm/s)"
                   % (label, worst_applied_rate, limits.lcnc_rate))
    failures.check(worst_joint <= 1e-6, "%sat rest the joints stand at the commanded positions "
                   "plus the applied offsets (worst %.2g mm)" % (label, worst_joint))
    return {"worst_step_in_limiter_steps": worst_step,
            "max_applied_rate_mm_s": worst_applied_rate,
            "max_applied_offset_mm": worst_offset, "writes": writes,
            "max_joint_minus_commanded_plus_offset_mm": worst_joint}


def write_record(csv_path, rows, with_offsets=True):
    """The positions of `rows` as CSV x,y,z,ox,oy,oz (mm): commanded positions and the external
    offsets LinuxCNC applied (zero when `with_offsets` is false: the machine as if uncompensated),
    as volcomp-tooltip-error and `volcomp-sim nc-run --positions` read them."""
    with open(csv_path, "w") as f:
        f.write("x,y,z,ox,oy,oz\n")
        for r in rows:
            o = [r[COL_EOFFSET + k] if with_offsets else 0.0 for k in range(3)]
            f.write("%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n" % (
                r[COL_POS], r[COL_POS + 1], r[COL_POS + 2], o[0], o[1], o[2]))
    return csv_path


def tooltip_error(tool, true_model, rows, csv_path):
    """The true tool-tip error along `rows` with and without their applied offsets."""
    write_record(csv_path, rows)
    out = subprocess.run([tool, true_model, csv_path], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError("volcomp-tooltip-error failed: " + out.stderr)
    return json.loads(out.stdout)
