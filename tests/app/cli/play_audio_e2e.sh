#!/bin/sh
# End-to-end: `play` plays the sound of its input through the sound output (the wav backend, read
# back here by Python's wave module, not by the library that wrote it). A 3 s clip whose sound is
# silent but for a 5 ms click at 1.000 s is encoded with its sound (AAC), then played on the mock
# display: the click must be in the WAV 1.000 s after its first frame within 2 ms (the sound
# starts with the first frame, PTS 0), the WAV must last the clip and hold every sample as ffmpeg
# decodes the clip's sound (none dropped or silenced between frames), --volume 50 must scale the click
# by (0.5)^3 as mpv's volume does, --mute must write silence, --no-audio and --audio-device none no
# file, the stats JSON must name the device and the sound, and a sound output that does not exist
# is one line and exit 2; a tone paused, resumed, sought and stopped through the control socket
# must join without a click (no sample step above a ramp's); a live UDP stream's sound must be heard
# at its media times. Exit 77 (skip) without the ffmpeg CLI.
# Usage: play_audio_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start play-audio ffmpeg python3

ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 \
    -f lavfi -i "aevalsrc='if(between(t,1,1.005),0.9*sin(2*PI*1000*t),0)':s=48000:d=3" -ac 2 \
    -pix_fmt yuv420p -c:v libx264 -preset ultrafast -c:a aac "$work/film.mp4" || fail "ffmpeg film"
ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 -vf format=gray -c:v libx264 -preset ultrafast \
    "$work/depth.mkv" || fail "ffmpeg depth"
"$exe" encode --depth "$work/depth.mkv" --color "$work/film.mp4" --preset ultrafast \
    -o "$work/clip.mkv" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode"; }

play() { # WAV ARGS...
    out="$1"
    shift
    "$exe" play "$work/clip.mkv" --display mock --haptic none --no-config --audio-device wav \
        --audio-device-options "path=$out" "$@"
}

cat >"$work/check.py" <<'PY'
import json, struct, sys, wave
path, stats, want_gain = sys.argv[1], sys.argv[2], float(sys.argv[3])
ref_peak = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
reference = sys.argv[5] if len(sys.argv) > 5 else ""
w = wave.open(path)
rate, channels, n = w.getframerate(), w.getnchannels(), w.getnframes()
s = struct.unpack("<%dh" % (n * channels), w.readframes(n))
bad = []
if (rate, channels) != (48000, 2):
    bad.append("%d Hz %d ch, want 48000 Hz 2 ch" % (rate, channels))
if abs(n / rate - 3.0) > 0.05:
    bad.append("the sound lasts %.3f s, want the clip's 3.000" % (n / rate))
peak = max(abs(x) for x in s)
if want_gain == 0.0:
    if peak != 0:
        bad.append("muted, yet a sample of %d" % peak)
