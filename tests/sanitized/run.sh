#!/usr/bin/env bash
# Unit, service, bridge and viewer tests under AddressSanitizer +
# UndefinedBehaviorSanitizer, in CI after the release ctest.
# Usage: tests/sanitized/run.sh
# It reuses the fuzz tree (build-fuzz: clang, ASan + UBSan on every target,
# see tests/fuzz/run.sh), so CI compiles the libraries once for both the
# fuzzers and these tests instead of building a third tree. It is built in
# unity batches like the release tree (11 min 20 s here, against ~14 min
# file by file): a file that compiles only because its batch includes
# something is found with -DHAPSIM_UNITY_BUILD=OFF (docs/reliability.md).
# Integration and validation tests stay in the release run: they time real
# processes against deadlines that ASan's ~2x slowdown would break.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build="$root/build-fuzz"
jobs=$(nproc 2>/dev/null || echo 2)
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHAPSIM_FUZZ=ON -DHAPSIM_UNITY_BUILD=ON \
    -DHAPSIM_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target hapsim-core-tests hapsim-io-tests hapsim-common-tests \
    hapsim-dds-tests hapsim-wire-tests \
    hapsim-runtime-tests hapsim-device-link-tests hapsim-streaming-tests hapsim-classroom-tests hapsim-api-tests \
    hapsim-web-tests \
    hapsim-servo-tests hapsim-openhaptics-tests hapsim-bridge-tests hapsim-load-tests hapsim-viewer-tests
# alloc_dealloc_mismatch=0: Debian's libgrpc 1.51 itself allocates with
# operator new(nothrow) and releases with free() in ChannelInit::Builder::Build
# (grpc_server_create); ASan stops every gRPC server test there otherwise.
# Our own code has no such pair: the fuzz targets, which run without a gRPC
# server, keep the check on.
export ASAN_OPTIONS=detect_leaks=1:alloc_dealloc_mismatch=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
cd "$build"
# Every test of these labels runs here. (Until UBSan left the installed
# headers alone — cmake/ubsan-third-party-headers.txt — 35 physics tests
# took minutes each in this tree and ran in the release ctest only.)
ctest --output-on-failure --timeout 600 -j "$jobs" -L '^(core|io|common|dds|wire|server/.*|device-bridge/.*|client-viewer)$'
