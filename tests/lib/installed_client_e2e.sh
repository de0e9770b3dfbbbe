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

# The minimal program of docs/embedding.md as a reader copies it, built the same way and run on a
# clip `depthtouch encode` writes (1 s): it prints time-pos as the clip plays and ends at end-file.
awk '/^## A minimal program/ { f = 1 } f && /^```c/ { c = 1; next } c && /^```/ { exit } c' \
    "$src/docs/embedding.md" >"$work/minimal.c"
[ -s "$work/minimal.c" ] || fail "no C block under '## A minimal program' in docs/embedding.md"
# shellcheck disable=SC2046 # pkg-config's flags are words
"$cc" -std=c99 -Wall -Wextra -Werror "$work/minimal.c" $(pkg-config --cflags --libs depthtouch) \
    -o "$work/minimal" || fail "docs/embedding.md's minimal program did not build"
clip="$work/clip.mkv"
"$build/app/cli/depthtouch" encode --color synthetic:head,size=160x120,frames=30 \
    --depth synthetic:head,size=160x120,frames=30 -o "$clip" --preset ultrafast \
    >"$work/encode.out" 2>&1 || fail "encode: $(cat "$work/encode.out")"
LD_LIBRARY_PATH=$(pkg-config --variable=libdir depthtouch) timeout 60 "$work/minimal" "$clip" \
    >"$work/minimal.log" 2>&1 || fail "the minimal program failed: $(cat "$work/minimal.log")"
grep -q '^time-pos = [0-9.]* s$' "$work/minimal.log" ||
    fail "the minimal program printed no time-pos: $(cat "$work/minimal.log")"
echo "PASS: a C program built with pkg-config against the installed libdepthtouch played a clip"
