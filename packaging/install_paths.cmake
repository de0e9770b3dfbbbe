# Run by `cmake --install` (and by CPack, which installs with the prefix /usr): the files whose path
# or content depends on the prefix, worked out with the prefix of this install, not the one the build
# was configured with, so that `cmake --install build --prefix P` stays inside P. The configuration
# folder follows GNUInstallDirs' rule (/etc for the prefix /usr, P/etc otherwise) and the unit names
# the program where this install puts it. DESTDIR applies (file(INSTALL) prepends it).
# Set by packaging/CMakeLists.txt: DT_PACKAGING_SOURCE, DT_PACKAGING_BINARY, DT_INSTALL_BINDIR,
# DT_INSTALL_DOCDIR (relative to the prefix).
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
    set(DT_CONFIG_DIR "/etc/depthtouch")
else()
    set(DT_CONFIG_DIR "${CMAKE_INSTALL_PREFIX}/etc/depthtouch")
endif()
set(DT_BINDIR "${CMAKE_INSTALL_PREFIX}/${DT_INSTALL_BINDIR}")
set(DT_DOC_DIR "${CMAKE_INSTALL_PREFIX}/${DT_INSTALL_DOCDIR}")
configure_file("${DT_PACKAGING_SOURCE}/depthtouch.service.in"
    "${DT_PACKAGING_BINARY}/install/depthtouch.service" @ONLY)
file(INSTALL "${DT_PACKAGING_BINARY}/install/depthtouch.service"
    DESTINATION "${CMAKE_INSTALL_PREFIX}/lib/systemd/system")
file(INSTALL "${DT_PACKAGING_SOURCE}/play.toml" DESTINATION "${DT_CONFIG_DIR}")
