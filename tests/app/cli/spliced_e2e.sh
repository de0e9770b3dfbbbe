#!/bin/sh
# End-to-end: a stream whose pictures change size part-way plays to its end. Two clips encoded at
# 320x240 (3 s) and 160x120 (2 s), joined by ffmpeg's concat demuxer into one MPEG-TS (as a
# broadcast splice or an HLS rendition switch joins them): `play` presents every one of the 150
# frame pairs at the first clip's size, against the frame counts ffprobe reads in the two clips.
# Exit 77 (skip) without the ffmpeg CLI tools. Usage: spliced_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start spliced ffmpeg ffprobe

clip() { # name, size, seconds
    ff -f lavfi -i "testsrc2=s=$2:r=30:d=$3" -pix_fmt yuv420p "$work/c$1.mkv" || fail "ffmpeg color $1"
    ff -f lavfi -i "testsrc2=s=$2:r=30:d=$3,format=gray" "$work/d$1.mkv" || fail "ffmpeg depth $1"
    "$exe" encode --color "$work/c$1.mkv" --depth "$work/d$1.mkv" --near 1 --far 2 --preset ultrafast \
        -o "$work/$1.ts" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode $1"; }
}
clip a 320x240 3
clip b 160x120 2
printf "file '%s'\nfile '%s'\n" "$work/a.ts" "$work/b.ts" >"$work/list.txt"
ff -f concat -safe 0 -i "$work/list.txt" -map 0 -c copy "$work/ab.ts" || fail "ffmpeg concat"
frames() { ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
    -of default=nw=1:nk=1 "$1" | head -n 1; }
want=$(( $(frames "$work/a.ts") + $(frames "$work/b.ts") ))
[ "$want" -eq 150 ] || fail "the two clips hold $want frames, want 150"

# Late frames are drawn, not dropped (--max-lateness 10): what is checked is that the decoder keeps
# the frames after the size change, whatever the machine's load (under ASan on a busy machine the
# player dropped 10 of 150 frames as late).
"$exe" play "$work/ab.ts" --display mock --haptic none --no-config --audio-device none \
    --max-lateness 10 --stats "$work/s.json" >"$work/log" 2>&1 || { cat "$work/log"; fail "play"; }
python3 - "$work/s.json" "$want" <<'PY' || { cat "$work/log"; fail "stats"; }
import json, sys
j, want = json.load(open(sys.argv[1])), int(sys.argv[2])
if j["frames_presented"] != want:
    sys.exit("presented %d of %d frame pairs: the frames after the size change were lost"
             % (j["frames_presented"], want))
if j["color_size"] != [320, 240] or j["depth_size"] != [320, 240]:
    sys.exit("sizes %s / %s, want the first clip's 320x240" % (j["color_size"], j["depth_size"]))
print("spliced: %d of %d frame pairs presented at %s" % (j["frames_presented"], want, j["color_size"]))
PY
