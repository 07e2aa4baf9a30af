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
#   the server, in layers (server/):
#   hapsim::runtime   core, common: sessions, registry, tick pool — no gRPC,
#                     no DDS, no TOML or OpenSSL
#   hapsim::device_link  runtime, dds, wire: the DDS adapter — no gRPC
#   hapsim::streaming runtime, proto, gRPC: frames for viewers — no DDS
#   hapsim::classroom runtime, toml++ and OpenSSL's crypto (class config,
#                     server directory, token hashes) — no gRPC, no
#                     protobuf, no DDS
#   hapsim::recording runtime + zstd: trial recordings (format, recorder,
#                     replay) — no gRPC, no DDS, no SQLite
#   hapsim::store     classroom + SQLite: the results database — no gRPC,
#                     no DDS
#   hapsim::api       the six above, proto, gRPC, prometheus-cpp's core
#                     (/metrics) — never the DDS wire types
#   hapsim::web       classroom, proto, gRPC, Boost.Beast, OpenSSL: the browser
#                     console's HTTPS/WebSocket, a gateway to the services
#                     over an in-process channel — no runtime internals,
#                     no DDS, never the services' code itself
#   hapsim::app       api, web: the server process
#   the device side, in layers (device-bridge/):
#   hapsim::servo     core (force-model law), common: devices, the servo
#                     tick, force safety — core types only, no DDS
#   hapsim::bridge    servo, dds, wire: the devices' DDS side — no gRPC
#   hapsim::load      bridge, nlohmann-json (hapsim-load's report) — no gRPC
#   hapsim::viewer    common, proto, gRPC client — no physics, no DDS, no export
#   hapsim::viewer_export  viewer + tinygltf: meshes to OBJ and glTF
#   hapsim::viewer_gui  viewer + GLFW, OpenGL/EGL, Dear ImGui, stb — rendering on
#                     top of the mesh cache; the cache and client never include GL
#   hapsim::netlab    common: the network lab's link emulation (TUN I/O,
#                     link models) — no simulation, no DDS, no gRPC
#   executables       their library; hapsim-load (to create sessions) and
#                     hapsim-bridge (--join: locate and join a session)
#                     add the viewer's gRPC client but never a server
#                     layer; hapsim-validate core + io.
include(HapsimLayers)

set(_net "grpc|grpcpp|dds/|ddsc|asio|spdlog|google/protobuf|boost/asio|haptics\\.h")
set(_server_layers "runtime|device_link|streaming|classroom|api|web|app")
set(_device_side "servo|bridge|load")
set(_std_os "(thread|mutex|shared_mutex|condition_variable|future|semaphore|stop_token|latch|barrier|chrono|ctime|fstream|iostream|istream|ostream|cstdio|stdio\\.h|filesystem)>")

# Includes.
hapsim_forbid_includes(hapsim::core TARGET hapsim_core DIRS ${PROJECT_SOURCE_DIR}/core
  PATTERN "${_net}|hapsim/(common|dds|io|${_server_layers}|${_device_side}|viewer|v1)/|${_std_os}"
  ALLOW src/assert.cpp)  # the one line the core writes: a failed check, before abort()
hapsim_forbid_includes(hapsim::io TARGET hapsim_io DIRS ${PROJECT_SOURCE_DIR}/io
  PATTERN "${_net}|hapsim/(common|dds|${_server_layers}|${_device_side}|viewer|v1)/")
