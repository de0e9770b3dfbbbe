# dt_target_warnings(TARGET): the project's warning set on one target (PRIVATE), -Werror when DT_WERROR is on.
include_guard(GLOBAL)

function(dt_target_warnings TARGET)
    target_compile_options(${TARGET} PRIVATE
        -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wnon-virtual-dtor
        -Wold-style-cast -Woverloaded-virtual -Wdouble-promotion -Wformat=2
        -Wimplicit-fallthrough)
    if(DT_WERROR)
        target_compile_options(${TARGET} PRIVATE -Werror)
    endif()
endfunction()
