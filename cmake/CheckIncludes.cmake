# Script mode: cmake -DRULES=<rules file> -P CheckIncludes.cmake
# The rules file (written by hapsim_forbid_includes) sets LAYER, DIRS,
# PATTERN (a regex of forbidden include targets) and ALLOW (exempt files,
# relative to the first of DIRS).
cmake_minimum_required(VERSION 3.25)  # script mode starts with no policies (IN_LIST)
include(${RULES})
list(GET DIRS 0 _base)
set(_line_regex "#[ \t]*include[ \t]*[<\"](${PATTERN})")
foreach(_dir IN LISTS DIRS)
  if(IS_DIRECTORY ${_dir})
    file(GLOB_RECURSE _files ${_dir}/*.h ${_dir}/*.hpp ${_dir}/*.cpp ${_dir}/*.cc)
  else()
    set(_files ${_dir})
  endif()
  foreach(_f IN LISTS _files)
    file(RELATIVE_PATH _rel ${_base} ${_f})
    if(_rel IN_LIST ALLOW)
      continue()
    endif()
    file(STRINGS ${_f} _hits REGEX "${_line_regex}")
    if(_hits)
      message(FATAL_ERROR "Layer violation: ${LAYER} may not include this (docs/architecture.md, \"Layers\"): "
                          "${_f}: ${_hits}")
    endif()
  endforeach()
endforeach()
