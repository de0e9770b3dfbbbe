# The Debian package and the install rules (packaging/CMakeLists.txt), as an integrator meets them:
#  1. DESTDIR=stage cmake --install: the program, unit, sysusers entry, udev rule, config, man page, docs,
#     copyright and changelog; the unit clean under `systemd-analyze verify`, its sandbox scored by
#     `systemd-analyze security` (at most 4.0, "OK") and opening the sound card (char-alsa, group
#     audio); the files its Documentation= names installed;
#  1b. cmake --install --prefix P: every file it writes lies under P, and the unit names P's program and config;
#  2. cpack writes depthtouch_<version>_<arch>.deb and depthtouch-dbgsym_<version>_<arch>.ddeb: the .deb's
#     Architecture, Depends (from dpkg-shlibdeps, and the Mesa driver), conffiles, maintainer scripts and
#     contents, its program stripped, the .ddeb holding that program's debug information under its build-id;
#  2b. (LIB) and libdepthtouch0 (the .so.0, Section libs, a shlibs, the committed symbols file and
#     the ldconfig trigger in its control, no maintainer script, the library stripped and its debug
#     file in libdepthtouch0-dbgsym) and libdepthtouch-dev (the header, the .so link, depthtouch.pc,
#     the CMake package config; Depends: libdepthtouch0 (= version)); nothing else; the program's
#     package depends on libdepthtouch0 exactly when the program links it (readelf -d);
#  2c. (GST) gstreamer1.0-depthtouch: the plugin in lib/<multiarch>/gstreamer-1.0, stripped, its
#     debug file in gstreamer1.0-depthtouch-dbgsym, Section video, Depends on GStreamer's library
#     (shlibs) and the Mesa driver; the program's package holds no plugin;
#     lintian reports no error and no warning on any of them;
#  3. (native builds) the package unpacked into a scratch root (dpkg-deb -x) runs: --version and a
#     short demo from there; with LIB, libdepthtouch0 and libdepthtouch-dev unpacked into a root of
#     their own: a C program built with that root's pkg-config file (CC) loads the library; with GST
#     (and no sanitizer), gst-inspect-1.0 loads the plugin from its unpacked package and lists
#     depthtouchsink and hapticsink.
# -DBUILD=<build dir> -DOUT=<scratch folder> -DVERSION=<x.y.z> -DARCH=<Debian arch> -DRUN=ON|OFF
# -DLIB=ON|OFF (the build has libdepthtouch) -DGST=ON|OFF (the build has the GStreamer plugin)
# -DLIBDIR=<its CMAKE_INSTALL_LIBDIR: lib/<multiarch>>
# -DSYMBOLS=<packaging/libdepthtouch0.symbols> -DCC=<a C compiler for the target>
# -DPAGES=ON|OFF (the build wrote the man pages and shell completion) -DRUN_PROGRAM=<the program, or
# its emulator wrapper in a cross build>
# -DSANITIZE=<the build's DT_SANITIZE> (RUN: a native build, whose program runs here; a sanitizer
# build's package is not one that ships: lintian is not run on it)
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
    usr/lib/udev/rules.d/60-novint-falcon.rules etc/depthtouch/play.toml usr/share/doc/depthtouch/README.md
    usr/share/doc/depthtouch/copyright usr/share/doc/depthtouch/changelog.gz
    usr/share/doc/depthtouch/docs/architecture.md)
if(PAGES) # the man pages are made by running the program (a cross build's through its emulator,
    # RUN_PROGRAM); one per command of the program's own --help
    list(APPEND files usr/share/man/man1/depthtouch.1.gz)
    execute_process(COMMAND ${RUN_PROGRAM} --help OUTPUT_VARIABLE top)
    string(REGEX REPLACE ".*\nSubcommands:\n" "" listing "${top}")
    string(REGEX MATCHALL "(^|\n)  [a-z][a-z0-9-]*" commands "${listing}")
    string(REGEX REPLACE "(^|\n)  " "" commands "${commands}")
    list(LENGTH commands n)
    if(n LESS 5)
        message(FATAL_ERROR "depthtouch --help lists ${n} commands: '${commands}'")
    endif()
    foreach(cmd ${commands})
        list(APPEND files usr/share/man/man1/depthtouch-${cmd}.1.gz)
    endforeach()
    # shell completion, written by the program too
    list(APPEND files usr/share/bash-completion/completions/depthtouch
        usr/share/zsh/vendor-completions/_depthtouch)
