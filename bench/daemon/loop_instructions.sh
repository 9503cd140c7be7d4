#!/usr/bin/env bash
# Instructions per CompensationLoop::step() without I/O (fake port, fake clock, trivial model),
# counted by callgrind: a figure that the machine's load does not move, for comparing two builds.
#
# Usage: bench/daemon/loop_instructions.sh [BUILD_DIR]     (default: build)
set -euo pipefail
build="${1:-build}"
bench="$build/bench/daemon/volcomp-bench-loop"
[ -x "$bench" ] || { echo "loop_instructions: $bench is missing (build the benchmarks)" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "loop_instructions: needs valgrind" >&2; exit 2; }
out="$(mktemp)"
trap 'rm -f "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out" "$bench" \
  --benchmark_filter=BM_LoopStepFakeModel --benchmark_min_time=0.01 >/dev/null 2>&1
python3 - "$out" <<'PY'
import re, sys
# Inclusive cost of every call to step(): the "calls=" line under a cfn of step() and the cost
# line after it.
lines = open(sys.argv[1]).read().split("\n")
names, calls, cost, callee = {}, 0, 0, None
for i, line in enumerate(lines):
    m = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
    if m:
        kind, ident, name = m.groups()
        if name:
            names[ident] = name
        if kind == "cfn":
            callee = names.get(ident)
        continue
    if line.startswith("calls=") and callee and callee.endswith("CompensationLoop::step()"):
        calls += int(line.split("=")[1].split()[0])
        cost += int(lines[i + 1].split()[1])
        callee = None
if not calls:
    sys.exit("loop_instructions: no call to step() found")
print(f"{cost / calls:.0f} instructions per step ({calls} steps)")
PY
