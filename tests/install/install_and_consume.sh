#!/usr/bin/env bash
# What `cmake --install` gives a new user, checked from a build tree:
#  - the programs, units, settings and reference files land in FHS places
#    under the prefix /usr (in a scratch DESTDIR), the units naming the
#    installed programs;
#  - the units pass `systemd-analyze verify` against that root (where
#    systemd-analyze exists);
#  - another CMake project finds the package (find_package(hapsim)), links
#    hapsim::core, builds and runs (tests/install/consumer).
# Usage: install_and_consume.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
root="$work/root"
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
[ "$prefix" = /usr ] || { echo "FAIL the build is configured to install under $prefix, not /usr"; exit 1; }
DESTDIR="$root" cmake --install "$build" >"$work/install.log"
fail=0
need() { [ -e "$root$1" ] && echo "ok   $1" || { echo "FAIL missing $1"; fail=1; }; }
for f in /usr/bin/hapsim-server /usr/bin/hapsim-bridge /usr/bin/hapsim-ctl /usr/bin/hapsim-viewer \
         /usr/bin/hapsim-load /usr/bin/hapsim-replay \
         /usr/lib/systemd/system/hapsim-server.service /usr/lib/systemd/system/hapsim-bridge@.service \
         /etc/hapsim/server.env /etc/hapsim/bridge.env /usr/share/hapsim/cyclonedds-loopback.xml \
         /usr/share/hapsim/make-dds-config.sh /usr/share/doc/hapsim/deploy.md \
         /usr/include/hapsim/core/scenes/scene.h; do
  need "$f"
done
core_lib=$(find "$root/usr/lib" -name libhapsim_core.a | head -1)  # /usr/lib/x86_64-linux-gnu on Debian
[ -n "$core_lib" ] && echo "ok   ${core_lib#"$root"}" || { echo "FAIL no libhapsim_core.a"; fail=1; }
config=$(find "$root/usr/lib" -name hapsimConfig.cmake | head -1)
[ -n "$config" ] && echo "ok   ${config#"$root"}" || { echo "FAIL no hapsimConfig.cmake"; fail=1; }
unit="$root/usr/lib/systemd/system/hapsim-server.service"
if grep -q '^ExecStart=/usr/bin/hapsim-server ' "$unit" && grep -q '^EnvironmentFile=/etc/hapsim/server.env' "$unit"; then
  echo "ok   the server unit runs /usr/bin/hapsim-server with /etc/hapsim/server.env"
else
  echo "FAIL the server unit does not name the installed program and settings"; fail=1
fi
"$root/usr/bin/hapsim-server" --help >/dev/null && echo "ok   the installed server runs (--help)" ||
  { echo "FAIL the installed server does not run"; fail=1; }
if command -v systemd-analyze >/dev/null; then
  # Verified on this host with the programs and settings they name pointed
  # into the scratch root (verify --root would want a whole systemd tree).
  mkdir -p "$work/verify"
  for unit in hapsim-server.service:hapsim-server.service hapsim-bridge@.service:hapsim-bridge@t1.service; do
    sed -e "s|=/usr/bin/|=$root/usr/bin/|g" -e "s|EnvironmentFile=\(-\?\)/etc/|EnvironmentFile=\1$root/etc/|g" \
        "$root/usr/lib/systemd/system/${unit%%:*}" >"$work/verify/${unit##*:}"
  done
  if systemd-analyze verify "$work/verify/hapsim-server.service" "$work/verify/hapsim-bridge@t1.service" \
       >"$work/verify.log" 2>&1 && ! grep -q . "$work/verify.log"; then
    echo "ok   systemd-analyze verify: both units clean"
  else
    echo "FAIL systemd-analyze verify:"; sed 's/^/     /' "$work/verify.log"; fail=1
  fi
else
  echo "skip systemd-analyze is not installed: the units are not verified"
fi
cmake -S "$here/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$root/usr" -DCMAKE_BUILD_TYPE=Release \
      >"$work/consumer-configure.log" 2>&1 || { cat "$work/consumer-configure.log"; exit 1; }
cmake --build "$work/consumer" >"$work/consumer-build.log" 2>&1 || { tail -20 "$work/consumer-build.log"; exit 1; }
"$work/consumer/press_tissue" || fail=1
echo "find_package(hapsim) found $(grep -m1 -o 'hapsim_DIR:PATH=.*' "$work/consumer/CMakeCache.txt" | sed "s|$root||")"
exit $fail
