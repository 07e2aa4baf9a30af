#!/usr/bin/env bash
# Configures and builds hapsim into build/ (executables in build/bin/).
# Usage: deploy/build.sh [extra cmake args]. Idempotent and incremental.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$root/build" -j "$jobs"
