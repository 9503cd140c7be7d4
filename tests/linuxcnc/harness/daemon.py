"""volcompd as a process beside a headless LinuxCNC (the way systemd runs it): configuration files,
start, SIGTERM, SIGKILL, and what it publishes on its HAL component."""
import json
import os
import signal
import subprocess

import lcnc

STATUS_ACTIVE = 1 << 0
STATUS_DISABLED = 1 << 1
STATUS_FAULT = 1 << 2
STATUS_LIMITED = 1 << 3


def write_config(path, model, transport, cycle_ms=5, max_offset=0.1, max_rate=0.5, extra=None):
    """A daemon configuration with commanded semantics and the read-back on."""
    config = {
        "cycle_period_ms": cycle_ms,
        "position_semantics": "commanded",
        "limiter": {"max_offset_mm": max_offset, "max_rate_mm_s": max_rate},
        "stale_timeout_ms": 500,
        "offset_readback": True,
        "model": os.path.abspath(model),
        "log_level": "info",
        "transport": transport,
    }
    config.update(extra or {})
    with open(path, "w") as f:
        json.dump(config, f, indent=2)
    return config


class Daemon:
    def __init__(self, volcompd, config, log):
        self.volcompd = volcompd
        self.config = config
        self.log_path = log
        self.proc = None

    def start(self):
        self.log = open(self.log_path, "a")
        self.proc = subprocess.Popen([self.volcompd, "--config", self.config], stdout=self.log,
                                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                     start_new_session=True)
        return self

    def running(self):
        return self.proc is not None and self.proc.poll() is None

    def terminate(self, timeout=30.0):
        """SIGTERM: the daemon ramps the offsets out and exits; returns its exit status."""
        self.proc.send_signal(signal.SIGTERM)
        return self._reap(timeout)

    def kill(self):
        self.proc.send_signal(signal.SIGKILL)
        return self._reap(10.0)

    def _reap(self, timeout):
        try:
            rc = self.proc.wait(timeout=timeout)
        finally:
            self.log.close()
        return rc

    def text(self):
        with open(self.log_path) as f:
            return f.read()


def component_names():
    """Names of the HAL components called volcomp*."""
    names = []
    for line in lcnc.halcmd("show", "comp").splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[2].startswith("volcomp") and parts[1] == "User":
            names.append(parts[2])
    return names


def wait_status(machine, component, predicate, what, timeout=30.0):
    """Waits until the daemon's status word (pin <component>.status) satisfies `predicate`."""
    return lcnc.wait_for(lambda: predicate(int(machine.get(component + ".status"))), what,
                         timeout, poll=0.01)
