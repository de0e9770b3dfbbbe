#!/bin/sh
# End-to-end: gst-launch-1.0 plays a clip made by `depthtouch encode` with the simulated hand,
# 1. its depth stream into hapticsink:
#   filesrc ! matroskademux name=d d.video_1 ! queue ! decodebin ! videoconvert ! hapticsink
# 2. both streams into depthtouchsink (issue 62's pipeline, on the headless display):
#   filesrc ! matroskademux name=d d.video_0 ! queue ! decodebin ! videoconvert ! s.color
#     d.video_1 ! queue ! decodebin ! s.depth depthtouchsink name=s haptic-device=sim
# The elements' INFO lines (GST_DEBUG=hapticsink:4, depthtouchsink:4) show the depth tags read
# from the demuxer (the planes encode wrote) and, at the end, that the haptic task ran and the hand
# touched the surface; depthtouchsink's that each of the 150 colour frames (5 s at 30 fps, the
# issue's run) was paired with its depth frame by running time and the stream ended in EOS, that
# neither element's renderer released (the simulated hand presses with its default 2 N; the
# watchdog's trips, missed deadlines, are printed), and that the haptic thread took no page fault
# after its warm-up where its memory is locked.
# Both pipelines run with RT_WATCH (tests/support/rt_watch.c) preloaded: the haptic thread made no
# allocation, free, lock or write after its first wait, inside gst-launch-1.0 as in the tests' own
# programs (tests/app/haptic_task/discipline_test.cpp). No assertion on timing. Exit 77 (skip)
# without gst-launch-1.0 or without the demuxer and decoder plugins (gstreamer1.0-plugins-good,
# gstreamer1.0-libav).
# Usage: gst_launch_e2e.sh DEPTHTOUCH RT_WATCH
set -u
exe="$1"
watch="$2"
. "$(dirname "$0")/../e2e_lib.sh"
e2e_start gst-launch gst-launch-1.0 gst-inspect-1.0
# the safety trips of the stop line $1 (the element $2, which dropped $3 frames): none the
# renderer's (a 2 N press). The watchdog's (a missed deadline) are the machine's, even on a
# SCHED_FIFO thread in a VM that steals its time: printed, not judged (a test must not fail because
# the machine is busy). So is a renderer's release after dropped frames: depth reaches the haptic
# task as its frames are presented, so a machine that did not keep up showed it a surface that
# jumped, and a release is the renderer's answer to a jump (paper IV.C).
trips() {
    all=$(echo "$1" | sed -n 's/.* \([0-9]*\) safety trips (\([0-9]*\) by the watchdog).*/\1/p')
    dog=$(echo "$1" | sed -n 's/.* \([0-9]*\) safety trips (\([0-9]*\) by the watchdog).*/\2/p')
    [ -n "$all" ] && [ -n "$dog" ] || fail "$2: no safety trips in the stop line: $1"
    if [ "$all" -ne "$dog" ] && [ "$3" -gt 0 ]; then
        echo "$2: the renderer released after $3 frames were dropped (the machine's load): $1"
    elif [ "$all" -ne "$dog" ]; then
        fail "$2: the renderer released on a 2 N press: $1"
    fi
    [ "$dog" -eq 0 ] || echo "$2: $dog watchdog trips (missed deadlines: the machine's load)"
}
# the haptic thread's discipline, as rt_watch.c counted it in the run whose output is $1 ($2 names it)
discipline() {
    w=$(grep "^rt-watch: .*(1 thread)" "$1") || { cat "$1"; fail "$2: no haptic thread watched"; }
    echo "$w" | grep -q ": 0 allocations, 0 frees, 0 locks, 0 writes " || fail "$2: $w"
    echo "$2: $w"
}
for element in matroskademux decodebin videoconvert avdec_h264; do
    gst-inspect-1.0 "$element" >/dev/null 2>&1 || { echo "GStreamer element $element missing: skipped"; exit 77; }
done

"$exe" encode --color synthetic:head,size=160x120,frames=150 --depth synthetic:head,size=160x120,frames=150 \
    -o "$work/clip.mkv" --preset ultrafast >"$work/encode.out" 2>&1 || { cat "$work/encode.out"; fail "encode"; }
