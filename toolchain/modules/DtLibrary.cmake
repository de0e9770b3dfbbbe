# dt_add_library(NAME SOURCES src... [PUBLIC target...] [PRIVATE target...] [SYSTEM_INCLUDES target...])
#   One of the project's static libraries: its sources, its include/ folder as the public include
#   directory, its PUBLIC and PRIVATE links, and the project's warning set (dt_target_warnings). The
#   include directories of the third-party targets in SYSTEM_INCLUDES are added as SYSTEM headers, so
#   that their own warnings stay out of our warning level.
# dt_target_system_includes(TARGET DEPENDENCY): the include directories of DEPENDENCY as SYSTEM
#   headers of TARGET (PRIVATE).
include_guard(GLOBAL)
include(DtWarnings)

function(dt_target_system_includes target dependency)
    get_target_property(_dt_inc ${dependency} INTERFACE_INCLUDE_DIRECTORIES)
    if(_dt_inc)
        target_include_directories(${target} SYSTEM PRIVATE ${_dt_inc})
    endif()
endfunction()

function(dt_add_library name)
    cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "SOURCES;PUBLIC;PRIVATE;SYSTEM_INCLUDES")
    if(arg_UNPARSED_ARGUMENTS OR NOT arg_SOURCES)
        message(FATAL_ERROR "dt_add_library(${name}): needs SOURCES; unknown: ${arg_UNPARSED_ARGUMENTS}")
    endif()
    add_library(${name} STATIC ${arg_SOURCES})
    target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
    foreach(dependency IN LISTS arg_SYSTEM_INCLUDES)
        dt_target_system_includes(${name} ${dependency})
    endforeach()
    if(arg_PUBLIC)
        target_link_libraries(${name} PUBLIC ${arg_PUBLIC})
    endif()
    if(arg_PRIVATE)
        target_link_libraries(${name} PRIVATE ${arg_PRIVATE})
    endif()
    dt_target_warnings(${name})
endfunction()
