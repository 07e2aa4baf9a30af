#!/usr/bin/env bash
# Proves the layer rules (cmake/HapsimLayerRules.cmake) fail the configure
# on a violation, for both kinds of check: a probe project with the real
# rule files, stub targets named like ours and a stub source tree is
# configured once clean (must pass) and once per injected violation (must
# fail naming it). Bounded: ~1 s per configure, all in a temp directory.
#   tests/build/layer_rules_probe.sh SOURCE_DIR WORK_DIR
set -euo pipefail
src=$(cd "${1:?usage: $0 SOURCE_DIR WORK_DIR}" && pwd)
work=${2:?usage: $0 SOURCE_DIR WORK_DIR}
rm -rf "$work" && mkdir -p "$work"
failures=0

# make_tree DIR: the stub tree — real rule files, one clean source per layer.
make_tree() {
  local t=$1
  mkdir -p "$t/cmake" "$t/core/src" "$t/io/src" "$t/common/src" "$t/dds/src" "$t/wire/src" \
           "$t/server/runtime/src" "$t/server/device_link/src" "$t/server/streaming/src" "$t/server/classroom/src" \
           "$t/server/api/src" "$t/server/web/src" "$t/server/app/src" "$t/server/recording/src" "$t/server/store/src" \
           "$t/device-bridge/servo/src" "$t/device-bridge/backends" "$t/device-bridge/dds/src" \
           "$t/device-bridge/load/src" "$t/client-viewer/src" "$t/netlab/src"
  cp "$src/cmake/HapsimLayers.cmake" "$src/cmake/HapsimLayerRules.cmake" "$src/cmake/CheckIncludes.cmake" "$t/cmake/"
  echo '#include <Eigen/Core>' >"$t/core/src/step.cpp"
  printf '#include <cstdio>\n#include <cstdlib>\n' >"$t/core/src/assert.cpp"  # the one allowed writer
  echo '#include <fstream>' >"$t/io/src/reader.cpp"
  echo '#include <spdlog/spdlog.h>' >"$t/common/src/logging.cpp"
  echo '#include <dds/dds.h>' >"$t/dds/src/dds.cpp"
  printf '#include "haptics.h"\n#include "hapsim/core/haptics/local_force_model.h"\n' >"$t/wire/src/topics_wire.cpp"
  printf '#include <mutex>\n#include "hapsim/core/scenes/scene.h"\n' >"$t/server/runtime/src/session.cpp"
  printf '#include "hapsim/dds/dds.h"\n#include "hapsim/wire/topics_wire.h"\n' >"$t/server/device_link/src/server_dds.cpp"
  echo '#include <grpcpp/grpcpp.h>' >"$t/server/streaming/src/viewer_link.cpp"
  echo '#include <toml++/toml.hpp>' >"$t/server/classroom/src/class_config.cpp"
  printf '#include <zstd.h>\n#include "hapsim/runtime/tick_input.h"\n' >"$t/server/recording/src/recording_format.cpp"
  printf '#include <sqlite3.h>\n#include "hapsim/classroom/trial_book.h"\n' >"$t/server/store/src/results_store.cpp"
  printf '#include <grpcpp/grpcpp.h>\n#include "hapsim/classroom/trial_book.h"\n' >"$t/server/api/src/session_service.cpp"
  printf '#include <boost/beast/websocket.hpp>\n#include "hapsim/classroom/access_policy.h"\n' >"$t/server/web/src/web_console.cpp"
  echo '#include "hapsim/api/session_service.h"' >"$t/server/app/src/server_app.cpp"
  echo '#include "hapsim/core/haptics/local_force_model.h"' >"$t/device-bridge/servo/src/servo_channel.cpp"
  echo '#include "hapsim/dds/dds.h"' >"$t/device-bridge/dds/src/device_dds.cpp"
  echo '#include "hapsim/bridge/model_router.h"' >"$t/device-bridge/load/src/load_runner.cpp"
  echo '#include <asio/signal_set.hpp>' >"$t/device-bridge/main.cpp"
  echo '#include <grpcpp/grpcpp.h>' >"$t/client-viewer/src/client.cpp"
  printf '#include <linux/if_tun.h>\n#include "hapsim/common/flags.h"\n' >"$t/netlab/src/tun.cpp"
  cat >"$t/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(layer_probe NONE)
list(APPEND CMAKE_MODULE_PATH ${CMAKE_CURRENT_SOURCE_DIR}/cmake)
set(HAPSIM_CORE_ONLY OFF)
# Stub externals and stub targets with our names and our real link graph.
foreach(ext Eigen3::Eigen spdlog::spdlog CycloneDDS::ddsc protobuf::libprotobuf gRPC::grpc gRPC::grpc++
           zstd::libzstd_shared SQLite::SQLite3 Boost::headers)
  add_library(${ext} INTERFACE IMPORTED)
endforeach()
target_link_libraries(gRPC::grpc++ INTERFACE gRPC::grpc)
foreach(t hapsim_core hapsim_io hapsim_common hapsim_dds_types hapsim_dds hapsim_wire hapsim_proto
          hapsim_runtime hapsim_device_link hapsim_streaming hapsim_classroom hapsim_recording hapsim_store
          hapsim_api hapsim_web hapsim_app
          hapsim_servo hapsim_bridge hapsim_load hapsim_viewer hapsim_viewer_export hapsim_netlab)
  add_library(${t} INTERFACE)
endforeach()
foreach(t hapsim-server hapsim-bridge hapsim-load hapsim-viewer hapsim-ctl hapsim-validate)
  add_custom_target(${t})
endforeach()
function(link t)
  target_link_libraries(${t} INTERFACE ${ARGN})
endfunction()
link(hapsim_core Eigen3::Eigen)
link(hapsim_io hapsim_core)
link(hapsim_common spdlog::spdlog)
link(hapsim_dds_types CycloneDDS::ddsc)
link(hapsim_dds hapsim_common hapsim_dds_types)
link(hapsim_proto protobuf::libprotobuf gRPC::grpc++)
link(hapsim_wire hapsim_core hapsim_dds_types)
link(hapsim_runtime hapsim_core hapsim_common)
link(hapsim_device_link hapsim_runtime hapsim_dds hapsim_wire)
link(hapsim_streaming hapsim_runtime hapsim_proto gRPC::grpc++)
link(hapsim_classroom hapsim_runtime)
link(hapsim_recording hapsim_runtime zstd::libzstd_shared)
link(hapsim_store hapsim_classroom SQLite::SQLite3)
link(hapsim_api hapsim_device_link hapsim_streaming hapsim_classroom hapsim_recording hapsim_store)
link(hapsim_web hapsim_classroom hapsim_proto gRPC::grpc++ Boost::headers)
link(hapsim_app hapsim_api hapsim_web)
link(hapsim_servo hapsim_core hapsim_common)
link(hapsim_bridge hapsim_servo hapsim_dds hapsim_wire)
link(hapsim_load hapsim_bridge)
link(hapsim_viewer hapsim_proto hapsim_common gRPC::grpc++ Eigen3::Eigen)
link(hapsim_viewer_export hapsim_viewer)
link(hapsim_netlab hapsim_common)
include(${CMAKE_CURRENT_SOURCE_DIR}/probe.cmake OPTIONAL)  # the injected violation, if any
include(HapsimLayerRules)
CMAKE
}

