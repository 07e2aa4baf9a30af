# hapsim_check_core_isolation(target dir): fail the build if hapsim::core
# (pure simulation, Eigen only) includes any I/O library header. The check
# (CheckCoreIsolation.cmake) runs at configure time and again before every
# build of the target, so a new include breaks the very next build.
set(HAPSIM_CORE_ISOLATION_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/CheckCoreIsolation.cmake)
function(hapsim_check_core_isolation target dir)
  set(DIR ${dir})
  include(${HAPSIM_CORE_ISOLATION_SCRIPT})
  add_custom_target(${target}_isolation_check
    COMMAND ${CMAKE_COMMAND} -DDIR=${dir} -P ${HAPSIM_CORE_ISOLATION_SCRIPT}
    COMMENT "Checking that hapsim::core includes no I/O library")
  add_dependencies(${target} ${target}_isolation_check)
endfunction()