endif()
foreach(p ${files})
    expect_file("${OUT}/stage" "${p}")
endforeach()
# The library's two packages, file by file (a plain install installs them too).
set(lib_files usr/${LIBDIR}/libdepthtouch.so.0 usr/${LIBDIR}/libdepthtouch.so.${VERSION}
    usr/share/doc/libdepthtouch0/copyright usr/share/doc/libdepthtouch0/changelog.gz)
set(dev_files usr/include/depthtouch/client.h usr/include/depthtouch/render_gl.h
    usr/${LIBDIR}/libdepthtouch.so
    usr/${LIBDIR}/pkgconfig/depthtouch.pc usr/${LIBDIR}/cmake/DepthTouch/depthtouch-config.cmake
    usr/${LIBDIR}/cmake/DepthTouch/depthtouch-config-version.cmake
    usr/${LIBDIR}/cmake/DepthTouch/depthtouch-targets.cmake
    usr/share/doc/libdepthtouch-dev/copyright usr/share/doc/libdepthtouch-dev/changelog.gz)
if(LIB)
    foreach(p ${lib_files} ${dev_files})
        expect_file("${OUT}/stage" "${p}")
    endforeach()
endif()
file(READ "${OUT}/stage/usr/lib/systemd/system/depthtouch.service" unit)
foreach(line "ExecStart=/usr/bin/depthtouch play --config /etc/depthtouch/play.toml" "LimitRTPRIO=95"
             "LimitMEMLOCK=infinity" "DeviceAllow=char-drm rw" "DeviceAllow=char-usb_device rw")
    string(FIND "${unit}" "${line}" at)
    if(at LESS 0)
        message(FATAL_ERROR "the unit lacks '${line}':\n${unit}")
    endif()
endforeach()
# The sound card under the sandbox: DevicePolicy=closed opens only the devices listed, and ALSA's
# nodes are group audio; without both ALSA is refused and the player falls back to the null output.
if(NOT unit MATCHES "\nDeviceAllow=char-alsa rw\n" OR NOT unit MATCHES "\nSupplementaryGroups=[^\n]* audio( |\n)")
    message(FATAL_ERROR "the unit does not open the sound card (DeviceAllow=char-alsa rw, group audio):\n${unit}")
endif()
file(READ "${OUT}/stage/usr/lib/sysusers.d/depthtouch.conf" sysusers)
if(NOT sysusers MATCHES "\nm depthtouch audio\n")
    message(FATAL_ERROR "the service user is not in the group audio:\n${sysusers}")
endif()
# Each file the unit's Documentation= names is installed (`systemctl help depthtouch` opens them).
if(NOT unit MATCHES "\nDocumentation=([^\n]*)")
    message(FATAL_ERROR "the unit has no Documentation=:\n${unit}")
endif()
string(REGEX MATCHALL "file:[^ ]+" docs "${CMAKE_MATCH_1}")
if(NOT docs)
    message(FATAL_ERROR "the unit's Documentation= names no file: '${CMAKE_MATCH_1}'")
endif()
foreach(doc ${docs})
    string(REGEX REPLACE "^file:/" "" doc "${doc}")
    expect_file("${OUT}/stage" "${doc}")
endforeach()
# The sandbox: systemd's own score of the unit (0 = fully confined, 10 = not at all; "OK" up to 4.0).
# The unit must still allow what the player needs: real-time scheduling and memory locking (the
# syscall filter's @resources and @memlock groups, RestrictRealtime off).
foreach(line "RestrictRealtime=" "MemoryDenyWriteExecute=")
    string(FIND "${unit}" "${line}" at)
    if(NOT at LESS 0)
        message(FATAL_ERROR "the unit sets ${line}, which the player cannot run under:\n${unit}")
    endif()
