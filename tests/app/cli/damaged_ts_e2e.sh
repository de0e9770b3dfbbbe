#!/bin/sh
# End-to-end (issue 60): a damaged MPEG-TS decodes on as ffmpeg decodes it, not from the next key
# frame. A 3 s clip (90 frame pairs, one key frame: x264's 250-frame interval) is encoded to
# MPEG-TS and 5 % of the 188-byte TS packets of its middle third are dropped (continuity errors,
# PES packets cut or merged), one file per seed. libavcodec then keeps back the pictures it cannot
# place or decode for a while; the receiver took that lag for a stream that stopped, drained its
# decoder and flushed it when its packets came on, and the flushed decoder gave nothing until the
# next key frame (where it was written, seed 1 gave 32 depth frames of ffmpeg's 74; seeds 4 and 6
# lost colour that way).
# For each file, `probe --decode` must give each stream's frames as ffprobe -count_frames counts
# them, the independent count: at most 3 fewer, and never more (a picture ffmpeg withholds is one
# libavcodec cannot vouch for: predicted from pictures that were lost); `play` of the first must
# exit 0 with as many frames decoded and the damaged ones counted as concealed.
# Exit 77 (skip) without the ffmpeg CLI tools. Usage: damaged_ts_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start damaged_ts ffmpeg ffprobe python3

ff -f lavfi -i "testsrc2=s=160x120:r=30:d=3" -pix_fmt yuv420p "$work/c.mkv" || fail "ffmpeg color"
ff -f lavfi -i "testsrc2=s=160x120:r=30:d=3,format=gray" "$work/d.mkv" || fail "ffmpeg depth"
"$exe" encode --color "$work/c.mkv" --depth "$work/d.mkv" --near 1 --far 2 --preset ultrafast \
    -o "$work/a.ts" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode"; }

seeds="1 2 3 4 5 6"
for seed in $seeds; do
    python3 - "$work/a.ts" "$work/s$seed.ts" "$seed" <<'PY' || fail "damage $seed"
import random, sys
data = open(sys.argv[1], "rb").read()
n = len(data) // 188
rng = random.Random(int(sys.argv[3]))
out = bytearray()
for i in range(n):
    if n // 3 <= i < 2 * n // 3 and rng.random() < 0.05:
        continue  # dropped: the continuity counters of its PID skip one
    out += data[i * 188:(i + 1) * 188]
open(sys.argv[2], "wb").write(out)
PY
done
frames() { # file, video stream: the frames ffmpeg's decoder gives
    ffprobe -v quiet -count_frames -select_streams "v:$2" -show_entries stream=nb_read_frames \
        -of default=nw=1:nk=1 "$1" | head -n 1
}
lost=0
for seed in $seeds; do
    f="$work/s$seed.ts"
    color=$(frames "$f" 0)
    depth=$(frames "$f" 1)
    if [ -z "$color" ] || [ -z "$depth" ]; then fail "seed $seed: ffprobe counted no frames"; fi
    lost=$((lost + 180 - color - depth))
    "$exe" probe "$f" --decode --json >"$work/p$seed.json" 2>"$work/log" ||
        { cat "$work/log"; fail "probe --decode seed $seed"; }
    python3 - "$work/p$seed.json" "$seed" "$color" "$depth" <<'PY' || fail "seed $seed"
import json, sys
d = json.load(open(sys.argv[1]))["decode"]
seed, want = sys.argv[2], {"color": int(sys.argv[3]), "depth": int(sys.argv[4])}
for kind in ("color", "depth"):
    got = d[kind + "_frames"]
    if got < want[kind] - 3 or got > want[kind]:
        sys.exit("seed %s: %d %s frames decoded, ffmpeg decodes %d" % (seed, got, kind, want[kind]))
print("damaged_ts: seed %s: color %d (ffmpeg %d), depth %d (ffmpeg %d), %d concealed"
      % (seed, d["color_frames"], want["color"], d["depth_frames"], want["depth"], d["concealed"]))
PY
done
# The damage must cost ffmpeg frames too, or there is nothing to compare.
[ "$lost" -gt 0 ] || fail "the damaged files lost no frames in ffmpeg's decoding"

f="$work/s1.ts"
want=$(( $(frames "$f" 0) + $(frames "$f" 1) ))
"$exe" play "$f" --display mock --haptic none --no-config --audio-device none \
    --max-lateness 10 --stats "$work/s.json" >"$work/log" 2>&1 || { cat "$work/log"; fail "play"; }
python3 - "$work/s.json" "$want" <<'PY' || { cat "$work/log"; fail "play stats"; }
import json, sys
j, want = json.load(open(sys.argv[1])), int(sys.argv[2])
got = j["frames_decoded"]
if got < want - 3 or got > want:
    sys.exit("play decoded %d color + depth frames, ffmpeg decodes %d" % (got, want))
if j["frames_concealed"] < 1:
    sys.exit("no frame pair counted as concealed in a damaged file")
print("damaged_ts: play: %d of ffmpeg's %d frames decoded, %d pairs presented, %d concealed"
      % (got, want, j["frames_presented"], j["frames_concealed"]))
PY
