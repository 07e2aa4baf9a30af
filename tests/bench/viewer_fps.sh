#!/usr/bin/env bash
# The viewer's frame rate on software rendering (Mesa llvmpipe).
# Not a test: run by hand, figures in docs/viewer.md. Usage:
#   tests/bench/viewer_fps.sh [BUILD_DIR] [SECONDS]
# 1. bench_viewer_render: one viewer frame (upload every vertex, draw mesh +
#    tool + arrow, ImGui panels with a 30 000-sample history), off screen,
#    side by side with the baseline of no mesh.
# 2. hapsim-viewer itself replaying a 5k and a 50k-vertex recording flat out
#    (--benchmark-seconds), off screen (EGL) and in a window under Xvfb; the
#    50k one as drawn by default (simplified) and with every triangle.
set -euo pipefail
build=${1:-build}
seconds=${2:-6}
bin=$build/bin
work=$(mktemp -d)
trap 'kill $xvfb 2>/dev/null || true; rm -rf "$work"' EXIT
HAPSIM_BENCH_RECORDINGS=$work "$bin/bench_viewer_render" --benchmark_min_time=3 2>&1 | grep -E "^BM_|^Benchmark|^---"
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp 3>"$work/display" 2>/dev/null &
xvfb=$!
for _ in $(seq 1 50); do [ -s "$work/display" ] && break; sleep 0.1; done
# The 50k sheet twice: as drawn by default (simplified to --max-triangles)
# and with every triangle (--max-triangles 0).
for run in "71 default" "224 default" "224 0"; do
  read -r grid budget <<<"$run"
  for mode in off-screen window; do
    for panels in true false; do
      flags=(--replay "$work/sheet_$grid.frames" --benchmark-seconds "$seconds" --panels="$panels")
      [ "$budget" != default ] && flags+=(--max-triangles "$budget")
      [ "$mode" = off-screen ] && flags+=(--headless)
      printf 'grid %-3s max-triangles %-7s %-10s panels=%-5s ' "$grid" "$budget" "$mode" "$panels"
      DISPLAY=":$(cat "$work/display")" "$bin/hapsim-viewer" "${flags[@]}" | grep '^benchmark'
    done
  done
done
