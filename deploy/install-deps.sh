#!/usr/bin/env bash
# Installs hapsim's build and test dependencies from Debian 12 packages.
# Idempotent: skips apt entirely when everything is already installed.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  ccache  # a clean clone compiles only what changed since the last build (cmake/HapsimCompilerCache.cmake)
  libeigen3-dev libasio-dev libspdlog-dev
  libprotobuf-dev protobuf-compiler libgrpc++-dev protobuf-compiler-grpc
  cyclonedds-dev cyclonedds-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  libtomlplusplus-dev libssl-dev openssl libtinygltf-dev nlohmann-json3-dev prometheus-cpp-dev
  libzstd-dev libsqlite3-dev  # trial recordings (zstd blocks), the results database
  python3 python3-scipy python3-numpy python3-grpcio python3-yaml curl
  iproute2  # the network lab (netlab/netlab.sh): ip netns, TUN devices
  yamllint  # the Kubernetes manifests' check (tests/install/check_k8s.py)
  file      # CPack's DEB generator reads the programs' type before dpkg-shlibdeps (deploy/make-deb.sh)
  clang libfuzzer-14-dev libclang-rt-14-dev
  libglfw3-dev libgl-dev libopengl-dev libegl-dev libgl1-mesa-dri libegl-mesa0 libimgui-dev libstb-dev xvfb xauth
  libboost-dev  # Boost.Beast: the web console's HTTPS/WebSocket
  nodejs chromium firefox-esr  # the web console: its bundle is built with Node.js; its tests drive Chromium and Firefox
)
# npm comes with some Node.js builds (NodeSource's) and is Debian's own package otherwise.
command -v npm >/dev/null 2>&1 || packages+=(npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo_cmd apt-get update -qq
$sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
