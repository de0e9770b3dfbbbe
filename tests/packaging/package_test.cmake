# The Debian package and the install rules (packaging/CMakeLists.txt), as an integrator meets them:
#  1. DESTDIR=stage cmake --install: the program, unit, sysusers entry, udev rule, config, man page, docs,
#     copyright and changelog; the unit's sandbox scored by `systemd-analyze security` (at most 4.0, "OK")
#     and opening the sound card (char-alsa, group audio); the files its Documentation= names installed;
#  1b. cmake --install --prefix P: every file it writes lies under P, and the unit names P's program and config;
#  2. cpack writes depthtouch_<version>_<arch>.deb and depthtouch-dbgsym_<version>_<arch>.ddeb: the .deb's
#     Architecture, Depends (from dpkg-shlibdeps, and the Mesa driver), conffiles, maintainer scripts and
#     contents, its program stripped, the .ddeb holding that program's debug information under its build-id;
#     lintian reports no error and no warning on either;
#  3. (native builds) the package unpacked into a scratch root (dpkg-deb -x) runs: --version and a
#     short demo from there.
# -DBUILD=<build dir> -DOUT=<scratch folder> -DVERSION=<x.y.z> -DARCH=<Debian arch> -DRUN=ON|OFF
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
if(NOT out MATCHES "Depends:[^\n]*libgl1-mesa-dri")
    message(FATAL_ERROR "Depends lacks the Mesa driver the headless display draws with:\n${out}")
endif()
run(dpkg-deb -I "${debs}" conffiles)
if(NOT out MATCHES "^/etc/depthtouch/play.toml")
    message(FATAL_ERROR "conffiles: '${out}'")
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
file(GLOB ddebs "${OUT}/cpack/depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb")
if(NOT ddebs)
    message(FATAL_ERROR "cpack wrote no depthtouch-dbgsym_${VERSION}_${ARCH}.ddeb")
endif()
run(dpkg-deb -x "${ddebs}" "${OUT}/ddeb-root")
expect_file("${OUT}/ddeb-root" "${debug_file}")
execute_process(COMMAND readelf -S "${OUT}/ddeb-root/${debug_file}" OUTPUT_VARIABLE dbg)
if(NOT dbg MATCHES "\\.debug_info")
    message(FATAL_ERROR "${debug_file} holds no debug information")
endif()
find_program(LINTIAN lintian)
if(SANITIZE)
    message("lintian: not run on a sanitizer build's package (${SANITIZE})")
elseif(NOT LINTIAN)
    message(FATAL_ERROR "lintian not found (toolchain/install-deps.sh installs it)")
else()
    execute_process(COMMAND ${LINTIAN} --fail-on error,warning "${debs}" "${ddebs}"
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
endif()
message("package: ${debs}")
