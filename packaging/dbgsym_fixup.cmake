# CPack post-build script (CPACK_POST_BUILD_SCRIPTS): finishes the debug package CPack's DEB
# generator writes (<package>-dbgsym_<version>_<arch>.ddeb, one per package with an ELF file:
# depthtouch, libdepthtouch0) as Debian's dh_strip would:
#  - the debug file's sections compressed (objcopy --compress-debug-sections: about a third the size);
#  - md5sums listing the package's own paths (CPack 3.25 writes its staging folder's absolute path);
#  - usr/share/doc/<package>-dbgsym a link to <package>'s folder (its copyright and changelog; the
#    ddeb depends on that exact version).
# Reference: Debian's debhelper, dh_strip(1); deb-md5sums(5).
foreach(_deb IN LISTS CPACK_PACKAGE_FILES)
    if(NOT _deb MATCHES "/([^/]+)-dbgsym_[^/]*\\.ddeb$")
        continue()
    endif()
    set(_package "${CMAKE_MATCH_1}")
    set(_root "${_deb}.root")
    file(REMOVE_RECURSE "${_root}")
    execute_process(COMMAND dpkg-deb -R "${_deb}" "${_root}" RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "dbgsym: dpkg-deb -R ${_deb} failed (${_rc})")
    endif()
    file(GLOB_RECURSE _debug RELATIVE "${_root}" "${_root}/usr/lib/debug/*.debug")
    foreach(_f IN LISTS _debug)
        execute_process(COMMAND "${CPACK_DT_OBJCOPY}" --compress-debug-sections "${_root}/${_f}"
            RESULT_VARIABLE _rc)
        if(NOT _rc EQUAL 0)
            message(FATAL_ERROR "dbgsym: ${CPACK_DT_OBJCOPY} --compress-debug-sections ${_f} failed (${_rc})")
        endif()
        file(CHMOD "${_root}/${_f}" PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)
    endforeach()
    file(MAKE_DIRECTORY "${_root}/usr/share/doc")
    file(CREATE_LINK "${_package}" "${_root}/usr/share/doc/${_package}-dbgsym" SYMBOLIC)
    set(_sums "")
    foreach(_f IN LISTS _debug)
        file(MD5 "${_root}/${_f}" _md5)
        string(APPEND _sums "${_md5}  ${_f}\n")
    endforeach()
    file(WRITE "${_root}/DEBIAN/md5sums" "${_sums}")
    file(READ "${_root}/DEBIAN/control" _control)
    set(_kib 0)
    foreach(_f IN LISTS _debug)
        file(SIZE "${_root}/${_f}" _size)
        math(EXPR _kib "${_kib} + (${_size} + 1023) / 1024")
    endforeach()
    string(REGEX REPLACE "Installed-Size: [0-9]+" "Installed-Size: ${_kib}" _control "${_control}")
    file(WRITE "${_root}/DEBIAN/control" "${_control}")
    execute_process(COMMAND dpkg-deb --root-owner-group -Zxz -b "${_root}" "${_deb}"
        RESULT_VARIABLE _rc OUTPUT_QUIET)
    file(REMOVE_RECURSE "${_root}")
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "dbgsym: dpkg-deb -b ${_deb} failed (${_rc})")
    endif()
endforeach()
