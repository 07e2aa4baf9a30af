#!/usr/bin/env bash
# One command, fresh Debian 12 machine: install dependencies, build, and run
# every test (unit, service, bridge, viewer, validation, end-to-end) with
# ctest. Exits non-zero on any failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/deploy/install-deps.sh"
"$root/deploy/build.sh"
jobs=$(nproc 2>/dev/null || echo 2)
cd "$root/build"
ctest --output-on-failure --timeout 600 -j "$jobs"
