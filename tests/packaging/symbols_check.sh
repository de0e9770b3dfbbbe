#!/bin/sh
# The symbols file of libdepthtouch0 (packaging/libdepthtouch0.symbols, shipped in the package's
# control) against the built library, as dh_makeshlibs checks it: dpkg-gensymbols -c4 fails when
# the library exports a symbol the file lacks, or lacks one the file lists (an ABI change that the
# file, and the soname when a symbol goes away, must follow). The check runs as for the release
# after this one (VERSION+check): dpkg-gensymbols forgives a symbol missing that the file dates to
# the version being built, which would hide one taken away before the first release. Every listed
# symbol carries the version node DEPTHTOUCH_0 of lib/depthtouch.map.
# Usage: symbols_check.sh SYMBOLS-FILE LIBRARY VERSION DEBIAN-ARCH
. "$(dirname "$0")/../e2e_lib.sh"
symbols=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
lib=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
version=$3
arch=$4
e2e_start symbols dpkg-gensymbols
grep -q '^libdepthtouch\.so\.0 libdepthtouch0 #MINVER#$' "$symbols" ||
    fail "$symbols does not open with 'libdepthtouch.so.0 libdepthtouch0 #MINVER#'"
grep '^ ' "$symbols" | grep -v '^ [A-Za-z0-9_]*@DEPTHTOUCH_0 [0-9][0-9.]*$' &&
    fail "the lines above are not 'name@DEPTHTOUCH_0 version'"
# DEB_HOST_ARCH: dpkg-gensymbols reads a cross build's library with that target's objdump.
(cd "$work" && DEB_HOST_ARCH=$arch dpkg-gensymbols -c4 -plibdepthtouch0 -v"$version+check" -a"$arch" \
    -e"$lib" -I"$symbols" -O"$work/symbols" >"$work/diff" 2>&1) ||
    fail "the library's symbols differ from $symbols (dpkg-gensymbols -c4; '+' a symbol to list with
the version that brings it, $version; '#MISSING' one the library no longer exports):
$(cat "$work/diff")"
listed=$(grep -c '^ ' "$symbols")
echo "PASS: the library exports the $listed symbols of $(basename "$symbols"), no more, no fewer"
