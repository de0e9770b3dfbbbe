# CPack post-build script (CPACK_POST_BUILD_SCRIPTS): a library package updates the loader's cache
# through the ldconfig trigger (its control's triggers file, "activate-noawait ldconfig": Debian
# policy 8.1.1), not by calling ldconfig. CPack's DEB generator writes, for a package with a shared
# object under /usr/lib, a postinst and a postrm that call ldconfig and do nothing else; in the
# packages named by CPACK_DT_LDCONFIG_PACKAGES (packaging/CMakeLists.txt) this script takes those
# two out, after checking that they are exactly CPack's and that the trigger is there.
# Reference: deb-triggers(5); lintian's maintscript-calls-ldconfig and lacks-ldconfig-trigger.
foreach(_deb IN LISTS CPACK_PACKAGE_FILES)
    get_filename_component(_name "${_deb}" NAME)
    string(REGEX REPLACE "_.*" "" _package "${_name}")
    if(NOT _name MATCHES "\\.deb$" OR NOT _package IN_LIST CPACK_DT_LDCONFIG_PACKAGES)
        continue()
    endif()
    set(_root "${_deb}.root")
    file(REMOVE_RECURSE "${_root}")
    execute_process(COMMAND dpkg-deb -R "${_deb}" "${_root}" RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "ldconfig trigger: dpkg-deb -R ${_deb} failed (${_rc})")
    endif()
    if(NOT EXISTS "${_root}/DEBIAN/triggers")
        message(FATAL_ERROR "ldconfig trigger: ${_name} has no triggers file")
    endif()
    file(READ "${_root}/DEBIAN/triggers" _triggers)
    if(NOT _triggers MATCHES "(^|\n)activate-noawait ldconfig\n")
        message(FATAL_ERROR "ldconfig trigger: ${_name}'s triggers file lacks 'activate-noawait ldconfig':\n${_triggers}")
    endif()
    foreach(_script postinst postrm)
        if(NOT EXISTS "${_root}/DEBIAN/${_script}")
            continue()
        endif()
        file(READ "${_root}/DEBIAN/${_script}" _text)
        # CPack's script: the shell line, set -e, and ldconfig under one condition.
        string(REGEX REPLACE "#[^\n]*\n|set -e\n|if \\[ \"\\$1\" = \"[a-z]+\" \\]; then\n|fi\n|[ \t\n]" ""
            _rest "${_text}")
        if(NOT _rest STREQUAL "ldconfig")
            message(FATAL_ERROR "ldconfig trigger: ${_name}'s ${_script} is not CPack's ldconfig call alone:\n${_text}")
        endif()
        file(REMOVE "${_root}/DEBIAN/${_script}")
    endforeach()
    execute_process(COMMAND dpkg-deb --root-owner-group -Zxz -b "${_root}" "${_deb}"
        RESULT_VARIABLE _rc OUTPUT_QUIET)
    file(REMOVE_RECURSE "${_root}")
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "ldconfig trigger: dpkg-deb -b ${_deb} failed (${_rc})")
    endif()
endforeach()
