#!/usr/bin/env bash
# Runs every libFuzzer target over its seed corpus (tests/fuzz/corpus/<name>).
# Usage: tests/fuzz/run.sh [SECONDS_PER_TARGET] [RUNS]
#   CI (deploy/test.sh): a short run of each, 20 s.
#   Campaign (docs/reliability.md): tests/fuzz/run.sh 0 1000000   (>= 10^6 executions each)
# Builds build-fuzz with clang (ASan + UBSan + libFuzzer) first. New inputs
# go to a scratch corpus, never into the repository's seeds; a crash leaves
# its input in build-fuzz/crashes/<name>/ and the script exits 1. An input
# slower than 60 s counts as a hang (a session-service input may build a
# scene at its limits: seconds under ASan).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-20}
runs=${2:--1}
build="$root/build-fuzz"
jobs=$(nproc 2>/dev/null || echo 2)
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHAPSIM_FUZZ=ON \
    -DHAPSIM_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target hapsim-fuzz
status=0
for exe in "$build"/fuzz/fuzz_*; do
  name=$(basename "$exe"); name=${name#fuzz_}
  seeds="$root/tests/fuzz/corpus/$name"
  scratch="$build/corpus/$name"
  crashes="$build/crashes/$name"
  mkdir -p "$scratch" "$crashes"
  limit=()
  [ "$seconds" != 0 ] && limit+=(-max_total_time="$seconds")
  echo "== fuzz_$name (${seconds}s, runs $runs)"
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      "$exe" "$scratch" "$seeds" "${limit[@]}" -runs="$runs" -max_len=4096 -timeout=60 -rss_limit_mb=2048 \
      -artifact_prefix="$crashes/" -print_final_stats=1 2>"$build/fuzz_$name.log"; then
    echo "fuzz_$name: FAILED (input in $crashes/, log $build/fuzz_$name.log)"
    tail -40 "$build/fuzz_$name.log"
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$build/fuzz_$name.log" | tail -3 || true
done
exit $status
