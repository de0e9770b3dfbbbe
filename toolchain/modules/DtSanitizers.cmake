# Applies DT_SANITIZE (a list such as address;undefined) to every target of the build.
include_guard(GLOBAL)

if(DT_SANITIZE)
    list(JOIN DT_SANITIZE "," _dt_sanitizers)
    add_compile_options(-fsanitize=${_dt_sanitizers} -fno-omit-frame-pointer -fno-sanitize-recover=all)
    add_link_options(-fsanitize=${_dt_sanitizers})
    message(STATUS "DepthTouch sanitizers: ${_dt_sanitizers}")
endif()
