#!/usr/bin/env bash
# Configures and builds hapsim into build/ (executables in build/bin/).
# Usage: deploy/build.sh [extra cmake args]. Idempotent and incremental.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc 2>/dev/null || echo 2)
# Every feature the README promises is required here (the viewer's window
# and pictures): a missing package fails the build naming it, instead of the
# feature disappearing quietly.
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DHAPSIM_WITH_VIEWER_GUI=ON "$@" >/dev/null
cmake --build "$root/build" -j "$jobs"
