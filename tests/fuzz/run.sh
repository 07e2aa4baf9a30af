#!/usr/bin/env bash
# Runs every libFuzzer target over its seed corpus (tests/fuzz/corpus/<name>).
# Usage: tests/fuzz/run.sh [SECONDS_PER_TARGET] [RUNS]
#   CI (deploy/test.sh): a short run of each, 20 s, as many at once as there are cores.
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
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHAPSIM_FUZZ=ON -DHAPSIM_UNITY_BUILD=ON \
    -DHAPSIM_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target hapsim-fuzz
# One target per core at a time (a libFuzzer process is single-threaded), so
# CI's 8 x 20 s take 80 s of wall time on 2 cores, not 160.
fuzz_one() {
  local exe=$1 name seeds scratch crashes limit=()
  name=$(basename "$exe"); name=${name#fuzz_}
  seeds="$root/tests/fuzz/corpus/$name"
  scratch="$build/corpus/$name"
  crashes="$build/crashes/$name"
  mkdir -p "$scratch" "$crashes"
  [ "$seconds" != 0 ] && limit+=(-max_total_time="$seconds")
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      "$exe" "$scratch" "$seeds" "${limit[@]}" -runs="$runs" -max_len=4096 -timeout=60 -rss_limit_mb=2048 \
      -artifact_prefix="$crashes/" -print_final_stats=1 2>"$build/fuzz_$name.log"; then
    echo "== fuzz_$name (${seconds}s, runs $runs): passed"
  else
    echo "== fuzz_$name (${seconds}s, runs $runs): FAILED (input in $crashes/, log $build/fuzz_$name.log)"
    tail -40 "$build/fuzz_$name.log"
    return 1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$build/fuzz_$name.log" | tail -3 || true
}
status=0
running=0
reap_one() { wait -n || status=1; running=$((running - 1)); }
for exe in "$build"/fuzz/fuzz_*; do
  [ "$running" -ge "$jobs" ] && reap_one
  fuzz_one "$exe" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do reap_one; done
exit $status
