#!/usr/bin/env bash
# Builds hapsim's OCI image from Debian's archive only: a debootstrap'd
# Debian 12 root, the hapsim .deb (deploy/make-deb.sh) installed into it with
# its dependencies, assembled into an OCI image layout with umoci (no
# registry, no Dockerfile, no daemon). Load it into podman with
#   podman load -i build/oci/hapsim-0.1.0.oci.tar && podman tag localhost/0.1.0 localhost/hapsim:0.1.0
# Before packing, the image's root is run once (chroot, as its user): the
# server starts on loopback and answers a gRPC health check.
# Needs root (debootstrap, chroot), the archive, and umoci (installed if
# missing). Usage: deploy/oci/build-image.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/oci}
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
[ "$(id -u)" -eq 0 ] || { echo "build-image: needs root (debootstrap, chroot)" >&2; exit 2; }
for tool in debootstrap umoci; do
  command -v $tool >/dev/null || apt-get install -y -qq $tool >/dev/null
done
mkdir -p "$out"
deb=$(bash "$root/deploy/make-deb.sh" "$build" "$out")
rootfs="$out/rootfs"
mirror=$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -1)
[ -n "$mirror" ] || mirror=$(awk '/^deb /{print $2; exit}' /etc/apt/sources.list 2>/dev/null)
if [ ! -x "$rootfs/bin/bash" ]; then
  echo "build-image: debootstrap bookworm (minbase) from $mirror"
  debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$out/debootstrap.log" 2>&1
fi
cp "$deb" "$rootfs/tmp/hapsim.deb"
cp /etc/resolv.conf "$rootfs/etc/resolv.conf"
mount -t proc proc "$rootfs/proc"
trap 'umount "$rootfs/proc" 2>/dev/null || true' EXIT
chroot "$rootfs" /bin/sh -c '
  set -e
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends /tmp/hapsim.deb >/dev/null
  rm -f /tmp/hapsim.deb
  apt-get clean
  rm -rf /var/lib/apt/lists/*
  getent passwd hapsim >/dev/null || useradd --system --uid 10001 --user-group --home-dir /var/lib/hapsim hapsim
  mkdir -p /var/lib/hapsim && chown hapsim:hapsim /var/lib/hapsim
  hapsim-server --help >/dev/null'
umount "$rootfs/proc"
trap - EXIT
: >"$rootfs/etc/resolv.conf"
# The OCI image: one layer, the root above; the server as its entry point.
layout="$out/layout"
rm -rf "$layout" "$out/bundle"
umoci init --layout "$layout"
umoci new --image "$layout:$version"
umoci unpack --image "$layout:$version" "$out/bundle" >/dev/null
rm -rf "$out/bundle/rootfs" && mv "$rootfs" "$out/bundle/rootfs"
umoci repack --image "$layout:$version" "$out/bundle"
mv "$out/bundle/rootfs" "$rootfs"
umoci config --image "$layout:$version" --config.user 10001:10001 --config.workingdir /var/lib/hapsim \
  --config.entrypoint /usr/bin/hapsim-server --config.cmd --listen=0.0.0.0:50051 --config.cmd --data-dir=/var/lib/hapsim \
  --config.exposedports 50051/tcp --config.exposedports 9464/tcp --config.volume /var/lib/hapsim \
  --config.label org.opencontainers.image.title=hapsim --config.label "org.opencontainers.image.version=$version"
# The image's own root runs the server: unpacked by umoci, run in a chroot
# as the image's user, it serves and answers a health check.
check="$out/check" && rm -rf "$check"
umoci unpack --image "$layout:$version" "$check" >/dev/null
mount -t proc proc "$check/rootfs/proc"
trap 'umount "$check/rootfs/proc" 2>/dev/null || true' EXIT
chroot --userspec=10001:10001 "$check/rootfs" /usr/bin/hapsim-server --listen 127.0.0.1:0 --port-file /tmp/port \
  --data-dir /var/lib/hapsim --dds-domain 231 --log-level warn &
server=$!
for _ in $(seq 100); do [ -s "$check/rootfs/tmp/port" ] && break; sleep 0.1; done
port=$(cat "$check/rootfs/tmp/port" 2>/dev/null || true)
health=1
[ -n "$port" ] && chroot --userspec=10001:10001 "$check/rootfs" /usr/bin/hapsim-ctl --server "127.0.0.1:$port" health && health=0
kill "$server" 2>/dev/null; wait "$server" 2>/dev/null || true
umount "$check/rootfs/proc"
trap - EXIT
rm -rf "$check"
[ "$health" = 0 ] || { echo "build-image: the image's server did not start and answer" >&2; exit 1; }
echo "build-image: the image's server ran as uid 10001 and answered a health check on 127.0.0.1:$port"
tar -C "$layout" -cf "$out/hapsim-$version.oci.tar" .
echo "$out/hapsim-$version.oci.tar ($(du -h "$out/hapsim-$version.oci.tar" | cut -f1))"
