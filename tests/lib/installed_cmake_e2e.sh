#!/bin/sh
# The CMake way in (issue 62): the libdepthtouch and libdepthtouch_dev components (the files of the
# packages libdepthtouch0 and libdepthtouch-dev) installed with DESTDIR into a scratch root, then a
# small CMake project that says only find_package(DepthTouch 0.1 REQUIRED) and links
# DepthTouch::depthtouch, configured with CMAKE_PREFIX_PATH=<root><prefix>: it finds the package
# config under lib/<multiarch>/cmake/DepthTouch, builds the C99 program of client_c_scenario.c
# against the installed header and library (not the build tree's), and the program plays a mock
# clip. A request for another major version (find_package(DepthTouch 1)) is refused by the version
# file.
# Usage: installed_cmake_e2e.sh CMAKE BUILD_DIR SOURCE_DIR CC GENERATOR MAKE_PROGRAM
. "$(dirname "$0")/../e2e_lib.sh"
cmake_exe=$1
build=$2
src=$3
cc=$4
generator=$5
make_program=$6
e2e_start installed-cmake "$cc"

root="$work/root"
for component in libdepthtouch libdepthtouch_dev; do
    DESTDIR="$root" "$cmake_exe" --install "$build" --component $component >"$work/install.log" 2>&1 ||
        fail "the $component component did not install: $(cat "$work/install.log")"
done
config=$(find "$root" -name depthtouch-config.cmake)
[ -n "$config" ] || fail "no depthtouch-config.cmake installed: $(cd "$root" && find . | sort)"
# <root><prefix>/lib/<multiarch>/cmake/DepthTouch/depthtouch-config.cmake
prefix=$(dirname "$config")
for _ in 1 2 3; do prefix=$(dirname "$prefix"); done
case $prefix in */lib) prefix=$(dirname "$prefix") ;; esac
[ -f "$prefix/include/depthtouch/client.h" ] || fail "no include/depthtouch/client.h beside $config"

mkdir -p "$work/app"
cp "$src/tests/lib/client_c_scenario.c" "$src/tests/lib/client_c_scenario.h" "$work/app/"
cat >"$work/app/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(embedder LANGUAGES C)
if(NOT DEFINED WANT_VERSION)
    set(WANT_VERSION 0.1)
endif()
find_package(DepthTouch ${WANT_VERSION} REQUIRED)
message(STATUS "DepthTouch ${DepthTouch_VERSION} from ${DepthTouch_DIR}")
get_target_property(lib DepthTouch::depthtouch LOCATION)
get_target_property(inc DepthTouch::depthtouch INTERFACE_INCLUDE_DIRECTORIES)
message(STATUS "DepthTouch::depthtouch: ${lib}; include ${inc}")
add_executable(app main.c client_c_scenario.c)
set_target_properties(app PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
target_compile_options(app PRIVATE -Wall -Wextra -Wpedantic -Werror)
target_link_libraries(app PRIVATE DepthTouch::depthtouch)
CMAKE
cat >"$work/app/main.c" <<'C'
#include <stdio.h>

#include "client_c_scenario.h"

int main(void)
{
    char why[256] = "";
    const int line = dt_test_c_scenario("mock://clip?frames=60&fps=30", why, sizeof why);
    if (line != 0) {
        fprintf(stderr, "client_c_scenario.c:%d: %s\n", line, why);
        return 1;
    }
    puts("played");
    return 0;
}
C
configure() {
    "$cmake_exe" -S "$work/app" -B "$1" -G "$generator" -DCMAKE_MAKE_PROGRAM="$make_program" \
        -DCMAKE_C_COMPILER="$cc" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
        -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF "$2"
}
configure "$work/app-build" -DWANT_VERSION=0.1 >"$work/configure.log" 2>&1 ||
    fail "find_package(DepthTouch 0.1) against $prefix failed: $(cat "$work/configure.log")"
grep -q "DepthTouch::depthtouch: $root/" "$work/configure.log" ||
    fail "DepthTouch::depthtouch is not the installed library: $(grep DepthTouch "$work/configure.log")"
grep -q "include $prefix/include" "$work/configure.log" ||
    fail "DepthTouch::depthtouch's include folder is not the installed one: $(grep DepthTouch "$work/configure.log")"
"$cmake_exe" --build "$work/app-build" >"$work/build.log" 2>&1 ||
    fail "the program did not build against the installed library: $(cat "$work/build.log")"
# The library's folder, as the package would have it in the loader's path.
LD_LIBRARY_PATH=$(dirname "$(grep -o "DepthTouch::depthtouch: [^;]*" "$work/configure.log" | cut -d' ' -f2)") \
    "$work/app-build/app" >"$work/run.log" 2>&1 || fail "the program failed: $(cat "$work/run.log")"
grep -qx played "$work/run.log" || fail "no 'played': $(cat "$work/run.log")"
configure "$work/app-build-1" -DWANT_VERSION=1 >"$work/configure-1.log" 2>&1 &&
    fail "find_package(DepthTouch 1) found the 0.x library: $(cat "$work/configure-1.log")"
grep -q "depthtouch-config.cmake, version: " "$work/configure-1.log" ||
    fail "find_package(DepthTouch 1) failed, but not on the version: $(cat "$work/configure-1.log")"
echo "PASS: a CMake project with find_package(DepthTouch) built against the installed library and played a clip"
