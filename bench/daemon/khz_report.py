#!/usr/bin/env python3
"""The report of bench/daemon/run_1khz.sh: missed deadlines of volcompd and of the empty-loop
baseline (cyclictest) per block and in total, and the check of every write the simulated
controller received against the limiter. Exits 1 when a write breaks the limits, 2 when a block
produced no figure.

One metric for both: a deadline is missed when no cycle started within one period of it, i.e.
the cycle woke up a whole period or more late (a late start) or never ran because the wake-up or
the cycle before ended after it (a skipped deadline). cyclictest skips the deadlines its late
wake-up passed, as volcompd's scheduler does, so a wake-up L late skips floor(L / period) of them.

Usage: khz_report.py WORK_DIR BLOCKS PERIOD_US MAX_OFFSET_MM MAX_RATE_MM_S QUANTUM_MM
                     RATE_TOLERANCE_MS WATCHDOG_S
WORK_DIR holds cyclictest-N.json and volcompd-N.err for N = 1..BLOCKS, sim.out (the simulator's
stdout, its report the last JSON line) and sim-writes.csv (its record of every write).
"""

import bisect
import json
import re
import sys
from pathlib import Path

STOP_LINE = re.compile(
    r"stopped after (\d+) cycles \((\d+) overruns\).*latest start (\d+) us after its deadline, "
    r"(\d+) cycles started a period or more late, (\d+) deadlines skipped \((\d+) while a cycle "
    r"ran\), longest cycle (\d+) us")
# cyclictest's histogram holds whole microseconds below its size; beyond it only a count.
HISTOGRAM_US = 100000


