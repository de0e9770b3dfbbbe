# DtCcache: compile through ccache when it is installed (option DT_CCACHE, default ON).
#
# Every build tree is its own base directory (CCACHE_BASEDIR = the source root) and the working
# directory is left out of the hash (CCACHE_NOHASHDIR), so two copies of the source tree compiled with
# the same preset and flags share their objects: the mutation check (tests/mutation/run.sh) builds a
# scratch copy of the tree and compiles only the files a mutant changed. A launcher set by the user
# (CMAKE_CXX_COMPILER_LAUNCHER) is kept. Sets DT_CCACHE_ACTIVE when ccache is the launcher: a
# compile that uses a precompiled header is never cached, so a target would then go without one
# (none uses one now: CLI11, the header that was precompiled, is in app/cli/command_line.cpp alone).
# Reference: ccache(1), "Compiling in different directories" and "Precompiled headers".
option(DT_CCACHE "Compile through ccache when it is installed" ON)
if(DT_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER AND NOT CMAKE_C_COMPILER_LAUNCHER)
    find_program(DT_CCACHE_PROGRAM ccache)
    find_program(DT_ENV_PROGRAM env)
    if(DT_CCACHE_PROGRAM AND DT_ENV_PROGRAM)
        set(_dt_launcher ${DT_ENV_PROGRAM} CCACHE_BASEDIR=${CMAKE_SOURCE_DIR} CCACHE_NOHASHDIR=1
            ${DT_CCACHE_PROGRAM})
        set(CMAKE_C_COMPILER_LAUNCHER ${_dt_launcher})
        set(CMAKE_CXX_COMPILER_LAUNCHER ${_dt_launcher})
        set(DT_CCACHE_ACTIVE ON) # no precompiled header then (ccache cannot cache it)
        message(STATUS "ccache: ${DT_CCACHE_PROGRAM} (base directory ${CMAKE_SOURCE_DIR})")
    endif()
endif()
