"""The machine the adapter's LinuxCNC tests run: the VMC-850 of config/examples (its travel, XYZ,
perfect servos) with the shipped HAL snippet, and the daemon settings they use."""
import os
import shutil

import checks
import lcnc

TRAVEL = {"X": (0.0, 850.0), "Y": (0.0, 500.0), "Z": (-500.0, 0.0)}
MAX_VELOCITY = 200.0
MAX_ACCELERATION = 2000.0
OFFSET_AV_RATIO = 0.05  # offsets: 10 mm/s, 100 mm/s^2; programs: 190 mm/s
CYCLE_MS = 5
MAX_OFFSET = 0.1
MAX_RATE = 0.5
COUNTS_PER_MM = 10000
TRANSPORT = {"type": "linuxcnc", "component": "volcomp", "counts_per_mm": COUNTS_PER_MM}


def machine(work, hal_dir):
    """A fresh `work` folder with LinuxCNC's configuration: sim files, the shipped snippet
    (volcomp.hal from `hal_dir`) and the test's own signals (test.hal)."""
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)
    m = lcnc.Machine(work, TRAVEL, max_velocity=MAX_VELOCITY, max_acceleration=MAX_ACCELERATION,
                     offset_av_ratio=OFFSET_AV_RATIO, hal_files=["volcomp.hal", "test.hal"])
    m.prepare()
    shutil.copy(os.path.join(hal_dir, "volcomp.hal"), work)
    checks.write_test_hal(os.path.join(work, "test.hal"))
    return m


def limits():
    return checks.Limits(max_offset=MAX_OFFSET, max_rate=MAX_RATE, cycle_ms=CYCLE_MS,
                         counts_per_mm=COUNTS_PER_MM, lcnc_rate=OFFSET_AV_RATIO * MAX_VELOCITY)
