# hapsim_warnings(target): warnings on for our own targets only (never for
# generated protobuf/IDL code, which we do not control).
# -Wno-missing-field-initializers: GCC 12 warns on every designated
# initializer that leaves a member to its default member initializer, which
# is the whole point of writing {.name = ..., .min = ...} (param tables).
function(hapsim_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
      -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
      -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough -Wno-missing-field-initializers>)
endfunction()