endforeach()
find_program(SYSTEMD_ANALYZE systemd-analyze)
if(SYSTEMD_ANALYZE)
    execute_process(COMMAND ${SYSTEMD_ANALYZE} security --offline=yes --no-pager
            "${OUT}/stage/usr/lib/systemd/system/depthtouch.service"
        OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT "${out}${err}" MATCHES "Overall exposure level for depthtouch.service: ([0-9.]+)")
        message(FATAL_ERROR "systemd-analyze security printed no score:\n${out}${err}")
    endif()
    set(score ${CMAKE_MATCH_1})
    message("systemd-analyze security: ${score}")
    if(score GREATER 4.0)
        message(FATAL_ERROR "the unit's exposure is ${score}, over 4.0 (OK):\n${out}")
    endif()
    foreach(group @resources @memlock)
        execute_process(COMMAND ${SYSTEMD_ANALYZE} syscall-filter @system-service OUTPUT_VARIABLE groups)
        string(FIND "${groups}" "${group}" at)
        if(at LESS 0)
            message(FATAL_ERROR "@system-service lacks ${group} (sched_setscheduler, mlockall)")
        endif()
    endforeach()
    # `systemd-analyze verify`: the unit loads as systemd reads it, without a warning (an unknown
    # or misspelt directive, a bad value). The staged unit names the program under /usr, not
    # installed on this machine: the copy checked names the staged one (the man page is checked
    # above as a file, not through man(1)).
    string(REGEX REPLACE "\nExecStart=/" "\nExecStart=${OUT}/stage/" verified "${unit}")
    file(WRITE "${OUT}/verify/depthtouch.service" "${verified}")
    execute_process(COMMAND ${SYSTEMD_ANALYZE} verify --man=no "${OUT}/verify/depthtouch.service"
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT "${out}${err}" STREQUAL "")
        message(FATAL_ERROR "systemd-analyze verify of the unit: exit ${rc}\n${out}${err}")
    endif()
else()
    message(FATAL_ERROR "systemd-analyze not found (toolchain/install-deps.sh installs systemd)")
endif()

# 1b. an install under another prefix stays inside it
file(REMOVE "${BUILD}/install_manifest.txt")
run(${CMAKE_COMMAND} --install "${BUILD}" --prefix "${OUT}/prefix")
file(STRINGS "${BUILD}/install_manifest.txt" written)
foreach(p ${written})
    string(FIND "${p}" "${OUT}/prefix/" at)
    if(NOT at EQUAL 0)
        message(FATAL_ERROR "--prefix ${OUT}/prefix wrote ${p}, outside the prefix")
    endif()
endforeach()
expect_file("${OUT}/prefix" etc/depthtouch/play.toml)
file(READ "${OUT}/prefix/lib/systemd/system/depthtouch.service" unit)
set(line "ExecStart=${OUT}/prefix/bin/depthtouch play --config ${OUT}/prefix/etc/depthtouch/play.toml")
string(FIND "${unit}" "${line}" at)
if(at LESS 0)
    message(FATAL_ERROR "the unit installed under a prefix lacks '${line}':\n${unit}")
endif()

# 2. the packages: exactly these, no other
run(cpack --config "${BUILD}/CPackConfig.cmake" -B "${OUT}/cpack")
set(expected depthtouch_${VERSION}_${ARCH}.deb depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb)
if(LIB)
    list(APPEND expected libdepthtouch0_${VERSION}_${ARCH}.deb libdepthtouch0-dbgsym_${VERSION}_${ARCH}.ddeb
        libdepthtouch-dev_${VERSION}_${ARCH}.deb)
endif()
if(GST)
    list(APPEND expected gstreamer1.0-depthtouch_${VERSION}_${ARCH}.deb
        gstreamer1.0-depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb)
