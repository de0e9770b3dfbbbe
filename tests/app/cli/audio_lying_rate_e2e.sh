#!/bin/sh
# End-to-end (issue 60, class 5): a sound whose header lies about its rate is refused as bad audio,
# not resampled by whatever ratio it gives. A 4 s clip (color, depth) gets 8-channel 48 kHz PCM
# in MKV; its SamplingFrequency element is then patched to 1 Hz and to 1e9 Hz.
# Before: 1 Hz was resampled to 48 kHz with buffers sized by the ratio (3.95 GB peak RSS for
# `--duration 3`) and 1e9 Hz took seconds to stop. Now, for each:
#   `play --duration 3` exits 0, the picture plays on (frames presented), no sound is played
#   (the stats' "audio" empty, no WAV written) and one note says why, with the rate the stream
#   gave; the peak RSS (/usr/bin/time -v where installed) stays under 500 MiB;
#   `play --loop` stopped by SIGTERM exits 0 (judged by its stopping at all within the test's
#   time-out; the wall time is printed, not checked).
# A true rate at the edge of the range (8 kHz) still plays its sound.
# Exit 77 (skip) without the ffmpeg CLI or python3. Usage: audio_lying_rate_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start audio_lying_rate ffmpeg python3

ff -f lavfi -i testsrc=size=96x72:rate=30:duration=4 -pix_fmt yuv420p -c:v libx264 -preset ultrafast \
    "$work/film.mkv" || fail "ffmpeg film"
ff -f lavfi -i testsrc=size=96x72:rate=30:duration=4 -vf format=gray -c:v libx264 -preset ultrafast \
    "$work/depth.mkv" || fail "ffmpeg depth"
"$exe" encode --color "$work/film.mkv" --depth "$work/depth.mkv" --preset ultrafast -o "$work/v.mkv" \
    >"$work/log" 2>&1 || { cat "$work/log"; fail "encode"; }
ff -i "$work/v.mkv" -f lavfi -i "sine=f=440:r=48000:d=4" -map 0 -map 1 -ac 8 -c:v copy -c:a pcm_s16le \
    "$work/a8.mkv" || fail "ffmpeg 8-channel sound"
ff -i "$work/v.mkv" -f lavfi -i "sine=f=440:r=8000:d=4" -map 0 -map 1 -c:v copy -c:a pcm_s16le \
    "$work/a8k.mkv" || fail "ffmpeg 8 kHz sound"
python3 - "$work" <<'PY' || fail "patching the rate"
import struct, sys
work = sys.argv[1]
data = open(work + "/a8.mkv", "rb").read()
tag = b"\xb5\x88" + struct.pack(">d", 48000.0)  # SamplingFrequency, an 8-byte float
if data.count(tag) != 1:
    sys.exit("no single 48000 Hz SamplingFrequency element")
for name, rate in (("r1", 1.0), ("r1e9", 1e9)):
    open("%s/%s.mkv" % (work, name), "wb").write(data.replace(tag, b"\xb5\x88" + struct.pack(">d", rate)))
PY

timed=""
[ -x /usr/bin/time ] && /usr/bin/time -v true >/dev/null 2>&1 && timed="/usr/bin/time -v -o"
for case in r1:1 r1e9:1000000000; do
    name=${case%%:*}
    rate=${case#*:}
    if [ -n "$timed" ]; then
        $timed "$work/$name.time" "$exe" play "$work/$name.mkv" --display mock --haptic none --no-config \
            --audio-device wav --audio-device-options "path=$work/$name.wav" --duration 3 \
            --stats "$work/$name.json" >"$work/$name.log" 2>&1
    else
        "$exe" play "$work/$name.mkv" --display mock --haptic none --no-config --audio-device wav \
            --audio-device-options "path=$work/$name.wav" --duration 3 --stats "$work/$name.json" \
            >"$work/$name.log" 2>&1
    fi
    rc=$?
    [ "$rc" -eq 0 ] || { cat "$work/$name.log"; fail "$name: play exited $rc, want 0 (the picture plays without sound)"; }
    presented=$(sed -n 's/.*"frames_presented": *\([0-9]*\).*/\1/p' "$work/$name.json")
    [ "${presented:-0}" -gt 0 ] || { cat "$work/$name.json"; fail "$name: no frame presented"; }
    grep -q '"audio": *""' "$work/$name.json" && [ ! -e "$work/$name.wav" ] ||
        { cat "$work/$name.log"; fail "$name: a sound was played"; }
    note="no sound: The sound's sample rate is outside 8000..384000 Hz (the stream says $rate Hz)"
    [ "$(grep -c "sample rate is outside" "$work/$name.log")" -eq 1 ] && grep -qF "$note" "$work/$name.log" &&
        grep -qF "\"$note\"" "$work/$name.json" ||
        { cat "$work/$name.log"; fail "$name: want one note: $note"; }
    rss=""
    if [ -n "$timed" ]; then
        rss=$(sed -n 's/.*Maximum resident set size (kbytes): *\([0-9]*\).*/\1/p' "$work/$name.time")
        [ "${rss:-0}" -gt 0 ] && [ "$rss" -lt 512000 ] ||
            { cat "$work/$name.time"; fail "$name: peak RSS $rss kB, want under 500 MiB"; }
    fi
    # SIGTERM while it plays (looping, the sound refused): it stops, exit 0.
    "$exe" play "$work/$name.mkv" --display mock --haptic none --no-config --audio-device wav \
        --audio-device-options "path=$work/$name-loop.wav" --loop >"$work/$name-loop.log" 2>&1 &
    e2e_bg=$!
    sleep 1.5
    t0=$(date +%s.%N)
    kill -TERM "$e2e_bg"
    wait "$e2e_bg"
    rc=$?
    e2e_bg=""
    t1=$(date +%s.%N)
    [ "$rc" -eq 0 ] || { cat "$work/$name-loop.log"; fail "$name: exit $rc after SIGTERM, want 0"; }
    echo "$name: $presented frames presented without sound; peak RSS ${rss:-?} kB;" \
        "$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }') s from SIGTERM to exit"
done

# A true 8 kHz sound (the range's lower edge) plays.
"$exe" play "$work/a8k.mkv" --display mock --haptic none --no-config --audio-device wav \
    --audio-device-options "path=$work/a8k.wav" --duration 3 --stats "$work/a8k.json" >"$work/a8k.log" 2>&1 ||
    { cat "$work/a8k.log"; fail "8 kHz: play"; }
grep -q '"audio": *"8000 Hz 1 ch"' "$work/a8k.json" && [ -s "$work/a8k.wav" ] ||
    { cat "$work/a8k.log"; fail "8 kHz: the sound is played"; }
echo PASS