if(NOT HAPSIM_CORE_ONLY)
  hapsim_forbid_includes(hapsim::common TARGET hapsim_common DIRS ${PROJECT_SOURCE_DIR}/common
    PATTERN "grpc|grpcpp|dds/|ddsc|google/protobuf|haptics\\.h|hapsim/(core|dds|io|${_server_layers}|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::dds TARGET hapsim_dds DIRS ${PROJECT_SOURCE_DIR}/dds
    PATTERN "grpc|grpcpp|google/protobuf|asio|hapsim/(core|io|${_server_layers}|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::wire TARGET hapsim_wire DIRS ${PROJECT_SOURCE_DIR}/wire
    PATTERN "grpc|grpcpp|google/protobuf|asio|spdlog|dds/dds\\.h|hapsim/(common|dds|io|${_server_layers}|${_device_side}|viewer|v1)/|${_std_os}")
  # The server's layers: each names only those below it.
  set(_not_server_extras "toml|openssl|prometheus")
  hapsim_forbid_includes(hapsim::runtime TARGET hapsim_runtime DIRS ${PROJECT_SOURCE_DIR}/server/runtime
    PATTERN "grpc|grpcpp|google/protobuf|dds/|ddsc|haptics\\.h|asio|${_not_server_extras}|hapsim/(io|dds|wire|device_link|streaming|classroom|api|app|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::device_link TARGET hapsim_device_link DIRS ${PROJECT_SOURCE_DIR}/server/device_link
    PATTERN "grpc|grpcpp|google/protobuf|asio|${_not_server_extras}|hapsim/(io|streaming|classroom|api|app|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::streaming TARGET hapsim_streaming DIRS ${PROJECT_SOURCE_DIR}/server/streaming
    PATTERN "dds/|ddsc|haptics\\.h|${_not_server_extras}|hapsim/(io|dds|wire|device_link|classroom|api|app|${_device_side}|viewer)/")
  hapsim_forbid_includes(hapsim::classroom TARGET hapsim_classroom DIRS ${PROJECT_SOURCE_DIR}/server/classroom
    PATTERN "grpc|grpcpp|google/protobuf|dds/|ddsc|haptics\\.h|asio|prometheus|hapsim/(io|dds|wire|device_link|streaming|api|app|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::recording TARGET hapsim_recording DIRS ${PROJECT_SOURCE_DIR}/server/recording
    PATTERN "grpc|grpcpp|google/protobuf|dds/|ddsc|haptics\\.h|asio|sqlite|${_not_server_extras}|hapsim/(io|dds|wire|device_link|streaming|classroom|store|api|app|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::store TARGET hapsim_store DIRS ${PROJECT_SOURCE_DIR}/server/store
    PATTERN "grpc|grpcpp|google/protobuf|dds/|ddsc|haptics\\.h|asio|zstd|prometheus|hapsim/(io|dds|wire|device_link|streaming|recording|api|app|${_device_side}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::api TARGET hapsim_api DIRS ${PROJECT_SOURCE_DIR}/server/api
    PATTERN "haptics\\.h|toml|openssl|hapsim/(io|wire|app|${_device_side}|viewer)/")
  hapsim_forbid_includes(hapsim::web TARGET hapsim_web DIRS ${PROJECT_SOURCE_DIR}/server/web
    PATTERN "dds/|ddsc|haptics\\.h|toml|sqlite|zstd|prometheus|[<]asio/|hapsim/(core|io|dds|wire|device_link|streaming|recording|store|api|app|${_device_side}|viewer)/")
  hapsim_forbid_includes(hapsim::app TARGET hapsim_app DIRS ${PROJECT_SOURCE_DIR}/server/app
    PATTERN "haptics\\.h|hapsim/(io|wire|${_device_side}|viewer)/")
  hapsim_forbid_includes(hapsim::servo TARGET hapsim_servo
    DIRS ${PROJECT_SOURCE_DIR}/device-bridge/servo ${PROJECT_SOURCE_DIR}/device-bridge/backends
    PATTERN "grpc|grpcpp|google/protobuf|dds/|ddsc|haptics\\.h|hapsim/(io|dds|wire|${_server_layers}|bridge|load|viewer|v1)/")
  hapsim_forbid_includes(hapsim::bridge TARGET hapsim_bridge
    DIRS ${PROJECT_SOURCE_DIR}/device-bridge/dds ${PROJECT_SOURCE_DIR}/device-bridge/main.cpp
    PATTERN "grpc|grpcpp|google/protobuf|hapsim/(io|${_server_layers}|load|viewer|v1)/")
  hapsim_forbid_includes(hapsim::load TARGET hapsim_load
    DIRS ${PROJECT_SOURCE_DIR}/device-bridge/load/include ${PROJECT_SOURCE_DIR}/device-bridge/load/src
    PATTERN "grpc|grpcpp|google/protobuf|haptics\\.h|hapsim/(io|wire|${_server_layers}|viewer|v1)/")
  hapsim_forbid_includes(hapsim::viewer TARGET hapsim_viewer DIRS ${PROJECT_SOURCE_DIR}/client-viewer
    PATTERN "dds/|ddsc|haptics\\.h|hapsim/(core|dds|io|${_server_layers}|servo|bridge|load)/")
  hapsim_forbid_includes(hapsim::netlab TARGET hapsim_netlab DIRS ${PROJECT_SOURCE_DIR}/netlab
    PATTERN "${_net}|hapsim/(core|io|dds|wire|${_server_layers}|${_device_side}|viewer|v1)/")
  # The mesh cache and gRPC client stay free of rendering and of file export.
  hapsim_forbid_includes(hapsim::viewer_client_only
    DIRS ${PROJECT_SOURCE_DIR}/client-viewer/include ${PROJECT_SOURCE_DIR}/client-viewer/src
    PATTERN "GL/|GLFW/|EGL/|imgui|stb/|tiny_gltf|hapsim/gui/|mesh_export\\.h")
