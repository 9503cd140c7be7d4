#!/usr/bin/env bash
# Source coverage of the fuzz corpus (the figures in docs/robustness.md): builds the fuzz targets
# with clang's source-based coverage into ${COVERAGE_BUILD_DIR:-build-coverage}, runs each once over
# its committed corpus and regression inputs, and prints the line and branch coverage of the
# parser sources each target is for. Not part of the test command; needs clang and llvm.
# Usage: scripts/fuzz-coverage.sh [TARGET...]   (default: every target below)
# With FUZZ_CORPUS_DIR set (e.g. build-sanitize/fuzz/corpus after a fuzz run), the inputs a fuzz
# run added (FUZZ_CORPUS_DIR/TARGET) are run too: the coverage fuzzing reached, not only the seeds.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${COVERAGE_BUILD_DIR:-$here/build-coverage}"

# Target -> the sources it is meant to cover (relative to the checkout).
declare -A sources=(
  [model_json]="config/src/json_text.cpp config/src/json_reader.cpp config/src/model_file.cpp config/src/machine_parse.cpp config/src/chain_parse.cpp config/src/units.cpp config/src/model_write.cpp"
  [measurements_csv]="calibration/src/measurements_csv.cpp config/src/text_input.cpp"
  [iso230_2_csv]="metrology/src/positioning_runs_csv.cpp metrology/src/iso230_2.cpp metrology/src/iso230_2_json.cpp"
  [points_csv]="tools/cli/points_csv.cpp tools/cli/cli_support.cpp config/src/text_input.cpp"
  [daemon_config]="daemon/config/src/daemon_config.cpp daemon/config/src/transport_config.cpp daemon/config/src/transport_limits.cpp drivers/modbus/config/src/modbus_config.cpp drivers/can/config/src/can_section.cpp drivers/can/config/src/can_layout.cpp drivers/linuxcnc/config/src/linuxcnc_config.cpp"
  [dbc]="drivers/can/config/src/dbc_file.cpp drivers/can/src/dbc.cpp drivers/can/src/signal.cpp"
  [modbus_registers]="drivers/modbus/src/codec.cpp drivers/modbus/src/register_plan.cpp drivers/modbus/config/src/modbus_config.cpp"
  [can_frames]="drivers/can/io/src/channel.cpp drivers/can/io/src/controller_port.cpp drivers/can/src/signal.cpp"
  [ngc]="nc/src/block.cpp nc/src/numbers.cpp nc/src/ngc_interpreter.cpp nc/src/ngc_reader.cpp nc/src/move.cpp nc/src/compensator.cpp"
  [canon]="nc/src/canon_reader.cpp nc/src/numbers.cpp nc/src/move.cpp nc/src/compensator.cpp"
)
targets=("$@")
if [ "${#targets[@]}" -eq 0 ]; then targets=("${!sources[@]}"); fi

flags="-fprofile-instr-generate -fcoverage-mapping"
CC=clang CXX=clang++ cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
  -DVOLCOMP_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" >/dev/null
for t in "${targets[@]}"; do
  cmake --build "$build" --target "volcomp_fuzz_$t" >/dev/null
  binary="$build/fuzz/volcomp_fuzz_$t"
  dirs=("$here/fuzz/corpus/$t")
  if [ -d "$here/fuzz/regressions/$t" ]; then dirs+=("$here/fuzz/regressions/$t"); fi
  if [ -n "${FUZZ_CORPUS_DIR:-}" ] && [ -d "$FUZZ_CORPUS_DIR/$t" ]; then
    dirs+=("$FUZZ_CORPUS_DIR/$t")
  fi
  rm -f "$build/$t".profraw
  LLVM_PROFILE_FILE="$build/$t.profraw" "$binary" "${dirs[@]}" >/dev/null 2>&1
  llvm-profdata merge -sparse "$build/$t.profraw" -o "$build/$t.profdata"
  files=()
  for s in ${sources[$t]}; do files+=("$here/$s"); done
  echo "== $t ($(find "${dirs[@]}" -type f | wc -l) inputs)"
  llvm-cov report "$binary" -instr-profile="$build/$t.profdata" "${files[@]}" |
    awk 'NR == 1 || /^-/ {next} {print}' | sed "s|$here/||"
done
