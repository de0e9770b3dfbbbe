#!/bin/sh
# End-to-end: gst-launch-1.0 plays the depth stream of a clip made by `depthtouch encode` into
# hapticsink with the simulated hand:
#   filesrc ! matroskademux name=d d.video_1 ! queue ! decodebin ! videoconvert ! hapticsink
# The element's INFO lines (GST_DEBUG=hapticsink:4) show the depth tags it read from the demuxer
# (the planes encode wrote) and, at the end, that the haptic task ran and the hand touched the
# surface. No assertion on timing. Exit 77 (skip) without gst-launch-1.0 or without the demuxer
# and decoder plugins (gstreamer1.0-plugins-good, gstreamer1.0-libav).
# Usage: gst_launch_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../e2e_lib.sh"
e2e_start gst-launch gst-launch-1.0 gst-inspect-1.0
for element in matroskademux decodebin videoconvert avdec_h264; do
    gst-inspect-1.0 "$element" >/dev/null 2>&1 || { echo "GStreamer element $element missing: skipped"; exit 77; }
done

"$exe" encode --color synthetic:head,size=160x120,frames=90 --depth synthetic:head,size=160x120,frames=90 \
    -o "$work/clip.mkv" --preset ultrafast >"$work/encode.out" 2>&1 || { cat "$work/encode.out"; fail "encode"; }
GST_DEBUG=hapticsink:4 GST_DEBUG_NO_COLOR=1 gst-launch-1.0 -q filesrc location="$work/clip.mkv" ! \
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
echo "gst-launch-1.0: $updates haptic updates, $contact in contact"