endif()
file(GLOB written RELATIVE "${OUT}/cpack" "${OUT}/cpack/*.deb" "${OUT}/cpack/*.ddeb")
list(SORT expected)
list(SORT written)
if(NOT written STREQUAL expected)
    message(FATAL_ERROR "cpack wrote '${written}', expected '${expected}'")
endif()
set(debs "${OUT}/cpack/depthtouch_${VERSION}_${ARCH}.deb")
run(dpkg-deb -f "${debs}" Package Version Architecture Depends)
message("${out}")
if(NOT out MATCHES "Architecture: ${ARCH}\n" OR NOT out MATCHES "Depends:[^\n]*libc6"
   OR NOT out MATCHES "Depends:[^\n]*libavcodec")
    message(FATAL_ERROR "the control fields are wrong (Architecture ${ARCH}, Depends from the shlibs):\n${out}")
endif()
if(NOT out MATCHES "Depends:[^\n]*libgl1-mesa-dri")
    message(FATAL_ERROR "Depends lacks the Mesa driver the headless display draws with:\n${out}")
endif()
run(dpkg-deb -I "${debs}" conffiles)
if(NOT out MATCHES "^/etc/depthtouch/play.toml")
    message(FATAL_ERROR "conffiles: '${out}'")
endif()
run(dpkg-deb -I "${debs}")
if(out MATCHES " (shlibs|symbols|triggers) ")
    message(FATAL_ERROR "the program's package has a library's control files:\n${out}")
endif()
# The maintainer scripts: the service stopped on remove, state forgotten on purge, restarted on upgrade.
foreach(pair "prerm;deb-systemd-invoke stop depthtouch.service" "postrm;deb-systemd-helper purge depthtouch.service"
             "postinst;deb-systemd-invoke try-restart depthtouch.service" "postinst;depthtouch.conf || true")
    list(GET pair 0 script)
    list(GET pair 1 line)
    run(dpkg-deb -I "${debs}" ${script})
    string(FIND "${out}" "${line}" at)
    if(at LESS 0)
        message(FATAL_ERROR "${script} lacks '${line}':\n${out}")
    endif()
endforeach()
# The program stripped; its debug information in the .ddeb under the program's build-id.
run(dpkg-deb -x "${debs}" "${OUT}/deb-root")
execute_process(COMMAND readelf -S -n "${OUT}/deb-root/usr/bin/depthtouch" OUTPUT_VARIABLE elf)
if(elf MATCHES "\\.debug_info")
    message(FATAL_ERROR "the packaged program is not stripped")
endif()
if(NOT elf MATCHES "Build ID: ([0-9a-f][0-9a-f])([0-9a-f]+)")
    message(FATAL_ERROR "the packaged program has no build-id:\n${elf}")
endif()
set(debug_file "usr/lib/debug/.build-id/${CMAKE_MATCH_1}/${CMAKE_MATCH_2}.debug")
set(ddebs "${OUT}/cpack/depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb")
set(lint "${debs}" "${ddebs}") # the packages lintian reads
run(dpkg-deb -x "${ddebs}" "${OUT}/ddeb-root")
expect_file("${OUT}/ddeb-root" "${debug_file}")
execute_process(COMMAND readelf -S "${OUT}/ddeb-root/${debug_file}" OUTPUT_VARIABLE dbg)
if(NOT dbg MATCHES "\\.debug_info")
    message(FATAL_ERROR "${debug_file} holds no debug information")
endif()
# The program's package depends on the library's exactly when the program links it.
execute_process(COMMAND readelf -d "${OUT}/deb-root/usr/bin/depthtouch" OUTPUT_VARIABLE dynamic)
run(dpkg-deb -f "${debs}" Depends)
if(dynamic MATCHES "NEEDED[^\n]*\\[libdepthtouch\\.so\\.0\\]")
    if(NOT out MATCHES "(^|[ ,])libdepthtouch0 ")
        message(FATAL_ERROR "the program links libdepthtouch.so.0, its package does not depend on libdepthtouch0:\n${out}")
    endif()
elseif(out MATCHES "libdepthtouch")
    message(FATAL_ERROR "the program does not link libdepthtouch.so.0, its package depends on it:\n${out}")
