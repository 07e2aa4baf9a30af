# HAPSIM_SANITIZE="address;undefined" or "thread": applied to every target.
# HAPSIM_FUZZ: every target is instrumented for libFuzzer plus ASan+UBSan
# (except the core's physics, which drops libFuzzer's coverage callbacks:
# core/CMakeLists.txt);
# the fuzz executables (tests/fuzz) link the fuzzer's main.
if(HAPSIM_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "HAPSIM_FUZZ needs clang: configure with CC=clang CXX=clang++")
  endif()
  set(HAPSIM_SANITIZE "address;undefined")
  add_compile_options(-fsanitize=fuzzer-no-link)
  # Line tables are all a sanitizer report needs (file:line in every frame);
  # full -g only makes the objects and the fuzz binaries bigger. (It is not
  # what makes this tree slow to build: docs/reliability.md, CI time.)
  add_compile_options(-gline-tables-only)
endif()
if(HAPSIM_SANITIZE)
  string(REPLACE ";" "," _san "${HAPSIM_SANITIZE}")
  add_compile_options(-fsanitize=${_san} -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=${_san})
  if("undefined" IN_LIST HAPSIM_SANITIZE AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    set(_ignorelist ${PROJECT_SOURCE_DIR}/cmake/ubsan-third-party-headers.txt)
    add_compile_options(-fsanitize-ignorelist=${_ignorelist})
    # The compiler cache leaves that flag out of its keys (it names a path in
    # this clone: cmake/HapsimCompilerCache.cmake) and keys on this instead,
    # which says the list is in use and what it holds.
    file(MD5 ${_ignorelist} _ignorelist_md5)
    add_compile_definitions(HAPSIM_UBSAN_IGNORELIST_MD5=${_ignorelist_md5})
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_ignorelist})
  endif()
  message(STATUS "hapsim: sanitizers ${_san}")
endif()