def baseline_block(path, period_us):
    """Missed deadlines of one cyclictest run, from its per-microsecond lateness histogram."""
    t = json.loads(path.read_text())["thread"]["0"]
    late = skipped = 0
    counted = 0
    for us, n in t["histogram"].items():
        counted += n
        if int(us) >= period_us:
            late += n
            skipped += n * (int(us) // period_us)
    overflow = t["cycles"] - counted  # later than the histogram: at least this many skipped each
    late += overflow
    skipped += overflow * (HISTOGRAM_US // period_us)
    return {"cycles": t["cycles"], "late": late, "skipped": skipped, "max_us": t["max"],
            "beyond_histogram": overflow}


def daemon_block(path):
    """Missed deadlines of one volcompd run, from the statistics it logs when it stops."""
    m = STOP_LINE.search(path.read_text(errors="replace"))
    if not m:
        return None
    cycles, overruns, latest, late, skipped, while_running, longest = (int(g) for g in m.groups())
    return {"cycles": cycles, "late": late, "skipped": skipped, "max_us": latest,
            "overruns": overruns, "while_running": while_running, "longest_us": longest}


def missed(b):
    return b["late"] + b["skipped"]


def read_record(path):
    rows = []
    with open(path) as f:
        next(f)  # header
        for line in f:
            v = line.strip().split(",")
            if len(v) == 8:
                rows.append((float(v[0]), [float(x) for x in v[1:4]], v[6] != "0", v[7] != "0"))
    return rows


def check_writes(rows, max_offset, max_rate, period_s, quantum, tolerance_s, watchdog_s):
    """Every write against the limits, independently of the simulator's own check: |o| within
    max_offset; no jump (no write more than one limiter step, max_rate x period, from the one
    before); max_rate over every window of 1, 10, 100 and 1000 writes, with the controller's
    time between them. Pairs across a silence longer than the controller's watchdog are left to
    the simulator (it ramps the offsets itself then; its per-write flag covers them)."""
    problems = []
    step_limit = max_rate * period_s + quantum + 1e-9
    times = [r[0] for r in rows]
    gaps = [0] + [i for i in range(1, len(rows)) if times[i] - times[i - 1] > watchdog_s]
    largest_step = largest_after_late = 0.0
    after_late = 0
    for j, (t, o, partial, violation) in enumerate(rows):
        if max(abs(x) for x in o) > max_offset + 0.5 * quantum + 1e-9:
            problems.append(f"write {j} at t={t:.4f} s: |offset| {o} mm > {max_offset} mm")
        if partial or violation:
            problems.append(f"write {j} at t={t:.4f} s: flagged by the simulator "
                            f"({'partial' if partial else 'limiter violation'})")
        segment_start = gaps[bisect.bisect_right(gaps, j) - 1]
        for k in (1, 10, 100, 1000):
            i = j - k
            if i < segment_start:
                break
            d = max(abs(a - b) for a, b in zip(o, rows[i][1]))
            if k == 1:
                largest_step = max(largest_step, d)
                if t - times[i] > 1.5 * period_s:  # a late or skipped cycle before this write
                    after_late += 1
                    largest_after_late = max(largest_after_late, d)
                if d > step_limit:
                    problems.append(f"write {j} at t={t:.4f} s: jump of {d * 1e3:.2f} um "
                                    f"> one step {step_limit * 1e3:.2f} um")
            window = max_rate * (t - times[i] + tolerance_s) + 2 * quantum + 1e-9
            if d > window:
                problems.append(f"writes {i}..{j} (t={times[i]:.4f}..{t:.4f} s): "
                                f"{d * 1e3:.2f} um > max_rate over the window {window * 1e3:.2f} um")
    return problems, {"largest_step_um": largest_step * 1e3, "step_limit_um": step_limit * 1e3,
                      "writes_after_late_cycle": after_late,
                      "largest_step_after_late_um": largest_after_late * 1e3}


def main(argv):
    work = Path(argv[1])
    blocks, period_us = int(argv[2]), int(argv[3])
    max_offset, max_rate, quantum = float(argv[4]), float(argv[5]), float(argv[6])
    tolerance_s, watchdog_s = float(argv[7]) / 1000, float(argv[8])
    per_block = []
    for n in range(1, blocks + 1):
        base = baseline_block(work / f"cyclictest-{n}.json", period_us)
        daemon = daemon_block(work / f"volcompd-{n}.err")
        if daemon is None:
            print(f"run_1khz: block {n}: volcompd logged no statistics when it stopped:\n"
                  + (work / f"volcompd-{n}.err").read_text(errors="replace")[-2000:],
                  file=sys.stderr)
            return 2
        per_block.append((n, base, daemon))

    print("\nmissed deadlines (no cycle started within one period: late starts + skipped)")
    print(f"{'block':>5} {'baseline':>9} {'volcompd':>9}   baseline: cycles / late starts / "
          f"skipped / latest start us   volcompd: cycles / late starts / skipped (while a cycle "
          f"ran) / latest start us / longest cycle us / overruns")
    for n, b, d in per_block:
        print(f"{n:>5} {missed(b):>9} {missed(d):>9}   {b['cycles']} / {b['late']} / "
              f"{b['skipped']} / {b['max_us']}   {d['cycles']} / {d['late']} / {d['skipped']} "
              f"({d['while_running']}) / {d['max_us']} / {d['longest_us']} / {d['overruns']}")
    total_b = sum(missed(b) for _, b, _ in per_block)
    total_d = sum(missed(d) for _, _, d in per_block)
    deadlines_b = sum(b["cycles"] + b["skipped"] for _, b, _ in per_block)
    deadlines_d = sum(d["cycles"] + d["skipped"] for _, _, d in per_block)
    print(f"{'total':>5} {total_b:>9} {total_d:>9}   of {deadlines_b} / {deadlines_d} deadlines")
    beyond = sum(b["beyond_histogram"] for _, b, _ in per_block)
    if beyond:
        print(f"note: {beyond} baseline wake-ups were later than {HISTOGRAM_US} us; each is "
              f"counted as {HISTOGRAM_US // period_us} skipped deadlines (a lower bound)")
    print(f"volcompd {'within' if total_d <= total_b else 'ABOVE'} the baseline: "
          f"{total_d} vs {total_b} missed deadlines")

    lines = [l for l in (work / "sim.out").read_text().splitlines() if l.startswith("{")]
    if not lines:
        print("run_1khz: the simulator wrote no report", file=sys.stderr)
        return 2
    report = json.loads(lines[-1])
    rows = read_record(work / "sim-writes.csv")
    problems, s = check_writes(rows, max_offset, max_rate, period_us * 1e-6, quantum,
                               tolerance_s, watchdog_s)
    print(f"\ncontroller: {len(rows)} writes recorded, simulator's count of limiter violations "
          f"{report['limiter_violations']}, partial writes {report.get('partial_writes', 0)}; "
          f"independent check: largest step {s['largest_step_um']:.2f} um (one step "
          f"{s['step_limit_um']:.2f} um), {s['writes_after_late_cycle']} writes after a late or "
          f"skipped cycle, largest step among them {s['largest_step_after_late_um']:.2f} um")
    if report["limiter_violations"]:
        problems.append(f"the simulator counted {report['limiter_violations']} limiter violations"
                        f", the first: {report.get('first_violation', '')}")
    if not rows:
        problems.append("the simulator recorded no write")
    if problems:
        print(f"run_1khz: FAILED, {len(problems)} problems with the writes:", file=sys.stderr)
        for p in problems[:20]:
            print("  " + p, file=sys.stderr)
        return 1
    print("limiter: 0 violations, no jump")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