else:
    loud = [i // channels for i, x in enumerate(s) if abs(x) > 0.25 * peak]
    click = loud[0] / rate
    if abs(click - 1.0) > 0.002:
        bad.append("the click sounds %.4f s after the first frame, want 1.000" % click)
    if ref_peak and abs(peak / ref_peak - want_gain) > 0.01:
        bad.append("peak %d is %.4f of the full volume's, want %.4f" % (peak, peak / ref_peak, want_gain))
if reference:
    # Every sample as ffmpeg decodes the clip's sound: nothing dropped, repeated or silenced
    # between the decoder's frames (MKV's millisecond timestamps are no gaps). Where the sound
    # stops is when the picture's end was reached on the wall clock: the 50 ms check above, not
    # a sample count (under a sanitizer on a busy machine it ended 12 ms before ffmpeg's last).
    raw = open(reference, "rb").read()
    ref = struct.unpack("<%dh" % (len(raw) // 2), raw)
    m = min(len(s), len(ref))
    differ = sum(1 for a, b in zip(s[:m], ref[:m]) if a != b)
    if differ or m < len(ref) // 2:
        bad.append("%d of %d samples differ from ffmpeg's decoding (%d samples there)" % (differ, m, len(ref)))
j = json.load(open(stats))
if j.get("audio_device") != "wav" or j.get("audio") != "48000 Hz 2 ch":
    bad.append("stats: audio_device %r, audio %r" % (j.get("audio_device"), j.get("audio")))
if bad:
    sys.exit("%s: %s" % (path, "; ".join(bad)))
print(peak)
PY

# 1. Full volume: the click 1.000 s in, the sound as long as the clip.
play "$work/a.wav" --stats "$work/a.json" >"$work/log" 2>&1 || { cat "$work/log"; fail "play"; }
grep -q "^  sound             48000 Hz 2 ch on wav: " "$work/log" || { cat "$work/log"; fail "summary"; }
ffmpeg -nostdin -v error -i "$work/clip.mkv" -map 0:a:0 -f s16le -ac 2 -ar 48000 - >"$work/ref.raw" ||
    fail "ffmpeg decoding the clip's sound"
peak=$(python3 "$work/check.py" "$work/a.wav" "$work/a.json" 1.0 0 "$work/ref.raw") || fail "full volume"
# 2. --volume 50: (50/100)^3 of it, at the same time.
play "$work/b.wav" --stats "$work/b.json" --volume 50 >"$work/log" 2>&1 || { cat "$work/log"; fail "--volume"; }
python3 "$work/check.py" "$work/b.wav" "$work/b.json" 0.125 "$peak" >/dev/null || fail "--volume 50"
# 3. --mute: silence, as long.
play "$work/c.wav" --stats "$work/c.json" --mute >"$work/log" 2>&1 || { cat "$work/log"; fail "--mute"; }
python3 "$work/check.py" "$work/c.wav" "$work/c.json" 0.0 >/dev/null || fail "--mute"
# 4. --no-audio, --audio-device none: no sound written, none in the stats.
for off in "--no-audio" "--audio-device none"; do
    # shellcheck disable=SC2086
    "$exe" play "$work/clip.mkv" --display mock --haptic none --no-config $off \
        --audio-device-options "path=$work/d.wav" --stats "$work/d.json" >"$work/log" 2>&1 ||
        { cat "$work/log"; fail "$off"; }
    [ ! -e "$work/d.wav" ] || fail "$off wrote sound"
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(j['audio'] != '' or j['audio_device'] != '')" \
        "$work/d.json" || fail "$off: stats name a sound"
done
# 5. A sound output that does not exist: one line naming the ones that do, exit 2.
"$exe" play "$work/clip.mkv" --display mock --haptic none --no-config --audio-device pulse \
    >/dev/null 2>"$work/err"
rc=$?
[ $rc -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "alsa" "$work/err" ||
    { cat "$work/err"; fail "--audio-device pulse: exit $rc, want 2 and one line naming alsa"; }
# 6. Joins: a steady 100 Hz tone (its own largest step between samples: 0.5 * 32767 * 2 pi 100 /
# 48000 = 214), paused, resumed, sought and stopped through the control socket. What the wav
# output heard must never step by more than the tone's own step plus a 10 ms ramp's (16384 / 480
# = 34) and the coding error: 400, where a cut without a fade steps by up to 16384.
ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 \
    -f lavfi -i "aevalsrc='0.5*sin(2*PI*100*t)':s=48000:d=3" -ac 2 \
    -pix_fmt yuv420p -c:v libx264 -preset ultrafast -c:a aac -b:a 192k "$work/tone.mp4" ||
    fail "ffmpeg tone"
"$exe" encode --depth "$work/depth.mkv" --color "$work/tone.mp4" --preset ultrafast \
    -o "$work/tone.mkv" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode tone"; }
"$exe" play "$work/tone.mkv" --display mock --haptic none --no-config --audio-device wav \
    --audio-device-options "path=$work/j.wav" --control "$work/ctl" >"$work/log" 2>&1 &
player=$!
python3 - "$work/ctl" "$work/j.wav" <<'PY' || { kill "$player" 2>/dev/null; cat "$work/log"; fail "joins"; }
import json, socket, struct, sys, time, wave
path, wav = sys.argv[1], sys.argv[2]
end = time.monotonic() + 20
while True:
    try:
        s = socket.socket(socket.AF_UNIX); s.connect(path); break
    except OSError:
        if time.monotonic() > end: sys.exit("no control socket")
        time.sleep(0.05)
f = s.makefile("rw")
def ask(*cmd):
    f.write(json.dumps({"command": list(cmd), "request_id": 1}) + "\n"); f.flush()
    while True:
        r = json.loads(f.readline())
        if r.get("request_id") == 1: return r
def pos():
    return ask("get_property", "time-pos").get("data") or 0.0
while pos() < 0.6:
    if time.monotonic() > end: sys.exit("the tone never played 0.6 s")
    time.sleep(0.02)
# Pause 0.4 s, resume, seek back 1.5 s in (the 3 s clip), pause again, stop.
for cmd, wait in ((("set_property", "pause", True), 0.4), (("set_property", "pause", False), 0.5),
                  (("seek", 1.5, "absolute"), 0.6), (("set_property", "pause", True), 0.2)):
    r = ask(*cmd)
    if r.get("error") != "success": sys.exit("%s: %s" % (cmd, r))
    time.sleep(wait)
ask("stop")
s.close()
time.sleep(1.0)
w = wave.open(wav)
n, ch = w.getnframes(), w.getnchannels()
x = struct.unpack("<%dh" % (n * ch), w.readframes(n))[0::ch]
steps = [abs(b - a) for a, b in zip(x, x[1:])]
largest = max(steps)
quiet = sum(1 for v in x if v == 0)
at = steps.index(largest) / 48000
if quiet < 0.3 * 48000:
    sys.exit("%.2f s of silence heard: the pause was not heard" % (quiet / 48000))
if largest > 400:
    sys.exit("a step of %d at %.3f s of what was heard: a click (limit 400)" % (largest, at))
print("joins: largest step %d (limit 400), %.2f s of silence heard, %.2f s in all" % (largest, quiet / 48000, n / 48000))
PY
wait "$player" || { cat "$work/log"; fail "play with joins"; }
# 7. A live stream's sound (UDP, one demuxer: its audio packets handed to the audio thread). The
# tone sounds the first half of every second of the sender's clip: each onset must be heard at
# its media time (whole seconds after the first frame, which is PTS 0 as the player listens
# before the sender starts) within 3 ms.
ff -f lavfi -i testsrc=size=96x72:rate=30:duration=3 \
    -f lavfi -i "aevalsrc='0.5*sin(2*PI*100*t)*lt(mod(t,1),0.5)':s=48000:d=3" -ac 2 \
    -pix_fmt yuv420p -c:v libx264 -preset ultrafast -c:a aac "$work/gated.mp4" || fail "ffmpeg gated"
e2e_port
"$exe" play "udp://127.0.0.1:$port" --display mock --haptic none --no-config --audio-device wav \
    --audio-device-options "path=$work/live.wav" --duration 4 --av-log "$work/live.csv" \
    --stats "$work/live.json" >"$work/live.log" 2>&1 &
player=$!
sleep 1
"$exe" encode --color "$work/gated.mp4" --depth "$work/depth.mkv" --preset ultrafast \
    -o "udp://127.0.0.1:$port" >"$work/send.log" 2>&1 || { cat "$work/send.log"; fail "encode to udp"; }
wait "$player" || { cat "$work/live.log"; fail "play udp"; }
python3 - "$work/live.wav" "$work/live.csv" "$work/live.json" <<'PY' || { cat "$work/live.log"; fail "live sound"; }
import json, struct, sys, wave
w = wave.open(sys.argv[1])
n, ch = w.getnframes(), w.getnchannels()
x = struct.unpack("<%dh" % (n * ch), w.readframes(n))[0::ch]
rows = [l.split(",") for l in open(sys.argv[2]).read().split("\n")[1:] if l]
first = float(rows[0][1]) - 1 / 30  # the log starts at the second frame on screen
quiet, onsets = 0, []
for i, v in enumerate(x):
    if abs(v) > 1000:
        if quiet > 0.3 * 48000:
            onsets.append(first + i / 48000)
        quiet = 0
    else:
        quiet += 1
if json.load(open(sys.argv[3])).get("audio") != "48000 Hz 2 ch":
    sys.exit("the stats name no sound")
if n < 1.5 * 48000 or len(onsets) < 1:
    sys.exit("%.2f s of sound heard, onsets %s" % (n / 48000, onsets))
late = [o - round(o) for o in onsets]
if any(abs(d) > 0.003 for d in late):
    sys.exit("onsets at %s s of media time, want whole seconds within 3 ms" % onsets)
print("live: %.2f s of sound, onsets %s" % (n / 48000, ", ".join("%.4f" % o for o in onsets)))
PY
echo "play: the click 1.000 s after the first frame, --volume 50 at 0.125, --mute silent, no sound with --no-audio, a bad device refused, pause/resume/seek/stop without a click, a live stream's sound in sync"
