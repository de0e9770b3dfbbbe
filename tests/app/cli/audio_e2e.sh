#!/bin/sh
# End-to-end: `encode` keeps the sound of its color input, or takes
# --audio's, on the picture's timeline. The color source is a 3 s clip whose sound is silent but
# for a 5 ms click at 1.000 s; in every output (MKV, MP4, MPEG-TS; copied AAC, and PCM coded as
# AAC) the click must sound 1.000 s after the picture's start within 2 ms (the sound decoded by
# ffmpeg, the start times read by ffprobe), the sound must end with the picture (a 5 s --audio
# file is cut to 3 s), --no-audio leaves it out, and the mistakes are one line and exit 2.
# Exit 77 (skip) without the ffmpeg CLI tools. Usage: audio_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start audio ffmpeg ffprobe python3

ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 \
    -f lavfi -i "aevalsrc='if(between(t,1,1.005),0.9*sin(2*PI*1000*t),0)':s=48000:d=3" -ac 2 \
    -pix_fmt yuv420p -c:v libx264 -preset ultrafast -c:a aac "$work/film.mp4" || fail "ffmpeg film"
ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 -vf format=gray -c:v libx264 -preset ultrafast \
    "$work/depth.mkv" || fail "ffmpeg depth"
ff -f lavfi -i "aevalsrc='if(between(t,1,1.005),0.9*sin(2*PI*1000*t),0)':s=44100:d=5" \
    -c:a pcm_s16le "$work/other.wav" || fail "ffmpeg wav"
enc() { "$exe" encode --depth "$work/depth.mkv" --preset ultrafast "$@"; }

cat >"$work/check.py" <<'PY'
import struct, subprocess, sys
path, codec, rate, channels, length = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
def probe(select, entries):
    out = subprocess.run(["ffprobe", "-v", "error", "-select_streams", select, "-show_entries",
                          "stream=" + entries, "-of", "csv=p=0", path], capture_output=True,
                         text=True, check=True).stdout.split()
    return out[0].split(",") if out else []
a = probe("a", "codec_name,sample_rate,channels,start_time")
v = probe("v:0", "start_time")
if not a:
    sys.exit("%s: no audio stream" % path)
bad = []
if a[:3] != [codec, str(rate), str(channels)]:
    bad.append("audio %s, want %s %d Hz %d ch" % (a[:3], codec, rate, channels))
raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-map", "0:a:0", "-f", "s16le", "-ac",
                      "1", "-ar", "48000", "-"], capture_output=True, check=True).stdout
s = struct.unpack("<%dh" % (len(raw) // 2), raw[:len(raw) // 2 * 2])
loud = [i for i, x in enumerate(s) if abs(x) > 8000]
if not loud:
    sys.exit("%s: no click in the sound" % path)
click = float(a[3]) + loud[0] / 48000.0 - float(v[0])
if abs(click - 1.0) > 0.002:
    bad.append("the click sounds %.4f s after the picture's start, want 1.000" % click)
end = float(a[3]) + len(s) / 48000.0 - float(v[0])
if abs(end - length) > 0.05:
    bad.append("the sound ends %.3f s after the picture's start, want %.3f" % (end, length))
if bad:
    sys.exit("%s: %s" % (path, "; ".join(bad)))
print("%s: %s %d Hz %d ch, click at %.4f s, ends at %.3f s" % (path, codec, rate, channels, click, end))
PY

# 1. The color input's sound, copied (AAC into MKV, MP4, MPEG-TS).
for out in a.mkv a.mp4 a.ts; do
    enc --color "$work/film.mp4" -o "$work/$out" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode $out"; }
    grep -q "^audio: aac 48000 Hz 2 ch, copied" "$work/log" || { cat "$work/log"; fail "$out: summary"; }
    python3 "$work/check.py" "$work/$out" aac 48000 2 3.0 || fail "$out"
done
# 2. --audio: a 5 s PCM file, coded as AAC (also in MKV, which could carry PCM), cut to the picture.
for out in b.mkv b.mp4 b.ts; do
    enc --color "$work/film.mp4" --audio "$work/other.wav" -o "$work/$out" >"$work/log" 2>&1 ||
        { cat "$work/log"; fail "encode --audio $out"; }
    grep -q "^audio: pcm_s16le 44100 Hz 1 ch, coded as aac" "$work/log" || { cat "$work/log"; fail "$out: summary"; }
    python3 "$work/check.py" "$work/$out" aac 44100 1 3.0 || fail "$out"
done
# 3. --no-audio, and a color input without sound: no audio stream, no audio line.
enc --color "$work/film.mp4" --no-audio -o "$work/c.mkv" >"$work/log" 2>&1 || { cat "$work/log"; fail "--no-audio"; }
[ -z "$(ffprobe -v error -select_streams a -show_entries stream=index -of csv=p=0 "$work/c.mkv")" ] &&
    ! grep -q "^audio:" "$work/log" || fail "--no-audio wrote sound"
enc --color "$work/depth.mkv" -o "$work/d.mkv" >"$work/log" 2>&1 || { cat "$work/log"; fail "silent color"; }
[ -z "$(ffprobe -v error -select_streams a -show_entries stream=index -of csv=p=0 "$work/d.mkv")" ] ||
    fail "sound from a color input without any"
# 4. Mistakes: one line, exit 2, no output.
bad() { # WORDS ARGS...
    words="$1"
    shift
    enc "$@" -o "$work/bad.mkv" >/dev/null 2>"$work/err"
    rc=$?
    [ $rc -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q -- "$words" "$work/err" &&
        [ ! -e "$work/bad.mkv" ] || { cat "$work/err"; fail "'$*': exit $rc, want 2 and one line with '$words'"; }
}
bad "--audio must name a file" --color "$work/film.mp4" --audio "$work/missing.wav"
bad "--audio excludes" --color "$work/film.mp4" --audio "$work/other.wav" --no-audio
bad "has no audio stream" --color "$work/film.mp4" --audio "$work/depth.mkv"
# an MP4 cut in half, before its index (written last): it does not open
head -c $(($(wc -c <"$work/film.mp4") / 2)) "$work/film.mp4" >"$work/cut.mp4"
bad "does not open as media" --color "$work/film.mp4" --audio "$work/cut.mp4"
echo "audio: copied and coded sound on the picture's timeline in MKV, MP4 and MPEG-TS; --no-audio; 4 mistakes refused"
