# Compiles through ccache when it is installed. CI builds a clean clone every
# time, twice (the release tree and the sanitized/fuzz tree), and most of
# what it compiles is what the last run compiled: on a 2-core host that is
# ~25 of its ~40 minutes.
# - base_dir (the source tree) and no hash_dir: a clone at another path,
#   or a build directory of another name, finds the same results.
# - ignore_options: the sanitizer ignore list's flag names a path in the
#   clone, which ccache would hash as it is; a define with the list's MD5
#   stands for it in the key (cmake/HapsimSanitizers.cmake).
# - __FILE__ relative to the source tree (-fmacro-prefix-map, always): the
#   unity batches include their files by absolute path, so ccache finds them
#   by their preprocessed text, and every gtest assertion's __FILE__ would
#   otherwise make that text differ from clone to clone. (It also makes the
#   binaries the same wherever the tree is.)
# ccache checks the compiler, every flag and every included header's
# contents; what it returns is what the compiler would have produced.
add_compile_options(-fmacro-prefix-map=${PROJECT_SOURCE_DIR}/=)
option(HAPSIM_CCACHE "Compile through ccache when it is installed" ON)
if(HAPSIM_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(HAPSIM_CCACHE_PROGRAM ccache)
  if(HAPSIM_CCACHE_PROGRAM)
    set(_hapsim_launcher
        ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR} CCACHE_NOHASHDIR=true
        CCACHE_IGNOREOPTIONS=-fsanitize-ignorelist=* ${HAPSIM_CCACHE_PROGRAM})
    set(CMAKE_C_COMPILER_LAUNCHER ${_hapsim_launcher})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${_hapsim_launcher})
    message(STATUS "hapsim: compiling through ${HAPSIM_CCACHE_PROGRAM}")
  endif()
endif()
