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
# The unit, service, bridge and viewer tests again under ASan + UBSan
# (clang, build-fuzz; tests/sanitized/run.sh).
"$root/tests/sanitized/run.sh"
# Every libFuzzer target (ASan + UBSan build with clang in build-fuzz) for
# 20 s over its seed corpus: a crash or a broken invariant fails the run
# (tests/fuzz/run.sh; the long campaign is in docs/reliability.md).
"$root/tests/fuzz/run.sh" 20
