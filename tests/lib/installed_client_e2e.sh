#!/bin/sh
# The integrator's way in (issue 62): libdepthtouch installed alone (`cmake --install BUILD
# --component libdepthtouch` and `--component libdepthtouch_dev`, `--prefix P`: the files of the
# packages libdepthtouch0 and libdepthtouch-dev), a C99 program compiled only against the installed
# header and `pkg-config --cflags --libs depthtouch`, run against the installed library: it plays a mock
# clip (client_c_scenario.c: options, loadfile, file-loaded, pause's property change, time-pos
# advancing, an asynchronous seek, stop's end-file).
# Usage: installed_client_e2e.sh CMAKE BUILD_DIR SOURCE_DIR CC
. "$(dirname "$0")/../e2e_lib.sh"
cmake_exe=$1
build=$2
src=$3
cc=$4
e2e_start installed-client pkg-config "$cc"

for component in libdepthtouch libdepthtouch_dev; do
    "$cmake_exe" --install "$build" --component $component --prefix "$work/prefix" >"$work/install.log" 2>&1 ||
        fail "the $component component did not install: $(cat "$work/install.log")"
done
[ -z "$(find "$work/prefix" -name 'depthtouch' -type f -path '*/bin/*')" ] ||
    fail "the components installed the program too"
pc=$(find "$work/prefix" -name depthtouch.pc)
[ -n "$pc" ] || fail "no depthtouch.pc installed"
PKG_CONFIG_PATH=$(dirname "$pc")
export PKG_CONFIG_PATH
cat >"$work/main.c" <<'EOF'
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
EOF
# Only the installed header: the source tree's lib/include is not on the path.
# shellcheck disable=SC2046 # pkg-config's flags are words
"$cc" -std=c99 -Wall -Wextra -Wpedantic -Werror -I"$src/tests/lib" "$work/main.c" \
    "$src/tests/lib/client_c_scenario.c" $(pkg-config --cflags --libs depthtouch) -o "$work/app" ||
    fail "the program did not build against the installed library"
LD_LIBRARY_PATH=$(pkg-config --variable=libdir depthtouch) "$work/app" >"$work/run.log" 2>&1 ||
    fail "the program failed: $(cat "$work/run.log")"
grep -qx played "$work/run.log" || fail "no 'played': $(cat "$work/run.log")"
echo "PASS: a C program built with pkg-config against the installed libdepthtouch played a clip"
