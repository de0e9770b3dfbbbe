#!/bin/sh
# `encode` for scripts, as ffmpeg (issue 61, item 10): an output file that exists is replaced only
# with -y (without it, or with -n, one line and exit 2, the file untouched); --progress writes
# ffmpeg's -progress blocks (frame=, fps=, out_time_us=, progress=continue|end) to a file or
# pipe:1, and a progress file that cannot be written is lost output (exit 1).
# Usage: encode_overwrite_e2e.sh /path/to/depthtouch
set -u
exe=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
"$exe" backends | grep -q headless || { echo "SKIP: no headless display for the synthetic head"; exit 77; }
e2e_work encode-overwrite
cd "$work" || exit 1
enc() {
    "$exe" encode --color synthetic:head,size=160x120,frames=30 \
        --depth synthetic:head,size=160x120,frames=30 --preset ultrafast "$@"
}

echo "not a clip" >kept.mkv
enc -o kept.mkv >refused.out 2>refused.err
rc=$?
[ "$rc" = 2 ] || fail "an existing output without -y: exit $rc, not 2"
[ "$(cat kept.mkv)" = "not a clip" ] || fail "an existing output without -y was replaced"
[ "$(wc -l <refused.err)" = 1 ] && grep -q "exists: -y replaces it" refused.err ||
    fail "an existing output without -y: the line is '$(cat refused.err)'"
enc -o kept.mkv -n >/dev/null 2>&1 && fail "-n replaced an existing output"
[ "$(cat kept.mkv)" = "not a clip" ] || fail "-n replaced an existing output"
enc -o kept.mkv -y >/dev/null 2>replaced.err || fail "-y: exit $? ($(cat replaced.err))"
"$exe" probe kept.mkv >probe.out 2>&1 || fail "-y did not write a clip: $(cat probe.out)"
enc -o other.mkv -y -n >/dev/null 2>both.err && fail "-y with -n was accepted"

enc -o p.mkv --progress pipe:1 >progress.out 2>progress.err || fail "--progress pipe:1: exit $?"
grep -q "^frame=30$" progress.out || fail "--progress: no frame=30 line: $(tail -8 progress.out)"
grep -q "^out_time_us=1000000$" progress.out || fail "--progress: 30 frames at 30 fps are not 1 s"
[ "$(grep '^progress=' progress.out | tail -1)" = "progress=end" ] || fail "--progress: no progress=end last"
[ "$(grep -c '^progress=end$' progress.out)" = 1 ] || fail "--progress: progress=end more than once"
enc -o q.mkv --progress progress.txt >/dev/null 2>&1 || fail "--progress FILE: exit $?"
grep -q "^progress=end$" progress.txt || fail "--progress FILE: no progress=end"
enc -o r.mkv --progress /dev/full >/dev/null 2>full.err
rc=$?
[ "$rc" = 1 ] || fail "--progress /dev/full: exit $rc, not 1 (lost output)"
grep -q "cannot write the progress" full.err || fail "--progress /dev/full: '$(cat full.err)'"
# A raw video input has no header with its size: the line says which options give it (it said
# "Failed to open the input (Io, Invalid argument)").
head -c 57600 /dev/zero >raw.yuv
"$exe" encode --color synthetic:head,size=160x120,frames=3 --depth raw.yuv -o raw.mkv >raw.out 2>raw.err
rc=$?
[ "$rc" = 2 ] || fail "a raw .yuv depth input without its size: exit $rc, not 2"
grep -q -- "--depth-video-size WxH" raw.err || fail "a raw input without its size: '$(cat raw.err)'"
echo "encode: -y/-n as ffmpeg's, --progress blocks ending in progress=end, raw input sizes asked for"
