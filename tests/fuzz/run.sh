#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# tests/fuzz/run.sh [SECONDS]: runs every harness of build/fuzz/fuzz/ (preset `fuzz`) for
# SECONDS each (default $FUZZ_SECONDS, else 30), $FUZZ_JOBS at a time (default 2), each on a
# temporary copy of its seeds (tests/fuzz/seeds/NAME/, the generated build/fuzz/fuzz/seeds/
# NAME/ and the example files of `examples` below, where they live): the tree is never
# modified. Prints libFuzzer's final counters per harness. A crash,
# sanitizer report, leak, timeout or out-of-memory fails the run (exit 1) and prints the
# reproducer's path and the command replaying it; the temporary directory is then kept.
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds=${1:-${FUZZ_SECONDS:-30}}
jobs=${FUZZ_JOBS:-2}
bin=build/fuzz/fuzz
shopt -s nullglob
harnesses=("$bin"/*_fuzz)
if ((${#harnesses[@]} == 0)); then
  echo "tests/fuzz/run.sh: no harness in $bin (build them: cmake --preset fuzz && cmake --build --preset fuzz)" >&2
  exit 2
fi
# Example files kept beside the code they configure, used in place as seeds.
declare -A examples=(
  [gateway_config_fuzz]="firmware/app/gateway.example.toml firmware/app/gateway.can.example.toml sim/server/examples/loop/gateway.toml"
  [server_config_fuzz]="sim/server/examples/alatiqi4x4.toml sim/server/examples/loop/plant.toml"
)
work=$(mktemp -d "${TMPDIR:-/tmp}/excite-fuzz.XXXXXX")

# run_one NAME: fuzzes NAME for $seconds; its exit status is left in $work/NAME/rc.
run_one() {
  local name=$1 dir=$work/$1
  mkdir -p "$dir/corpus"
  for seeds in "tests/fuzz/seeds/$name" "$bin/seeds/$name"; do
    if [[ -d "$seeds" ]]; then cp -r "$seeds/." "$dir/corpus/"; fi
  done
  for example in ${examples[$name]:-}; do
    if [[ -f "$example" ]]; then cp "$example" "$dir/corpus/"; fi
  done
  local rc=0
  # -timeout: one input longer than 10 s is a hang; -rss_limit_mb also bounds single
  # allocations (malloc_limit_mb defaults to it), so an input that asks for gigabytes fails.
  "$bin/$name" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$dir/" "$dir/corpus" >"$dir/log" 2>&1 || rc=$?
  echo "$rc" >"$dir/rc"
}

running=0
for harness in "${harnesses[@]}"; do
  if ((running >= jobs)); then
    wait -n
    running=$((running - 1))
  fi
  run_one "$(basename "$harness")" &
  running=$((running + 1))
done
wait

failed=0
printf '%-22s %10s %8s %7s %7s %9s\n' harness runs exec/s cov ft corpus
for harness in "${harnesses[@]}"; do
  name=$(basename "$harness")
  dir=$work/$name
  stat() { sed -n "s/^stat::$1: *//p" "$dir/log" | tail -1; }
  # The last status line (#N DONE/pulse cov: ft: corp: N/size exec/s:) gives cov, ft, corpus.
  last=$(grep -E '^#[0-9]+' "$dir/log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  printf '%-22s %10s %8s %7s %7s %9s\n' "$name" "$(stat number_of_executed_units)" \
    "$(stat average_exec_per_sec)" "${cov:-?}" "${ft:-?}" "${corp:-?}"
  if [[ "$(cat "$dir/rc")" != 0 ]]; then
    failed=1
    echo "FAIL $name (exit $(cat "$dir/rc")): log $dir/log" >&2
    grep -E 'ERROR:|fuzz property violated|runtime error:' "$dir/log" | head -5 >&2 || true
    for artifact in "$dir"/crash-* "$dir"/leak-* "$dir"/timeout-* "$dir"/oom-*; do
      echo "  reproducer: $artifact" >&2
      echo "  replay:     $harness $artifact" >&2
    done
  fi
done
if ((failed)); then
  echo "tests/fuzz/run.sh: failures above; corpora and logs kept in $work" >&2
  exit 1
fi
rm -rf "$work"
