#!/usr/bin/env bash
# One command, fresh Debian 12 machine: install dependencies, build, and run
# every test (unit, service, bridge, viewer, validation, end-to-end) with
# ctest. Exits non-zero on any failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# Elapsed time at each phase, so CI's budget (well under 30 min) can be watched.
phase() { echo "== test.sh: $1 at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
"$root/deploy/install-deps.sh"
phase "dependencies installed"
"$root/deploy/build.sh"
phase "built"
jobs=$(nproc 2>/dev/null || echo 2)
cd "$root/build"
ctest --output-on-failure --timeout 600 -j "$jobs"
phase "ctest passed"
# The unit, service, bridge and viewer tests again under ASan + UBSan
# (clang, build-fuzz; tests/sanitized/run.sh).
"$root/tests/sanitized/run.sh"
phase "sanitized tests passed"
# Every libFuzzer target (ASan + UBSan build with clang in build-fuzz) for
# 20 s over its seed corpus: a crash or a broken invariant fails the run
# (tests/fuzz/run.sh; the long campaign is in docs/reliability.md).
"$root/tests/fuzz/run.sh" 20
phase "fuzz targets passed"
