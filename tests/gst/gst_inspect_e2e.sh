#!/bin/sh
# End-to-end: gst-inspect-1.0 loads libgstdepthtouch.so from GST_PLUGIN_PATH (the build folder,
# set by CTest) and lists hapticsink: its always sink pad `sink`, its caps (GRAY8 and GRAY16_LE
# video) and its properties. Exit 77 (skip) without gst-inspect-1.0.
# Usage: gst_inspect_e2e.sh
set -u
. "$(dirname "$0")/../e2e_lib.sh"
e2e_start gst-inspect gst-inspect-1.0

gst-inspect-1.0 hapticsink >"$work/inspect.out" 2>"$work/inspect.err" ||
    { cat "$work/inspect.err"; fail "gst-inspect-1.0 hapticsink exited $?"; }
gst-inspect-1.0 depthtouch >"$work/plugin.out" 2>&1 || fail "gst-inspect-1.0 depthtouch (the plugin)"
grep -q "hapticsink" "$work/plugin.out" || { cat "$work/plugin.out"; fail "the plugin lists hapticsink"; }
for text in "SINK template: 'sink'" "Availability: Always" "video/x-raw" "GRAY8" "GRAY16_LE" \
    "libgstdepthtouch.so"; do
    grep -qF "$text" "$work/inspect.out" || { cat "$work/inspect.out"; fail "no '$text'"; }
done
for prop in haptic-device haptic-device-options stiffness method depth-near depth-far \
    contact-force contact-force-z hip-z servo-rate updates safety-trips; do
    grep -Eq "^  $prop *:" "$work/inspect.out" || { cat "$work/inspect.out"; fail "no property $prop"; }
done
# the stiffness's range is play's (app/options/option_range.h: 100..3000 N/m, default 800)
grep -A2 "^  stiffness " "$work/inspect.out" | grep -q "Range: *100 - *3000 Default: *800" ||
    { grep -A2 "^  stiffness " "$work/inspect.out"; fail "stiffness range"; }
echo "gst-inspect-1.0: hapticsink with its pad, caps and properties"
