# hapsim_check_core_isolation(dir): fail the build if hapsim::core (pure
# simulation, Eigen only) includes any I/O library header. Runs at configure
# time and again as a build step, so a new include breaks the very next build.
function(hapsim_check_core_isolation target dir)
  set(_pattern "#[ \t]*include[ \t]*[<\"](grpc|grpcpp|dds/|ddsc|asio|spdlog|google/protobuf|boost/asio)")
  file(GLOB_RECURSE _files ${dir}/*.h ${dir}/*.hpp ${dir}/*.cpp ${dir}/*.cc)
  foreach(_f IN LISTS _files)
    file(STRINGS ${_f} _hits REGEX "${_pattern}")
    if(_hits)
      message(FATAL_ERROR "hapsim::core must link Eigen only, but ${_f} includes: ${_hits}")
    endif()
  endforeach()
  add_custom_target(${target}_isolation_check
    COMMAND ${CMAKE_COMMAND} -DDIR=${dir} -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/CheckCoreIsolation.cmake
    COMMENT "Checking that hapsim::core includes no I/O library")
  add_dependencies(${target} ${target}_isolation_check)
endfunction()
