#!/usr/bin/env bash
# Fuzzes one libFuzzer target for a bounded time (CTest fuzz.<name>, label fuzz; see
# fuzz/CMakeLists.txt). Usage: run_fuzzer.sh BINARY NAME SECONDS WORKDIR DICT CORPUS_DIR...
# New inputs go to WORKDIR/corpus/NAME (the committed corpus is only read); a finding is saved
# as WORKDIR/findings/NAME-crash-<sha1> (or -timeout-, -oom-, -leak-) and fails the test. One
# line of statistics per run is appended to WORKDIR/summary.txt.
set -euo pipefail
binary=$1 name=$2 seconds=$3 work=$4 dict=$5
shift 5
mkdir -p "$work/corpus/$name" "$work/findings"
args=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048
      -print_final_stats=1 -artifact_prefix="$work/findings/$name-")
if [ -f "$dict" ]; then args+=(-dict="$dict"); fi
log="$work/$name.log"
status=0
start=$(date +%s)
"$binary" "${args[@]}" "$work/corpus/$name" "$@" >"$log" 2>&1 || status=$?
elapsed=$(($(date +%s) - start))

stat() { grep -o "stat::$1: *[0-9]*" "$log" | tail -n 1 | grep -o '[0-9]*$' || echo "?"; }
coverage=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -n 1 || true)
corpus=$(find "$work/corpus/$name" "$@" -type f | wc -l)
line="fuzz $name: $(stat number_of_executed_units) runs in ${elapsed} s ($(stat average_exec_per_sec)/s), ${coverage:-cov: ?}, corpus $corpus, peak RSS $(stat peak_rss_mb) MB"
echo "$line" | tee -a "$work/summary.txt"
if [ "$status" -ne 0 ]; then
  tail -n 80 "$log"
  echo "fuzz $name: FINDING (exit $status); input saved under $work/findings/" >&2
  exit 1
fi