LD_PRELOAD="$watch" GST_DEBUG=hapticsink:4 GST_DEBUG_NO_COLOR=1 gst-launch-1.0 -q filesrc location="$work/clip.mkv" ! \
    matroskademux name=d d.video_1 ! queue ! decodebin ! videoconvert ! \
    hapticsink haptic-device=sim stiffness=1000 >"$work/launch.out" 2>&1 ||
    { cat "$work/launch.out"; fail "gst-launch-1.0 exited $?"; }
grep -q "haptic device 'sim', method finger, stiffness 1000 N/m" "$work/launch.out" ||
    { cat "$work/launch.out"; fail "the element's start line"; }
grep -q "depth tags: near 0.5 m, far 1.5 m, mapping 'inverse_z', bits 8" "$work/launch.out" ||
    { cat "$work/launch.out"; fail "the depth tags of the file (encode's planes of the head scene)"; }
line=$(grep "stopped: " "$work/launch.out") || { cat "$work/launch.out"; fail "no stop line"; }
echo "$line" | grep -q "depth planes 0.5..1.5 m (tags)" || fail "planes: $line"
updates=$(echo "$line" | sed -n 's/.*stopped: \([0-9]*\) updates, \([0-9]*\) in contact.*/\1/p')
contact=$(echo "$line" | sed -n 's/.*stopped: \([0-9]*\) updates, \([0-9]*\) in contact.*/\2/p')
[ -n "$updates" ] && [ "$updates" -gt 0 ] || fail "no haptic updates: $line"
[ -n "$contact" ] && [ "$contact" -gt 0 ] || fail "the hand never touched: $line"
# the simulated hand presses the head with its default 2 N: the renderer never releases on it
trips "$line" hapticsink 0
echo "gst-launch-1.0: $updates haptic updates, $contact in contact"
discipline "$work/launch.out" hapticsink

# 2. depthtouchsink: colour + depth into play's player (a depth stream decoded to I420: its luma)
LD_PRELOAD="$watch" GST_DEBUG=depthtouchsink:4 GST_DEBUG_NO_COLOR=1 gst-launch-1.0 filesrc location="$work/clip.mkv" ! \
    matroskademux name=d d.video_0 ! queue ! decodebin ! videoconvert ! s.color \
    d.video_1 ! queue ! decodebin ! s.depth \
    depthtouchsink name=s haptic-device=sim display=headless stiffness=1000 >"$work/sink.out" 2>&1 ||
    { cat "$work/sink.out"; fail "gst-launch-1.0 depthtouchsink exited $?"; }
grep -q "Got EOS from element" "$work/sink.out" || { cat "$work/sink.out"; fail "no EOS"; }
grep -q "haptic device 'sim', display 'headless', method finger, stiffness 1000 N/m" "$work/sink.out" ||
    { cat "$work/sink.out"; fail "depthtouchsink's start line"; }
grep -q "depth tags: near 0.5 m, far 1.5 m, mapping 'inverse_z', bits 8" "$work/sink.out" ||
    { cat "$work/sink.out"; fail "depthtouchsink: the depth tags of the file"; }
line=$(grep "stopped: .* pairs" "$work/sink.out") || { cat "$work/sink.out"; fail "no stop line"; }
echo "$line" | grep -q "stopped: 150 pairs, [0-9]* presented, 0 depth unpaired" ||
    fail "every colour frame paired with its depth frame: $line"
presented=$(echo "$line" | sed -n 's/.* pairs, \([0-9]*\) presented.*/\1/p')
updates=$(echo "$line" | sed -n 's/.* \([0-9]*\) haptic updates.*/\1/p')
[ -n "$presented" ] && [ "$presented" -gt 0 ] || fail "nothing presented: $line"
[ -n "$updates" ] && [ "$updates" -gt 0 ] || fail "no haptic updates: $line"
# the haptic thread's faults after its warm-up are counted (their number is the machine's)
echo "$line" | grep -Eq "by the watchdog\), [0-9]+ page faults after warm-up" || fail "page faults: $line"
if grep -q "Started dt-haptic: .*memory locked" "$work/sink.out"; then
    echo "$line" | grep -q " 0 page faults after warm-up" || fail "page faults with memory locked: $line"
else
    echo "the haptic thread's memory is not locked here: its page faults are the machine's"
fi
trips "$line" depthtouchsink $((150 - presented))
echo "gst-launch-1.0 depthtouchsink: 150 pairs, $presented presented, $updates haptic updates"
discipline "$work/sink.out" depthtouchsink