# expect NAME pass|fail [MESSAGE-REGEX] [SETUP-COMMAND...]
expect() {
  local name=$1 want=$2 regex=$3; shift 3
  local t="$work/$name"
  make_tree "$t"
  (cd "$t" && "$@")
  local rc=0
  cmake -S "$t" -B "$t/build" >"$t/configure.log" 2>&1 || rc=$?
  # CMake wraps long messages: one line, single spaces, for the regex.
  tr '\n' ' ' <"$t/configure.log" | tr -s ' ' >"$t/configure.txt"
  if [ "$want" = pass ] && [ $rc -eq 0 ]; then
    echo "ok   $name: configures"
  elif [ "$want" = fail ] && [ $rc -ne 0 ] && grep -Eq "$regex" "$t/configure.txt"; then
    echo "ok   $name: refused (...$(grep -Eo "$regex" "$t/configure.txt" | head -1 | rev | cut -c1-90 | rev))"
  else
    echo "FAIL $name: wanted $want${regex:+ /$regex/}, configure exit $rc"; sed 's/^/     /' "$t/configure.log" | tail -8
    failures=$((failures + 1))
  fi
}

expect clean pass "" true
expect core_includes_thread fail "hapsim::core may not include.*<thread>" \
  sh -c 'echo "#include <thread>" >>core/src/step.cpp'
