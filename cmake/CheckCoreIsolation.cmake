# Script mode: cmake -DDIR=<core dir> -P CheckCoreIsolation.cmake
set(_pattern "#[ \t]*include[ \t]*[<\"](grpc|grpcpp|dds/|ddsc|asio|spdlog|google/protobuf|boost/asio)")
file(GLOB_RECURSE _files ${DIR}/*.h ${DIR}/*.hpp ${DIR}/*.cpp ${DIR}/*.cc)
foreach(_f IN LISTS _files)
  file(STRINGS ${_f} _hits REGEX "${_pattern}")
  if(_hits)
    message(FATAL_ERROR "hapsim::core must link Eigen only, but ${_f} includes: ${_hits}")
  endif()
endforeach()
