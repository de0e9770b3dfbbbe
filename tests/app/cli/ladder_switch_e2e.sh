#!/bin/sh
# End-to-end: an HLS ladder (`encode --renditions`, three renditions of color and a flat depth)
# played over HTTP with the default `rendition=auto` while the link falls, 4 s in, to 1.15 times
# the smallest rendition's BANDWIDTH (throttled_http.py): the player goes down to the smallest
# rendition and plays on to the end: no more than a segment of pictures skipped a change (how late
# they came is printed, not held: it is this machine's timing), the smaller rendition's segments
# fetched from then on, and the sim finger pressing the depth through the switch: no safety release within 0.1 s of it, no force
# step there larger than the press's own or the force stage's slew limit (2 N an update).
# Usage: ladder_switch_e2e.sh DEPTHTOUCH   (exit 77 without the ffmpeg CLI or python3)
exe=$1
here=$(dirname "$0")
. "$here/../../e2e_lib.sh"
e2e_start ladder-switch ffmpeg python3

ff -f lavfi -i testsrc2=size=320x240:rate=30:duration=16 -start_number 0 "$work/c-%03d.png" || fail "ffmpeg color"
ff -f lavfi -i "color=c=0x909090:size=320x240:rate=30:duration=16,format=gray" -start_number 0 "$work/d-%03d.png" ||
    fail "ffmpeg depth"
mkdir "$work/www"
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" \
    --renditions 240,120,60 -o "$work/www/show.m3u8" --preset ultrafast >"$work/enc.out" 2>&1 ||
    { cat "$work/enc.out"; fail "encode --renditions exited $?"; }
low=$(sed -n 's/^#EXT-X-STREAM-INF:BANDWIDTH=\([0-9]*\),.*RESOLUTION=80x60,.*/\1/p' "$work/www/show.m3u8")
[ -n "$low" ] || { cat "$work/www/show.m3u8"; fail "no 80x60 rendition"; }
link=$((low * 115 / 100 / 8)) # bytes/s

e2e_port
python3 "$here/throttled_http.py" "$port" "$work/www" "0=0,4=$link" 2>"$work/http.log" &
e2e_bg=$!
python3 - "$port" <<'PY' || fail "the throttled server does not listen"
import socket, sys, time
for _ in range(50):
    try:
        socket.create_connection(("127.0.0.1", int(sys.argv[1])), 0.2).close()
        sys.exit(0)
    except OSError:
        time.sleep(0.1)
sys.exit(1)
PY
"$exe" play "http://127.0.0.1:$port/show.m3u8" --display mock --haptic sim --verbose \
    --force-log "$work/f.csv" --stats "$work/p.json" >"$work/play.out" 2>&1 ||
    { cat "$work/play.out"; fail "play exited $?"; }
grep -q 'Rendition [0-9x]* -> 80x60' "$work/play.out" ||
    { cat "$work/play.out"; fail "no switch down to 80x60 on a link of $link bytes/s"; }
last=$(grep -o 'GET /show_[0-9]*p[0-9]*\.ts' "$work/http.log" | tail -1)
[ "$last" = "GET /show_60p7.ts" ] || { cat "$work/http.log"; fail "the last segment fetched: $last, want show_60p7.ts"; }
python3 - "$work/p.json" "$work/f.csv" "$work/play.out" <<'PY' || { cat "$work/play.out"; fail "the play across the switch"; }
import csv, json, math, re, sys
j = json.load(open(sys.argv[1]))
segment_frames = 60  # 2 s at 30 fps
down = re.findall(r"Rendition ([0-9x]+) -> ([0-9x]+) at", open(sys.argv[3]).read())
# Each change down skips at most the rest of a segment.
assert j["frames_received"] >= 480 - segment_frames * len(down), ("pictures skipped", j["frames_received"], down)
# The finger feels the new rendition's depth: depth went on reaching the haptic task after the
# change at 8 s (about half the pairs come after it).
assert j["depth_pairs_published"] >= 0.6 * j["frames_received"], (j["depth_pairs_published"], j["frames_received"])
# How late the pictures came is a figure of this machine's timing, printed, not held (straight down
# 1.29 s in most runs; up to 2.3 s, and 3.1 s by way of 160x120: docs/playing.md).
rows = list(csv.DictReader(open(sys.argv[2])))
assert rows, "an empty force log"
# The switch's place in the video (the log: "... at 8.000 s"). The depth is still: a force step
# there comes from the change of rendition alone, and may not exceed the finger's own steps.
at = float(re.search(r"Rendition [0-9x]+ -> 80x60 at ([0-9.]+) s", open(sys.argv[3]).read()).group(1))
force = lambda r: [float(r[k]) for k in ("fx", "fy", "fz")]
# A finger that pressed up to the switch presses on after it. (The haptic task's watchdog, on a
# loaded machine, now and then ramps the force back in and the finger is let go, away from any
# switch: docs/playing.md "Changing rendition while playing".)
pressing = lambda r: r["contact"] == "1" and float(r["fz"]) > 1.0
before = [r for r in rows if at - 0.1 < float(r["play_t"]) < at]
after = [r for r in rows if at <= float(r["play_t"]) < at + 0.1]
assert before and after, "haptic updates around the switch"
# Whether the watchdog acted around the switch: the force ramped in again (gain < 1) within the
# half second before the switch's window ends. Then a let-go there is the watchdog's (this machine's
# missed deadlines), not the switch's, and the press through the switch is printed, not judged.
watchdog = [r for r in rows if at - 0.5 <= float(r["play_t"]) < at + 0.1 and float(r["gain"]) < 1.0]
window = lambda: ["t %s contact %s released %s fz %s gain %s" % (r["play_t"], r["contact"], r["released"], r["fz"], r["gain"])
                  for r in before[-3:] + after[:3]]
if watchdog:
    print("the watchdog ramped the force in around the switch (gain %.3f at the least): the press through it "
          "is not judged this run" % min(float(r["gain"]) for r in watchdog))
else:
    if all(map(pressing, before)):
        assert all(map(pressing, after)), ("the finger presses the surface through the switch", window())
    assert not any(r["released"] == "1" for r in after), ("a safety release at the switch", window())
near, far = [0.0], [0.0]
for a, b in zip(rows, rows[1:]):
    (near if abs(float(b["play_t"]) - at) < 0.1 else far).append(math.dist(force(a), force(b)))
assert max(far) > 0.0, "the finger never pressed"
assert max(near) <= 2.0 and max(near) <= 1.25 * max(far), ("a force step at the switch", max(near), max(far))
print("switch at %.3f s (%s): %d of 480 frames received, late at most %.0f ms; largest force step %.3f N at "
      "the switch, %.3f N elsewhere" % (at, down, j["frames_received"], j["late_ms_max"], max(near), max(far)))
PY
