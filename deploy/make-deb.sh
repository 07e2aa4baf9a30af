#!/usr/bin/env bash
# Builds hapsim's Debian package from a build tree (deploy/build.sh first):
# what `cmake --install` installs, under /usr and /etc, with its library
# dependencies found by dpkg-shlibdeps. Prints the .deb's path.
#   deploy/make-deb.sh [BUILD_DIR] [OUT_DIR]      (default: build, build/packages)
# Install it on a Debian 12 machine with: apt-get install ./hapsim_*.deb
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/packages}
mkdir -p "$out"
[ -f "$build/CPackConfig.cmake" ] || { echo "make-deb: $build is not a configured build tree (run deploy/build.sh)" >&2; exit 2; }
cpack --config "$build/CPackConfig.cmake" -B "$out" >"$out/cpack.log" 2>&1 || { tail -20 "$out/cpack.log" >&2; exit 1; }
rm -rf "$out/_CPack_Packages"
ls "$out"/hapsim_*.deb