endif()

# 2b. the library's packages
if(LIB)
    set(lib_deb "${OUT}/cpack/libdepthtouch0_${VERSION}_${ARCH}.deb")
    set(dev_deb "${OUT}/cpack/libdepthtouch-dev_${VERSION}_${ARCH}.deb")
    # The fields a user reads (dpkg-deb -I).
    run(dpkg-deb -I "${lib_deb}")
    message("${out}")
    foreach(field "Package: libdepthtouch0" "Version: ${VERSION}" "Architecture: ${ARCH}" "Section: libs"
                  "Source: depthtouch")
        if(NOT out MATCHES "\n ${field}\n")
            message(FATAL_ERROR "libdepthtouch0's control lacks '${field}':\n${out}")
        endif()
    endforeach()
    if(NOT out MATCHES "\n Depends:[^\n]*libc6")
        message(FATAL_ERROR "libdepthtouch0's Depends is not from the shlibs of what it links:\n${out}")
    endif()
    if(out MATCHES " (postinst|postrm|preinst|prerm|conffiles) ")
        message(FATAL_ERROR "libdepthtouch0 has a maintainer script or conffiles (the ldconfig trigger does their work):\n${out}")
    endif()
    run(dpkg-deb -I "${lib_deb}" shlibs)
    if(NOT out STREQUAL "libdepthtouch 0 libdepthtouch0 (>= ${VERSION})\n")
        message(FATAL_ERROR "libdepthtouch0's shlibs: '${out}'")
    endif()
    run(dpkg-deb -I "${lib_deb}" symbols)
    file(READ "${SYMBOLS}" committed)
    if(NOT out STREQUAL committed)
        message(FATAL_ERROR "libdepthtouch0's symbols file is not ${SYMBOLS}:\n${out}")
    endif()
    run(dpkg-deb -I "${lib_deb}" triggers)
    if(NOT out STREQUAL "activate-noawait ldconfig\n")
        message(FATAL_ERROR "libdepthtouch0's triggers: '${out}'")
    endif()
    run(dpkg-deb -I "${dev_deb}")
    message("${out}")
    foreach(field "Package: libdepthtouch-dev" "Version: ${VERSION}" "Architecture: ${ARCH}" "Section: libdevel"
                  "Depends: libdepthtouch0 \\(= ${VERSION}\\)" "Source: depthtouch")
        if(NOT out MATCHES "\n ${field}\n")
            message(FATAL_ERROR "libdepthtouch-dev's control lacks '${field}':\n${out}")
        endif()
    endforeach()
    if(out MATCHES " (postinst|postrm|preinst|prerm|conffiles|shlibs|symbols|triggers) ")
        message(FATAL_ERROR "libdepthtouch-dev has control files of a library or a service:\n${out}")
    endif()
    # Their files (dpkg-deb -c: "./path" or "./path -> target"), each in one package only.
    run(dpkg-deb -c "${lib_deb}")
    set(lib_list "${out}")
    run(dpkg-deb -c "${dev_deb}")
    set(dev_list "${out}")
    run(dpkg-deb -c "${debs}")
    set(program_list "${out}")
    foreach(p ${lib_files})
        if(NOT lib_list MATCHES " \\./${p}( -> [^\n]*)?\n")
            message(FATAL_ERROR "libdepthtouch0 lacks ${p}:\n${lib_list}")
        endif()
    endforeach()
    if(NOT lib_list MATCHES " \\./usr/${LIBDIR}/libdepthtouch\\.so\\.0 -> libdepthtouch\\.so\\.${VERSION}\n")
        message(FATAL_ERROR "libdepthtouch0's libdepthtouch.so.0 is not the soname link:\n${lib_list}")
    endif()
    foreach(p ${dev_files})
        if(NOT dev_list MATCHES " \\./${p}( -> [^\n]*)?\n")
            message(FATAL_ERROR "libdepthtouch-dev lacks ${p}:\n${dev_list}")
        endif()
    endforeach()
    if(NOT dev_list MATCHES " \\./usr/${LIBDIR}/libdepthtouch\\.so -> libdepthtouch\\.so\\.0\n")
        message(FATAL_ERROR "libdepthtouch-dev's libdepthtouch.so is not the link to the soname:\n${dev_list}")
    endif()
    if(lib_list MATCHES "(include/|pkgconfig|cmake/|libdepthtouch\\.so -> )" OR dev_list MATCHES "\\./[^ \n]*/libdepthtouch\\.so\\.")
        message(FATAL_ERROR "a development file in libdepthtouch0 or the library in libdepthtouch-dev:\n${lib_list}\n${dev_list}")
    endif()
    if(program_list MATCHES "(libdepthtouch|include/depthtouch|depthtouch\\.pc|DepthTouch)")
        message(FATAL_ERROR "the program's package holds a file of the library's:\n${program_list}")
    endif()
    # The library stripped, its debug information in libdepthtouch0-dbgsym under its build-id.
    run(dpkg-deb -x "${lib_deb}" "${OUT}/lib-root")
    execute_process(COMMAND readelf -S -n -d "${OUT}/lib-root/usr/${LIBDIR}/libdepthtouch.so.${VERSION}"
        OUTPUT_VARIABLE elf)
    if(elf MATCHES "\\.debug_info")
        message(FATAL_ERROR "the packaged library is not stripped")
    endif()
    if(NOT elf MATCHES "SONAME[^\n]*\\[libdepthtouch\\.so\\.0\\]")
        message(FATAL_ERROR "the packaged library's soname is not libdepthtouch.so.0:\n${elf}")
    endif()
    if(NOT elf MATCHES "Build ID: ([0-9a-f][0-9a-f])([0-9a-f]+)")
        message(FATAL_ERROR "the packaged library has no build-id:\n${elf}")
    endif()
    set(lib_debug_file "usr/lib/debug/.build-id/${CMAKE_MATCH_1}/${CMAKE_MATCH_2}.debug")
    set(lib_ddeb "${OUT}/cpack/libdepthtouch0-dbgsym_${VERSION}_${ARCH}.ddeb")
    run(dpkg-deb -x "${lib_ddeb}" "${OUT}/lib-ddeb-root")
    expect_file("${OUT}/lib-ddeb-root" "${lib_debug_file}")
    run(dpkg-deb -f "${lib_ddeb}" Depends)
    if(NOT out STREQUAL "libdepthtouch0 (= ${VERSION})\n")
        message(FATAL_ERROR "libdepthtouch0-dbgsym's Depends: '${out}'")
    endif()
    list(APPEND lint "${lib_deb}" "${dev_deb}" "${lib_ddeb}")