expect core_includes_fstream fail "hapsim::core may not include.*<fstream>" \
  sh -c 'echo "#include <fstream>" >core/src/mesh_file.cpp'
expect core_includes_the_clock fail "hapsim::core may not include.*<chrono>" \
  sh -c 'echo "#include <chrono>" >>core/src/step.cpp'
expect core_includes_common fail "hapsim::core may not include.*hapsim/common/" \
  sh -c 'echo "#include \"hapsim/common/clock.h\"" >>core/src/step.cpp'
expect core_includes_dds fail "hapsim::core may not include.*dds/dds.h" \
  sh -c 'echo "#include <dds/dds.h>" >>core/src/step.cpp'
expect bridge_includes_grpc fail "hapsim::bridge may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>device-bridge/dds/src/device_dds.cpp'
expect viewer_includes_server fail "hapsim::viewer may not include.*hapsim/runtime/" \
  sh -c 'echo "#include \"hapsim/runtime/session.h\"" >>client-viewer/src/client.cpp'
expect common_includes_dds fail "hapsim::common may not include.*haptics" \
  sh -c 'echo "#include \"haptics.h\"" >>common/src/logging.cpp'
expect core_links_common fail "hapsim_core links hapsim_common" \
  sh -c 'echo "link(hapsim_core hapsim_common)" >probe.cmake'
expect viewer_links_server fail "hapsim_viewer links hapsim_(app|api|runtime)" \
  sh -c 'echo "link(hapsim_viewer hapsim_app)" >probe.cmake'
expect viewer_links_core_through_another fail "hapsim-viewer links hapsim_(io|core)" \
  sh -c 'echo "add_library(viewer_helper INTERFACE)
link(viewer_helper hapsim_io)
add_dependencies(hapsim-viewer viewer_helper)
set_property(TARGET hapsim-viewer PROPERTY INTERFACE_LINK_LIBRARIES viewer_helper)" >probe.cmake'
expect bridge_links_grpc fail "hapsim_bridge links gRPC::grpc" \
  sh -c 'echo "link(hapsim_bridge gRPC::grpc++)" >probe.cmake'
expect dds_links_proto fail "hapsim_dds links hapsim_proto" \
  sh -c 'echo "link(hapsim_dds hapsim_proto)" >probe.cmake'
expect wire_includes_dds_api fail "hapsim::wire may not include.*dds/dds.h" \
  sh -c 'echo "#include <dds/dds.h>" >>wire/src/topics_wire.cpp'
expect wire_includes_common fail "hapsim::wire may not include.*hapsim/common/" \
  sh -c 'echo "#include \"hapsim/common/clock.h\"" >>wire/src/topics_wire.cpp'
expect wire_links_common fail "hapsim_wire links hapsim_common" \
  sh -c 'echo "link(hapsim_wire hapsim_common)" >probe.cmake'

# The server's layers and the device side's.
expect runtime_includes_grpc fail "hapsim::runtime may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>server/runtime/src/session.cpp'
expect runtime_includes_dds fail "hapsim::runtime may not include.*hapsim/dds/" \
  sh -c 'echo "#include \"hapsim/dds/dds.h\"" >>server/runtime/src/session.cpp'
expect runtime_includes_classroom fail "hapsim::runtime may not include.*hapsim/classroom/" \
  sh -c 'echo "#include \"hapsim/classroom/trial_tracker.h\"" >>server/runtime/src/session.cpp'
expect runtime_links_dds fail "hapsim_runtime links hapsim_dds" \
  sh -c 'echo "link(hapsim_runtime hapsim_dds)" >probe.cmake'
expect device_link_includes_grpc fail "hapsim::device_link may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>server/device_link/src/server_dds.cpp'
expect device_link_links_proto fail "hapsim_device_link links hapsim_proto" \
  sh -c 'echo "link(hapsim_device_link hapsim_proto)" >probe.cmake'
