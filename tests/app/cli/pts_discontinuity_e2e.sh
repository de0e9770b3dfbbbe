#!/bin/sh
# End-to-end (issue 60): timestamp discontinuities do not freeze or end the picture. One 3 s clip
# (90 frame pairs) is encoded to MPEG-TS and its bytes are joined as a broadcast splice, an encoder
# restart or a looped feed join them, keeping each segment's own timestamps (`cat`, not the concat
# demuxer, which would make them continuous):
#   forward  the clip, then the clip 1000 s later (a splice)            180 pairs
#   backward the clip 100 s later, then the clip (a jump back)          180 pairs
#   reset    the clip 60 s later, then the clip starting at PTS 0       180 pairs
#   repeat   the clip three times over (the same 3 s)                   270 pairs
# `play` must present about every pair (one per stream may be lost at each jump: the frame that
# shows it) and end at the end of the input, not after 90 pairs nor at a --duration.
# Exit 77 (skip) without the ffmpeg CLI tools. Usage: pts_discontinuity_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start pts_discontinuity ffmpeg ffprobe

ff -f lavfi -i "testsrc2=s=160x120:r=30:d=3" -pix_fmt yuv420p "$work/c.mkv" || fail "ffmpeg color"
ff -f lavfi -i "testsrc2=s=160x120:r=30:d=3,format=gray" "$work/d.mkv" || fail "ffmpeg depth"
"$exe" encode --color "$work/c.mkv" --depth "$work/d.mkv" --near 1 --far 2 --preset ultrafast \
    -o "$work/a.ts" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode"; }
shift_ts() { # seconds, output: the clip's timestamps moved by that much
    ff -i "$work/a.ts" -map 0 -c copy -output_ts_offset "$1" "$2" || fail "ffmpeg shift $1"
}
shift_ts 1000 "$work/a1000.ts"
shift_ts 100 "$work/a100.ts"
shift_ts 60 "$work/a60.ts"
ff -i "$work/a.ts" -map 0 -c copy -muxdelay 0 -muxpreload 0 "$work/a0.ts" || fail "ffmpeg zero"
cat "$work/a.ts" "$work/a1000.ts" >"$work/forward.ts"
cat "$work/a100.ts" "$work/a.ts" >"$work/backward.ts"
cat "$work/a60.ts" "$work/a0.ts" >"$work/reset.ts"
cat "$work/a.ts" "$work/a.ts" "$work/a.ts" >"$work/repeat.ts"

# kind, pairs wanted, jumps. --duration bounds a frozen picture (it ends there with about 90 pairs:
# the pairs presented tell; the wall time is only printed, a busy machine takes longer).
check() {
    start=$(date +%s)
    "$exe" play "$work/$1.ts" --display mock --haptic none --no-config --audio-device none \
        --max-lateness 10 --duration 30 --stats "$work/$1.json" >"$work/$1.log" 2>&1 ||
        { cat "$work/$1.log"; fail "play $1"; }
    took=$(( $(date +%s) - start ))
    python3 - "$work/$1.json" "$1" "$2" "$3" "$took" <<'PY' || { cat "$work/$1.log"; fail "$1"; }
import json, sys
j = json.load(open(sys.argv[1]))
kind, want, jumps, took = sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
got = j["frames_presented"]
if got < want - 2 * jumps - 2:
    sys.exit("%s: presented %d of %d frame pairs" % (kind, got, want))
print("pts_discontinuity: %s: %d of %d frame pairs presented in %d s" % (kind, got, want, took))
PY
}
check forward 180 1
check backward 180 1
check reset 180 1
check repeat 270 2