endif()
# 2c. the GStreamer plugin's package
set(gst_plugin "usr/${LIBDIR}/gstreamer-1.0/libgstdepthtouch.so")
if(GST)
    set(gst_deb "${OUT}/cpack/gstreamer1.0-depthtouch_${VERSION}_${ARCH}.deb")
    run(dpkg-deb -I "${gst_deb}")
    message("${out}")
    foreach(field "Package: gstreamer1.0-depthtouch" "Version: ${VERSION}" "Architecture: ${ARCH}"
                  "Section: video" "Source: depthtouch")
        if(NOT out MATCHES "\n ${field}\n")
            message(FATAL_ERROR "gstreamer1.0-depthtouch's control lacks '${field}':\n${out}")
        endif()
    endforeach()
    if(NOT out MATCHES "\n Depends:[^\n]*libgstreamer1\\.0-0" OR NOT out MATCHES "\n Depends:[^\n]*libgl1-mesa-dri")
        message(FATAL_ERROR "gstreamer1.0-depthtouch's Depends lacks GStreamer (shlibs) or Mesa:\n${out}")
    endif()
    run(dpkg-deb -c "${gst_deb}")
    foreach(p ${gst_plugin} usr/share/doc/gstreamer1.0-depthtouch/copyright
              usr/share/doc/gstreamer1.0-depthtouch/changelog.gz)
        if(NOT out MATCHES " \\./${p}\n")
            message(FATAL_ERROR "gstreamer1.0-depthtouch lacks ${p}:\n${out}")
        endif()
    endforeach()
    run(dpkg-deb -c "${debs}")
    if(out MATCHES "gstreamer-1\\.0")
        message(FATAL_ERROR "the program's package holds the GStreamer plugin:\n${out}")
    endif()
    run(dpkg-deb -x "${gst_deb}" "${OUT}/gst-root")
    execute_process(COMMAND readelf -S "${OUT}/gst-root/${gst_plugin}" OUTPUT_VARIABLE elf)
    if(elf MATCHES "\\.debug_info")
        message(FATAL_ERROR "the packaged plugin is not stripped")
    endif()
    list(APPEND lint "${gst_deb}" "${OUT}/cpack/gstreamer1.0-depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb")
