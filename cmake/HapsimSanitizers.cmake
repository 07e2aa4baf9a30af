# HAPSIM_SANITIZE="address;undefined" or "thread": applied to every target.
if(HAPSIM_SANITIZE)
  string(REPLACE ";" "," _san "${HAPSIM_SANITIZE}")
  add_compile_options(-fsanitize=${_san} -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=${_san})
  message(STATUS "hapsim: sanitizers ${_san}")
endif()
