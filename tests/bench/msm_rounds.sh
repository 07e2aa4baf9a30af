#!/usr/bin/env bash
# Repeated symplectic Euler benchmark rounds and their summary table, as in
# docs/performance.md ("Symplectic Euler: AVX-512 kernel vs portable kernel").
#
#   tests/bench/msm_rounds.sh BENCH_BINARY [ROUNDS] [PREVIOUS_BENCH_BINARY]
#
# Each round runs BENCH_BINARY's symplectic_euler benchmarks (the default
# kernel and the portable baseline, 3 repetitions each) and, if given, a
# previous build's binary right after it, so both see the same machine
# state. Prints a markdown table of per-size medians over the rounds.
set -euo pipefail
bench=${1:?usage: $0 BENCH_BINARY [ROUNDS] [PREVIOUS_BENCH_BINARY]}
rounds=${2:-8}
previous=${3:-}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run() {  # run BINARY JSON_OUT
  "$1" --benchmark_filter='symplectic_euler' --benchmark_min_time=0.2 --benchmark_repetitions=3 \
       --benchmark_report_aggregates_only=true --benchmark_out="$2" --benchmark_out_format=json >/dev/null 2>&1
}
for r in $(seq 1 "$rounds"); do
  run "$bench" "$out/new$r.json"
  [ -n "$previous" ] && run "$previous" "$out/old$r.json"
  echo "round $r/$rounds done $(date +%T), load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
python3 "$(dirname "$0")/msm_rounds_table.py" "$out"