endif()
find_program(LINTIAN lintian)
if(SANITIZE)
    message("lintian: not run on a sanitizer build's package (${SANITIZE})")
elseif(NOT LINTIAN)
    message(FATAL_ERROR "lintian not found (toolchain/install-deps.sh installs it)")
else()
    execute_process(COMMAND ${LINTIAN} --fail-on error,warning ${lint}
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("lintian: ${out}")
    if(NOT rc EQUAL 0 OR out MATCHES "(^|\n)[EW]: ")
        message(FATAL_ERROR "lintian (exit ${rc}):\n${out}\n${err}")
    endif()
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
    # libdepthtouch0 and libdepthtouch-dev unpacked together: the .so link of the one reaches the
    # library of the other, and depthtouch.pc (found in that root) points into the root.
    find_program(PKG_CONFIG pkg-config)
    if(LIB AND PKG_CONFIG AND CC)
        run(dpkg-deb -x "${OUT}/cpack/libdepthtouch0_${VERSION}_${ARCH}.deb" "${OUT}/lib-dev-root")
        run(dpkg-deb -x "${OUT}/cpack/libdepthtouch-dev_${VERSION}_${ARCH}.deb" "${OUT}/lib-dev-root")
        set(ENV{PKG_CONFIG_PATH} "${OUT}/lib-dev-root/usr/${LIBDIR}/pkgconfig")
        run(${PKG_CONFIG} --cflags --libs depthtouch)
        string(STRIP "${out}" flags)
        separate_arguments(flags UNIX_COMMAND "${flags}")
        file(WRITE "${OUT}/version.c" "#include <depthtouch/client.h>
#include <stdio.h>
int main(void)
{
    printf(\"%lx\\n\", dt_client_api_version());
    return dt_client_api_version() == DT_CLIENT_API_VERSION ? 0 : 1;
}
")
        run(${CC} -std=c99 -Wall -Werror "${OUT}/version.c" ${flags} -o "${OUT}/version")
        set(ENV{LD_LIBRARY_PATH} "${OUT}/lib-dev-root/usr/${LIBDIR}")
        run("${OUT}/version")
        unset(ENV{LD_LIBRARY_PATH})
        message("a program built against the unpacked libdepthtouch-dev loaded libdepthtouch0 (API ${out})")
    endif()
    # The plugin from its unpacked package, as GStreamer finds it once installed.
    find_program(GST_INSPECT gst-inspect-1.0)
    if(GST AND GST_INSPECT AND NOT SANITIZE)
        set(ENV{GST_PLUGIN_PATH} "${OUT}/gst-root/usr/${LIBDIR}/gstreamer-1.0")
        set(ENV{GST_REGISTRY} "${OUT}/gst-registry.bin")
        run(${GST_INSPECT} depthtouch)
        unset(ENV{GST_PLUGIN_PATH})
        unset(ENV{GST_REGISTRY})
        if(NOT out MATCHES "depthtouchsink" OR NOT out MATCHES "hapticsink")
            message(FATAL_ERROR "gst-inspect-1.0 depthtouch from the package:\n${out}")
        endif()
        message("gst-inspect-1.0 loaded the packaged plugin: depthtouchsink, hapticsink")
    endif()
endif()
message("package: ${debs}")
