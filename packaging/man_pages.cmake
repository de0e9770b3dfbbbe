# Writes the man pages from the program's own --help (help2man), so they list exactly the options of
# the command-line tables: depthtouch(1) for the program and depthtouch-COMMAND(1) for each command
# (as git and systemd name theirs), each gzip -9n (Debian policy 12.1). Fails when --help lists a
# command that COMMANDS lacks or the other way round, so a new command cannot ship without its page.
# cmake -DPROGRAM=<depthtouch> -DHELP2MAN=<help2man> -DGZIP=<gzip> -DOUT_DIR=<dir> "-DCOMMANDS=a;b"
#       -P man_pages.cmake
execute_process(COMMAND "${PROGRAM}" --help OUTPUT_VARIABLE top RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "man pages: '${PROGRAM} --help' exited with ${rc}")
endif()
string(REGEX REPLACE ".*\nSubcommands:\n" "" listing "${top}")
string(REGEX MATCHALL "(^|\n)  [a-z][a-z0-9-]*" listed "${listing}")
string(REGEX REPLACE "(^|\n)  " "" listed "${listed}")
if(NOT "${listed}" STREQUAL "${COMMANDS}")
    message(FATAL_ERROR "man pages: --help lists the commands '${listed}', packaging/CMakeLists.txt "
                        "'${COMMANDS}': add the new one to DT_MAN_COMMANDS")
endif()

# One page: help2man with HELP_OPTION, renamed to PAGE (its title and NAME line) and compressed.
function(write_page page help_option summary)
    set(file "${OUT_DIR}/${page}.1")
    execute_process(COMMAND "${HELP2MAN}" --no-info --no-discard-stderr "--help-option=${help_option}"
            --version-option=--version "--name=${summary}" "--include=${OUT_DIR}/see-also.h2m"
            --output "${file}" "${PROGRAM}"
        RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "man pages: help2man for ${page} exited with ${rc}: ${err}")
    endif()
    file(READ "${file}" text)
    string(TOUPPER "${page}" title)
    string(REGEX REPLACE "\n\\.TH DEPTHTOUCH " "\n.TH ${title} " text "${text}")
    string(REGEX REPLACE "\n\\.SH NAME\ndepthtouch \\\\- " "\n.SH NAME\n${page} \\\\- " text "${text}")
    file(WRITE "${file}" "${text}")
    execute_process(COMMAND "${GZIP}" -9n -f "${file}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "man pages: gzip ${file} exited with ${rc}")
    endif()
endfunction()

set(see_also "[SEE ALSO]\n.BR depthtouch (1)")
foreach(cmd ${COMMANDS})
    string(APPEND see_also ",\n.BR depthtouch-${cmd} (1)")
endforeach()
string(APPEND see_also "\n.PP\nThe documentation: /usr/share/doc/depthtouch/README.md and docs/.\n")
file(WRITE "${OUT_DIR}/see-also.h2m" "${see_also}")

write_page(depthtouch --help "touchable 3D video: play, make and touch color + depth video")
foreach(cmd ${COMMANDS})
    if(NOT listing MATCHES "(^|\n)  ${cmd} +([^\n]+)")
        message(FATAL_ERROR "man pages: no summary of ${cmd} in --help")
    endif()
    write_page(depthtouch-${cmd} "${cmd} --help" "${CMAKE_MATCH_2}")
endforeach()
