# Shared body of the cross toolchain files. Inputs: DT_CROSS_TRIPLE, DT_CROSS_QEMU.
# Sets only the compilers, the sysroot, the find-root modes, pkg-config's search path and the emulator.
set(CMAKE_C_COMPILER ${DT_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${DT_CROSS_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${DT_CROSS_TRIPLE})

if(NOT DT_SYSROOT AND DEFINED ENV{DT_SYSROOT})
    set(DT_SYSROOT $ENV{DT_SYSROOT})
endif()
set(DT_SYSROOT "${DT_SYSROOT}" CACHE PATH "Target root file system (empty: Debian multiarch on the host)")

if(DT_SYSROOT)
    set(CMAKE_SYSROOT ${DT_SYSROOT})
    set(CMAKE_FIND_ROOT_PATH ${DT_SYSROOT})
    set(ENV{PKG_CONFIG_SYSROOT_DIR} ${DT_SYSROOT})
    set(_dt_target_root ${DT_SYSROOT})
else()
    # Multiarch: the target's libraries live beside the host's under /usr/lib/<triple>; the cross
    # compiler's own runtime lives in /usr/<triple>. qemu runs the programs against the target's
    # own libc (libc6:<arch>, installed with the -dev packages, loader in /lib): the cross
    # toolchain's copy in /usr/<triple> is a different build, and mixing its loader with the
    # multiarch libc hangs pthread_create under qemu-user.
    set(CMAKE_FIND_ROOT_PATH /usr/${DT_CROSS_TRIPLE} /)
    set(ENV{PKG_CONFIG_SYSROOT_DIR} "")
    set(_dt_target_root /)
endif()
set(ENV{PKG_CONFIG_LIBDIR}
    "${DT_SYSROOT}/usr/lib/${DT_CROSS_TRIPLE}/pkgconfig:${DT_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# qemu-user runs the cross-built tests; -L points it at the target's dynamic loader and libraries.
find_program(DT_QEMU_EXECUTABLE ${DT_CROSS_QEMU})
if(DT_QEMU_EXECUTABLE)
    set(CMAKE_CROSSCOMPILING_EMULATOR ${DT_QEMU_EXECUTABLE} -L ${_dt_target_root})
endif()
