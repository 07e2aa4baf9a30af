#!/usr/bin/env bash
# The Debian package (deploy/make-deb.sh): it builds, declares the library
# packages the programs need, marks the settings as conffiles, has the
# maintainer scripts, and unpacks to the same FHS tree `cmake --install`
# gives (programs, units naming them, settings, the CMake package).
# Usage: check_deb.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src=$1 build=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
deb=$(bash "$src/deploy/make-deb.sh" "$build" "$work")
echo "package: $(basename "$deb"), $(du -h "$deb" | cut -f1)"
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for lib in libgrpc++ libprotobuf libddsc libzstd libsqlite3 libssl libeigen3-dev; do
  grep -q "$lib" <<<"$depends" && ok "depends on $lib" || bad "does not depend on $lib"
done
dpkg-deb -e "$deb" "$work/control"
for f in conffiles postinst prerm postrm; do [ -f "$work/control/$f" ] && ok "control: $f" || bad "control: no $f"; done
for f in /etc/hapsim/server.env /etc/hapsim/bridge.env; do
  grep -qx "$f" "$work/control/conffiles" && ok "conffile $f" || bad "$f is not a conffile"
done
dpkg-deb -x "$deb" "$work/root"
for f in usr/bin/hapsim-server usr/bin/hapsim-bridge usr/bin/hapsim-ctl usr/bin/hapsim-viewer \
         usr/lib/systemd/system/hapsim-server.service usr/lib/systemd/system/hapsim-bridge@.service \
         etc/hapsim/server.env usr/lib/x86_64-linux-gnu/cmake/hapsim/hapsimConfig.cmake \
         usr/include/hapsim/core/scenes/scene.h; do
  [ -e "$work/root/$f" ] && ok "/$f" || bad "/$f missing"
done
grep -q '^ExecStart=/usr/bin/hapsim-server ' "$work/root/usr/lib/systemd/system/hapsim-server.service" &&
  ok "the unit runs /usr/bin/hapsim-server" || bad "the unit does not run /usr/bin/hapsim-server"
exit $fail
