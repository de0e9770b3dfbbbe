#!/bin/sh
# End-to-end (issue 60): a timestamp discontinuity on a live MPEG-TS over UDP does not freeze the
# picture. The file cases are pts_discontinuity_e2e.sh's; here the same joined streams come over
# UDP loopback, paced in real time (188 x 7 bytes a datagram, evenly over the 6 s), to
# `play udp://...`, which ends by itself once the sender stops (the live stream's silence):
#   forward  the clip, then the clip 1000 s later (a splice)            180 pairs
#   backward the clip 100 s later, then the clip (a jump back)          180 pairs
#   reset    the clip 60 s later, then the clip starting at PTS 0       180 pairs
# `play` must re-base its media clock at the splice (its --verbose log says so), present about
# every pair (the frame that shows a jump is lost, and the last 3 pairs of any live stream that
# stops) and end at the end of the stream with exit 0; a picture frozen at the splice would present
# about 90 pairs and hold to --duration. The time from the splice's datagram to the re-base (the
# first picture after it) is printed, a figure and not a check (a busy machine is slower).
# Exit 77 (skip) without the ffmpeg CLI or python3. Usage: live_splice_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start live_splice ffmpeg python3
e2e_port

# One 3 s clip (90 pairs), its timestamps moved, joined byte for byte (as the file test does).
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

# The sender: TS packets, 7 a datagram, paced evenly over the stream's duration (not by its
# timestamps, which jump: `ffmpeg -re` would wait out the 1000 s). It prints the monotonic clock
# (the player's log clock) when it sent the datagram that holds the splice's first byte.
cat >"$work/send.py" <<'PY'
import socket, sys, time

src, port, seconds, splice = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
data = open(src, "rb").read()
size = 188 * 7
count = (len(data) + size - 1) // size
step = seconds / count
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
start = time.monotonic()
spliced = 0.0
for k in range(count):
    s.sendto(data[k * size:(k + 1) * size], ("127.0.0.1", port))
    if k == splice // size:
        spliced = time.monotonic()
    wait = start + (k + 1) * step - time.monotonic()
    if wait > 0:
        time.sleep(wait)
print("%.6f sent %d datagrams in %.1f s" % (spliced, count, time.monotonic() - start))
PY

# kind, its first segment. The player ends by itself about 1.6 s after the sender stops (the live
# stream's silence); --duration, well above the 6 s sent, bounds a frozen picture.
check() {
    "$exe" play "udp://127.0.0.1:$port" --display mock --haptic none --no-config --audio-device none \
        --verbose --max-lateness 10 --duration 30 --stats "$work/$1.json" >"$work/$1.log" 2>&1 &
    e2e_bg=$!
    # The sender starts once the player listens (its port bound): a bounded poll.
    e2e_wait_udp "$port" "$e2e_bg"
    python3 "$work/send.py" "$work/$1.ts" "$port" 6 "$(wc -c <"$work/$2.ts")" >"$work/$1.send" 2>&1 ||
        { cat "$work/$1.send"; fail "$1: the sender"; }
    wait "$e2e_bg"
    rc=$?
    e2e_bg=""
    [ "$rc" -eq 0 ] || { cat "$work/$1.log"; fail "$1: play exited $rc, want 0"; }
    python3 - "$work/$1.json" "$work/$1.log" "$work/$1.send" "$1" <<'PY' || { cat "$work/$1.log"; fail "$1"; }
import json, re, sys
j = json.load(open(sys.argv[1]))
log = open(sys.argv[2]).read()
sent = open(sys.argv[3]).read().split()
kind = sys.argv[4]
got, want = j["frames_presented"], 180
# A re-base of the media clock at the splice (two for the reset: libavformat takes the clip at
# PTS 0 after one that began at 61.4 s for a 33-bit wrap until 1.4 s, then jumps back).
rebases = [float(t) for t in
           re.findall(r"^\[ *([0-9.]+)\] INFO  Playback: Timestamp discontinuity", log, re.M)]
if not rebases:
    sys.exit("%s: no timestamp discontinuity re-based the media clock" % kind)
# Lost: the pair that shows a jump (one at each re-base, as from a file), and the last pairs of a
# live stream that stops (a plain 3 s clip over UDP: 87 of 90 presented, its last frames not out
# of the demuxer and the pairer when the silence ends play); 8 allowed. A frozen picture: about 90.
if got < want - 8:
    sys.exit("%s: presented %d of %d frame pairs" % (kind, got, want))
if "end of stream" not in log:
    sys.exit("%s: play did not end at the end of the stream" % kind)
print("live_splice: %s: %d of %d frame pairs presented, %d re-base(s); picture %.2f s after the "
      "splice was sent" % (kind, got, want, len(rebases), rebases[0] - float(sent[0])))
PY
}
check forward a
check backward a100
check reset a60
echo PASS
