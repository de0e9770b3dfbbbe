#!/bin/sh
# `play` under a small stack limit (`ulimit -s`, issue 60): glibc sizes every thread's stack from
# it, and at 48 KiB the FFmpeg decoders or the EGL driver overflowed theirs (SIGSEGV, no word).
# A small soft limit is raised at start (platform/stack_limit.h) and the clip plays; a hard limit
# below what depthtouch needs is one line naming `ulimit -s` and exit 1.
# Usage: stack_limit_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
e2e_need prlimit
"$exe" backends | grep -q headless || { echo "SKIP: no headless display in this build"; exit 77; }
e2e_work stack-limit
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg" # no config of this machine
"$exe" encode --color synthetic:head,size=160x120,frames=30 --depth synthetic:head,size=160x120,frames=30 \
    --preset ultrafast -o "$work/head.mkv" >"$work/encode.out" 2>&1 || fail "encode: $(cat "$work/encode.out")"

# play_limited OUT LIMIT: the clip on the headless display under prlimit --stack=LIMIT.
play_limited() {
    prlimit --stack="$2" -- "$exe" play "$work/head.mkv" --display headless --haptic none --no-audio \
        --quiet >"$work/$1.out" 2>"$work/$1.err" </dev/null
}

play_limited soft 49152:unlimited
rc=$?
[ "$rc" = 0 ] || fail "a 48 KiB soft stack limit: exit $rc ($(cat "$work/soft.err"))"
play_limited hard 49152:49152
rc=$?
[ "$rc" = 1 ] || fail "a 48 KiB hard stack limit: exit $rc, not 1 ($(cat "$work/hard.err"))"
[ "$(wc -l <"$work/hard.err")" = 1 ] || fail "a 48 KiB hard stack limit: not one line: $(cat "$work/hard.err")"
grep -q "ulimit -s" "$work/hard.err" || fail "the line does not name ulimit -s: $(cat "$work/hard.err")"
echo "stack limit: 48 KiB soft raised and played; 48 KiB hard: '$(cat "$work/hard.err")'"
