# The allowed dependency graph, enforced by the build (docs/architecture.md,
# "Layers"). Two checks:
#
#  hapsim_forbid_includes(LAYER DIRS ... PATTERN regex [ALLOW files...])
#     fails the configure, and the very next build of the layer, if a source
#     file under DIRS has an #include line matching PATTERN (files in ALLOW,
#     relative to the first DIR, are exempt). Script: CheckIncludes.cmake.
#
#  hapsim_layer_allows(target dep...) + hapsim_check_layers()
#     after every target is defined, walks each declared target's link
#     closure (LINK_LIBRARIES and INTERFACE_LINK_LIBRARIES, transitively)
#     and fails the configure if it reaches a watched library that is not in
#     its allowed list. Watched: every hapsim_* target and the big external
#     ones (gRPC, protobuf, Cyclone DDS, spdlog, Eigen); other imported
#     targets (absl, fmt, ...) come with those and are not judged.
#
# tests/build/layer_rules_probe.sh proves both fail on a violation.

set(HAPSIM_LAYER_CHECK_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/CheckIncludes.cmake)
set(HAPSIM_LAYER_EXTERNALS Eigen3::Eigen spdlog::spdlog CycloneDDS::ddsc protobuf::libprotobuf
    gRPC::grpc gRPC::grpc++ gRPC::grpc++_reflection prometheus-cpp::core nlohmann_json::nlohmann_json
    zstd::libzstd_shared SQLite::SQLite3 Boost::headers)

function(hapsim_forbid_includes layer)
  cmake_parse_arguments(ARG "" "PATTERN;TARGET" "DIRS;ALLOW" ${ARGN})
  set(rules ${CMAKE_BINARY_DIR}/layer_rules/${layer}.cmake)
  file(WRITE ${rules} "set(LAYER [==[${layer}]==])\nset(DIRS [==[${ARG_DIRS}]==])\n"
                      "set(PATTERN [==[${ARG_PATTERN}]==])\nset(ALLOW [==[${ARG_ALLOW}]==])\n")
  set(RULES ${rules})
  include(${HAPSIM_LAYER_CHECK_SCRIPT})
  if(ARG_TARGET)
    add_custom_target(${ARG_TARGET}_include_check
      COMMAND ${CMAKE_COMMAND} -DRULES=${rules} -P ${HAPSIM_LAYER_CHECK_SCRIPT}
      COMMENT "Checking the includes of layer ${layer}" VERBATIM)
    add_dependencies(${ARG_TARGET} ${ARG_TARGET}_include_check)
  endif()
endfunction()

function(hapsim_layer_allows target)
  set_property(GLOBAL APPEND PROPERTY HAPSIM_LAYER_TARGETS ${target})
  set_property(GLOBAL PROPERTY HAPSIM_LAYER_ALLOWED_${target} ${ARGN})
endfunction()

# The real target behind an alias, or the name itself.
function(_hapsim_resolve name out)
  if(TARGET ${name})
    get_target_property(aliased ${name} ALIASED_TARGET)
    if(aliased)
      set(${out} ${aliased} PARENT_SCOPE)
      return()
    endif()
  endif()
  set(${out} ${name} PARENT_SCOPE)
endfunction()

# Every target `target` links, directly or through others.
function(_hapsim_link_closure target out)
  set(seen "")
  set(todo ${target})
  while(todo)
    list(POP_FRONT todo t)
    if(NOT TARGET ${t})
      continue()
    endif()
    set(deps "")
    get_target_property(imported ${t} IMPORTED)
    get_target_property(type ${t} TYPE)
    if(NOT imported AND NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${t} LINK_LIBRARIES)
      if(direct)
        list(APPEND deps ${direct})
      endif()
    endif()
    get_target_property(iface ${t} INTERFACE_LINK_LIBRARIES)
    if(iface)
      list(APPEND deps ${iface})
    endif()
    foreach(d IN LISTS deps)
      # $<LINK_ONLY:x> and other generator expressions around a name.
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" d "${d}")
      if(d MATCHES "^\\$<")
        continue()
      endif()
      _hapsim_resolve(${d} r)
      if(NOT r IN_LIST seen)
        list(APPEND seen ${r})
        list(APPEND todo ${r})
      endif()
    endforeach()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

function(hapsim_check_layers)
  get_property(targets GLOBAL PROPERTY HAPSIM_LAYER_TARGETS)
  set(watched ${HAPSIM_LAYER_EXTERNALS})
  foreach(t IN LISTS targets)
    list(APPEND watched ${t})
  endforeach()
  foreach(t IN LISTS targets)
    if(NOT TARGET ${t})
      continue()  # not built in this configuration (e.g. HAPSIM_CORE_ONLY)
    endif()
    get_property(allowed GLOBAL PROPERTY HAPSIM_LAYER_ALLOWED_${t})
    _hapsim_link_closure(${t} closure)
    foreach(dep IN LISTS closure)
      if((dep MATCHES "^hapsim_" OR dep IN_LIST watched) AND NOT dep IN_LIST allowed)
        message(FATAL_ERROR "Layer violation: ${t} links ${dep}, which its layer may not use "
                            "(allowed: ${allowed}). See docs/architecture.md, \"Layers\".")
      endif()
    endforeach()
  endforeach()
endfunction()
