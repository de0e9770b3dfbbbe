# The Debian package and the install rules (packaging/CMakeLists.txt), as an integrator meets them:
#  1. DESTDIR=stage cmake --install: the program, unit, sysusers entry, udev rule, config, man page, docs;
#  2. cpack writes depthtouch_<version>_<arch>.deb: its Architecture, Depends (from dpkg-shlibdeps),
#     conffiles and contents;
#  3. (native builds) the package unpacked into a scratch root (dpkg-deb -x) runs: --version and a
#     short demo from there.
# -DBUILD=<build dir> -DOUT=<scratch folder> -DVERSION=<x.y.z> -DARCH=<Debian arch> -DRUN=ON|OFF
# (RUN: a native build, whose program runs here)
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")

function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
    if(NOT rc EQUAL 0)
        string(REPLACE ";" " " cmd "${ARGN}")
        message(FATAL_ERROR "'${cmd}' exited with ${rc}:\n${out}\n${err}")
    endif()
    set(out "${out}" PARENT_SCOPE)
endfunction()

function(expect_file root path)
    if(NOT EXISTS "${root}/${path}")
        message(FATAL_ERROR "missing ${path} under ${root}")
    endif()
endfunction()

# 1. a staged install
set(ENV{DESTDIR} "${OUT}/stage")
run(${CMAKE_COMMAND} --install "${BUILD}")
unset(ENV{DESTDIR})
set(files usr/bin/depthtouch usr/lib/systemd/system/depthtouch.service usr/lib/sysusers.d/depthtouch.conf
    usr/lib/udev/rules.d/60-novint-falcon.rules etc/depthtouch/play.toml usr/share/doc/depthtouch/README.md)
if(RUN) # the man page is made by running the program: native builds only
    list(APPEND files usr/share/man/man1/depthtouch.1)
endif()
foreach(p ${files})
    expect_file("${OUT}/stage" "${p}")
endforeach()
file(READ "${OUT}/stage/usr/lib/systemd/system/depthtouch.service" unit)
foreach(line "ExecStart=/usr/bin/depthtouch play --config /etc/depthtouch/play.toml" "LimitRTPRIO=95"
             "LimitMEMLOCK=infinity")
    string(FIND "${unit}" "${line}" at)
    if(at LESS 0)
        message(FATAL_ERROR "the unit lacks '${line}':\n${unit}")
    endif()
endforeach()

# 2. the package
run(cpack --config "${BUILD}/CPackConfig.cmake" -B "${OUT}/cpack")
file(GLOB debs "${OUT}/cpack/depthtouch_${VERSION}_${ARCH}.deb")
list(LENGTH debs n)
if(NOT n EQUAL 1)
    file(GLOB all "${OUT}/cpack/*")
    message(FATAL_ERROR "expected depthtouch_${VERSION}_${ARCH}.deb, cpack wrote: ${all}")
endif()
run(dpkg-deb -f "${debs}" Package Version Architecture Depends)
message("${out}")
if(NOT out MATCHES "Architecture: ${ARCH}\n" OR NOT out MATCHES "Depends:[^\n]*libc6"
   OR NOT out MATCHES "Depends:[^\n]*libavcodec")
    message(FATAL_ERROR "the control fields are wrong (Architecture ${ARCH}, Depends from the shlibs):\n${out}")
endif()
run(dpkg-deb -I "${debs}" conffiles)
if(NOT out MATCHES "^/etc/depthtouch/play.toml")
    message(FATAL_ERROR "conffiles: '${out}'")
endif()
run(dpkg-deb -c "${debs}")
foreach(p ${files})
    string(FIND "${out}" " ./${p}" at)
    if(at LESS 0)
        message(FATAL_ERROR "the package lacks ${p}:\n${out}")
    endif()
endforeach()

# 3. installed into a scratch root, it runs from there
if(RUN)
    run(dpkg-deb -x "${debs}" "${OUT}/root")
    run("${OUT}/root/usr/bin/depthtouch" --version)
    if(NOT out MATCHES "^depthtouch ${VERSION}")
        message(FATAL_ERROR "--version: '${out}'")
    endif()
    run("${OUT}/root/usr/bin/depthtouch" demo --duration 1 --frames 15 --size 160x108 --haptic mock
        --out "${OUT}/demo")
    message("${out}")
    expect_file("${OUT}/demo" stats.json)
endif()
message("package: ${debs}")
