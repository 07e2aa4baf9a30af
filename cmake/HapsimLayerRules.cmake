# The layers of hapsim and what each may use — the graph drawn in
# docs/architecture.md ("Layers"), checked here on every configure and
# (includes) before every build of a layer. Included at the end of the
# top-level CMakeLists.txt, once every target exists.
#
#   hapsim::core      Eigen only; no threads, clocks or I/O of any kind
#   hapsim::io        core (files in, arrays out)
#   hapsim::common    spdlog, threads (flags, logging, clocks, mailboxes)
#   hapsim::dds       common + Cyclone DDS (+ the generated DDS types)
#   hapsim::wire      core + the generated DDS types: the only converters
#                     between the topics' IDL structs and core types
#   hapsim::proto     protobuf + gRPC (generated code)
#   hapsim::service   core, common, dds, proto, gRPC, toml++ and OpenSSL's
#                     crypto (class config, token hashes), prometheus-cpp's
#                     core (/metrics) — the server
#   hapsim::bridge    core (force-model law), common, dds, nlohmann-json
#                     (hapsim-load's report) — no gRPC at all
#   hapsim::viewer    common, proto, gRPC client, tinygltf (export) — no physics, no DDS
#   hapsim::viewer_gui  viewer + GLFW, OpenGL/EGL, Dear ImGui, stb — rendering on
#                     top of the mesh cache; the cache and client never include GL
#   executables       their library; hapsim-load adds the viewer's gRPC
#                     client (to create sessions) but never the server's
#                     service library; hapsim-validate core + io.
include(HapsimLayers)

set(_net "grpc|grpcpp|dds/|ddsc|asio|spdlog|google/protobuf|boost/asio|haptics\\.h")
set(_std_os "(thread|mutex|shared_mutex|condition_variable|future|semaphore|stop_token|latch|barrier|chrono|ctime|fstream|iostream|istream|ostream|cstdio|stdio\\.h|filesystem)>")

# Includes.
hapsim_forbid_includes(hapsim::core TARGET hapsim_core DIRS ${PROJECT_SOURCE_DIR}/core
  PATTERN "${_net}|hapsim/(common|dds|io|service|bridge|viewer|v1)/|${_std_os}"
  ALLOW src/assert.cpp)  # the one line the core writes: a failed check, before abort()
hapsim_forbid_includes(hapsim::io TARGET hapsim_io DIRS ${PROJECT_SOURCE_DIR}/io
  PATTERN "${_net}|hapsim/(common|dds|service|bridge|viewer|v1)/")
if(NOT HAPSIM_CORE_ONLY)
  hapsim_forbid_includes(hapsim::common TARGET hapsim_common DIRS ${PROJECT_SOURCE_DIR}/common
    PATTERN "grpc|grpcpp|dds/|ddsc|google/protobuf|haptics\\.h|hapsim/(core|dds|io|service|bridge|viewer|v1)/")
  hapsim_forbid_includes(hapsim::dds TARGET hapsim_dds DIRS ${PROJECT_SOURCE_DIR}/dds
    PATTERN "grpc|grpcpp|google/protobuf|asio|hapsim/(core|io|service|bridge|viewer|v1)/")
  hapsim_forbid_includes(hapsim::wire TARGET hapsim_wire DIRS ${PROJECT_SOURCE_DIR}/wire
    PATTERN "grpc|grpcpp|google/protobuf|asio|spdlog|dds/dds\\.h|hapsim/(common|dds|io|service|bridge|viewer|v1)/|${_std_os}")
  hapsim_forbid_includes(hapsim::service TARGET hapsim_service DIRS ${PROJECT_SOURCE_DIR}/server/service
    PATTERN "hapsim/(bridge|viewer)/")
  hapsim_forbid_includes(hapsim::bridge TARGET hapsim_bridge
    DIRS ${PROJECT_SOURCE_DIR}/device-bridge/include ${PROJECT_SOURCE_DIR}/device-bridge/src
         ${PROJECT_SOURCE_DIR}/device-bridge/backends ${PROJECT_SOURCE_DIR}/device-bridge/main.cpp
    PATTERN "grpc|grpcpp|google/protobuf|hapsim/(io|service|viewer|v1)/")
  hapsim_forbid_includes(hapsim::viewer TARGET hapsim_viewer DIRS ${PROJECT_SOURCE_DIR}/client-viewer
    PATTERN "dds/|ddsc|haptics\\.h|hapsim/(core|dds|io|service|bridge)/")
  # The mesh cache and gRPC client stay free of rendering.
  hapsim_forbid_includes(hapsim::viewer_without_gl
    DIRS ${PROJECT_SOURCE_DIR}/client-viewer/include ${PROJECT_SOURCE_DIR}/client-viewer/src
    PATTERN "GL/|GLFW/|EGL/|imgui|stb/|hapsim/gui/")
endif()

# Links (transitive).
set(_core hapsim_core Eigen3::Eigen)
set(_common hapsim_common spdlog::spdlog)
set(_dds hapsim_dds hapsim_dds_types CycloneDDS::ddsc ${_common})
set(_proto hapsim_proto protobuf::libprotobuf gRPC::grpc++ gRPC::grpc)
set(_viewer hapsim_viewer ${_proto} ${_common} Eigen3::Eigen TinyGLTF::TinyGLTF)
set(_wire hapsim_wire ${_core} hapsim_dds_types CycloneDDS::ddsc)
set(_bridge hapsim_bridge ${_core} ${_dds} ${_wire} nlohmann_json::nlohmann_json)
hapsim_layer_allows(hapsim_core Eigen3::Eigen)
hapsim_layer_allows(hapsim_io ${_core})
hapsim_layer_allows(hapsim_common spdlog::spdlog)
hapsim_layer_allows(hapsim_dds_types CycloneDDS::ddsc)
hapsim_layer_allows(hapsim_dds ${_dds})
hapsim_layer_allows(hapsim_proto ${_proto})
hapsim_layer_allows(hapsim_wire ${_wire})
set(_service_extras tomlplusplus::tomlplusplus OpenSSL::Crypto prometheus-cpp::core)
hapsim_layer_allows(hapsim_service hapsim_service ${_core} ${_dds} ${_wire} ${_proto} ${_service_extras})
hapsim_layer_allows(hapsim_bridge ${_bridge})
hapsim_layer_allows(hapsim_viewer ${_viewer})
hapsim_layer_allows(hapsim-server hapsim_service ${_core} ${_dds} ${_wire} ${_proto} ${_service_extras})
hapsim_layer_allows(hapsim-bridge ${_bridge})
hapsim_layer_allows(hapsim-load ${_bridge} ${_viewer})
if(HAPSIM_WITH_VIEWER_GUI)
  hapsim_layer_allows(hapsim_viewer_gui ${_viewer})
endif()
hapsim_layer_allows(hapsim-viewer ${_viewer} hapsim_viewer_gui)
hapsim_layer_allows(hapsim-ctl ${_viewer})
hapsim_layer_allows(hapsim-validate hapsim_io ${_core})
hapsim_check_layers()