expect streaming_includes_dds fail "hapsim::streaming may not include.*dds/dds.h" \
  sh -c 'echo "#include <dds/dds.h>" >>server/streaming/src/viewer_link.cpp'
expect streaming_links_dds fail "hapsim_streaming links hapsim_dds" \
  sh -c 'echo "link(hapsim_streaming hapsim_dds)" >probe.cmake'
expect classroom_includes_grpc fail "hapsim::classroom may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>server/classroom/src/class_config.cpp'
expect classroom_includes_streaming fail "hapsim::classroom may not include.*hapsim/streaming/" \
  sh -c 'echo "#include \"hapsim/streaming/viewer_hub.h\"" >>server/classroom/src/class_config.cpp'
expect classroom_links_proto fail "hapsim_classroom links hapsim_proto" \
  sh -c 'echo "link(hapsim_classroom hapsim_proto)" >probe.cmake'
expect recording_includes_sqlite fail "hapsim::recording may not include.*sqlite3.h" \
  sh -c 'echo "#include <sqlite3.h>" >>server/recording/src/recording_format.cpp'
expect recording_links_sqlite fail "hapsim_recording links SQLite::SQLite3" \
  sh -c 'echo "link(hapsim_recording SQLite::SQLite3)" >probe.cmake'
expect store_includes_grpc fail "hapsim::store may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>server/store/src/results_store.cpp'
expect store_links_proto fail "hapsim_store links hapsim_proto" \
  sh -c 'echo "link(hapsim_store hapsim_proto)" >probe.cmake'
expect web_includes_api fail "hapsim::web may not include.*hapsim/api/" \
  sh -c 'echo "#include \"hapsim/api/session_service.h\"" >>server/web/src/web_console.cpp'
expect web_includes_dds fail "hapsim::web may not include.*dds/dds.h" \
  sh -c 'echo "#include <dds/dds.h>" >>server/web/src/web_console.cpp'
expect web_links_api fail "hapsim_web links hapsim_api" \
  sh -c 'echo "link(hapsim_web hapsim_api)" >probe.cmake'
expect api_includes_wire_types fail "hapsim::api may not include.*haptics" \
  sh -c 'echo "#include \"haptics.h\"" >>server/api/src/session_service.cpp'
expect api_includes_app fail "hapsim::api may not include.*hapsim/app/" \
  sh -c 'echo "#include \"hapsim/app/server_app.h\"" >>server/api/src/session_service.cpp'
expect servo_includes_dds fail "hapsim::servo may not include.*hapsim/dds/" \
  sh -c 'echo "#include \"hapsim/dds/dds.h\"" >>device-bridge/servo/src/servo_channel.cpp'
expect servo_includes_wire_types fail "hapsim::servo may not include.*haptics" \
  sh -c 'echo "#include \"haptics.h\"" >>device-bridge/servo/src/servo_channel.cpp'
expect servo_links_dds fail "hapsim_servo links hapsim_dds" \
  sh -c 'echo "link(hapsim_servo hapsim_dds)" >probe.cmake'
expect netlab_includes_core fail "hapsim::netlab may not include.*hapsim/core/" \
  sh -c 'echo "#include \"hapsim/core/scenes/scene.h\"" >>netlab/src/tun.cpp'
expect netlab_links_dds fail "hapsim_netlab links hapsim_dds" \
  sh -c 'echo "link(hapsim_netlab hapsim_dds)" >probe.cmake'
expect load_includes_grpc fail "hapsim::load may not include.*grpcpp" \
  sh -c 'echo "#include <grpcpp/grpcpp.h>" >>device-bridge/load/src/load_runner.cpp'
expect load_links_grpc fail "hapsim_load links gRPC::grpc" \
  sh -c 'echo "link(hapsim_load gRPC::grpc++)" >probe.cmake'

expect viewer_client_includes_gltf fail "hapsim::viewer_client_only may not include.*tiny_gltf" \
  sh -c 'echo "#include <tiny_gltf.h>" >>client-viewer/src/client.cpp'
expect load_links_export fail "hapsim-load links hapsim_viewer_export" \
  sh -c 'echo "set_property(TARGET hapsim-load PROPERTY INTERFACE_LINK_LIBRARIES hapsim_viewer_export)" >probe.cmake'

echo "$failures failed"
[ $failures -eq 0 ]
