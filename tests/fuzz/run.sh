#!/usr/bin/env bash
# Runs every libFuzzer target of a VOXLUX_FUZZ build for SECONDS each (default 60), each on a
# working corpus made of its committed corpus (tests/fuzz/corpus/TARGET) and seeds from grids/,
# tests/golden/ and ../shared/data when it is there, as many targets at once as there are cores.
# Fails on a crash, leak or hang; the input that did it is left as BUILD/fuzz/TARGET-crash-*.
# Prints each target's executions.
#   tests/fuzz/run.sh build-sanitize 60
set -euo pipefail
build=${1:?usage: tests/fuzz/run.sh BUILD [SECONDS]}
seconds=${2:-60}
src="$(cd "$(dirname "$0")/../.." && pwd)"
shared="$src/../shared/data"

seeds() {
  case $1 in
    scene) ls "$src"/grids/*.json ;;
    light_edits) ls "$src"/grids/*edits*.json ;;
    vdb) ls "$shared"/oiio/damaged/*.vdb "$shared"/*/smoke_000001.vdb "$shared"/*/torus01.vdb 2>/dev/null || true ;;
    exr) ls "$src"/tests/golden/*.exr ;;
  esac
}

# OpenVDB's own leaks on a damaged tree are not ours (lsan_suppressions.txt says which).
export LSAN_OPTIONS="suppressions=$src/tests/fuzz/lsan_suppressions.txt"
# One target: its working corpus, its run, its line of figures; non-zero on a crash, leak or hang.
fuzz() {
  local target=$1 work="$build/fuzz/$1" log="$build/fuzz/$1.log"
  rm -rf "$work" && mkdir -p "$work"
  cp "$src/tests/fuzz/corpus/$target"/* "$work"/
  for seed in $(seeds "$target"); do cp "$seed" "$work/seed-$(basename "$seed")"; done
  # -seed: the same sequence of inputs on every run of a build (how far it gets follows the speed).
  # -max_len: mutations of the first 8 kB, where the structure is (a cache's voxels are not).
  if ! "$build/tests/fuzz/fuzz_$target" -seed=1 -max_total_time="$seconds" -max_len=8192 -timeout=20 -rss_limit_mb=4096 \
       -print_final_stats=1 -artifact_prefix="$build/fuzz/$target-" "$work" >"$log" 2>&1; then
    tail -n 40 "$log"
    echo "fuzz: fuzz_$target failed; its input is $build/fuzz/$target-*" >&2
    return 1
  fi
  local runs rate
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  echo "fuzz: fuzz_$target ran $runs inputs in ${seconds} s ($rate per second), no crash"
}

# A libFuzzer run is one thread: one target per core at a time, each still given SECONDS.
cores=$(nproc)
trap 'kill $(jobs -p) 2>/dev/null' INT TERM   # an interrupted run leaves no fuzzer behind
running=()
failed=0
for target in scene light_edits cli_specs vdb exr chan camera mesh; do
  fuzz "$target" &
  running+=($!)
  if (( ${#running[@]} >= cores )); then
    wait "${running[0]}" || failed=1
    running=("${running[@]:1}")
  fi
done
for pid in "${running[@]}"; do wait "$pid" || failed=1; done
exit $failed