endif()

# Links (transitive).
set(_core hapsim_core Eigen3::Eigen)
set(_common hapsim_common spdlog::spdlog)
set(_dds hapsim_dds hapsim_dds_types CycloneDDS::ddsc ${_common})
set(_proto hapsim_proto protobuf::libprotobuf gRPC::grpc++ gRPC::grpc)
set(_viewer hapsim_viewer ${_proto} ${_common} Eigen3::Eigen)
set(_viewer_export hapsim_viewer_export ${_viewer} TinyGLTF::TinyGLTF)
set(_wire hapsim_wire ${_core} hapsim_dds_types CycloneDDS::ddsc)
set(_servo hapsim_servo ${_core} ${_common})
set(_bridge hapsim_bridge ${_servo} ${_dds} ${_wire})
set(_load hapsim_load ${_bridge} nlohmann_json::nlohmann_json)
hapsim_layer_allows(hapsim_core Eigen3::Eigen)
hapsim_layer_allows(hapsim_io ${_core})
hapsim_layer_allows(hapsim_common spdlog::spdlog)
hapsim_layer_allows(hapsim_dds_types CycloneDDS::ddsc)
hapsim_layer_allows(hapsim_dds ${_dds})
hapsim_layer_allows(hapsim_proto ${_proto})
hapsim_layer_allows(hapsim_wire ${_wire})
set(_runtime hapsim_runtime ${_core} ${_common})
set(_device_link hapsim_device_link ${_runtime} ${_dds} ${_wire})
set(_streaming hapsim_streaming ${_runtime} ${_proto})
set(_classroom hapsim_classroom ${_runtime})
set(_recording hapsim_recording ${_runtime} zstd::libzstd_shared)
set(_store hapsim_store ${_classroom} SQLite::SQLite3)
set(_api hapsim_api ${_device_link} ${_streaming} ${_classroom} ${_recording} ${_store} prometheus-cpp::core)
hapsim_layer_allows(hapsim_runtime ${_runtime})
hapsim_layer_allows(hapsim_device_link ${_device_link})
hapsim_layer_allows(hapsim_streaming ${_streaming})
hapsim_layer_allows(hapsim_classroom ${_classroom})
hapsim_layer_allows(hapsim_recording ${_recording})
hapsim_layer_allows(hapsim_store ${_store})
hapsim_layer_allows(hapsim_api ${_api})
set(_web hapsim_web ${_classroom} ${_proto} Boost::headers)
hapsim_layer_allows(hapsim_web ${_web})
hapsim_layer_allows(hapsim_app hapsim_app ${_api} ${_web})
hapsim_layer_allows(hapsim_servo ${_servo})
hapsim_layer_allows(hapsim_bridge ${_bridge})
hapsim_layer_allows(hapsim_load ${_load})
hapsim_layer_allows(hapsim_viewer ${_viewer})
hapsim_layer_allows(hapsim_viewer_export ${_viewer_export})
hapsim_layer_allows(hapsim-server hapsim_app ${_api} ${_web})
hapsim_layer_allows(hapsim-bridge ${_bridge} ${_viewer})
hapsim_layer_allows(hapsim-load ${_load} ${_viewer})
if(HAPSIM_WITH_VIEWER_GUI)
  hapsim_layer_allows(hapsim_viewer_gui ${_viewer_export})
endif()
hapsim_layer_allows(hapsim-viewer ${_viewer_export} hapsim_viewer_gui)
hapsim_layer_allows(hapsim-ctl ${_viewer_export})
hapsim_layer_allows(hapsim-validate hapsim_io ${_core})
hapsim_layer_allows(hapsim_netlab ${_common})
hapsim_layer_allows(hapsim-linkem hapsim_netlab ${_common} nlohmann_json::nlohmann_json)
hapsim_check_layers()
