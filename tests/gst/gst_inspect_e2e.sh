#!/bin/sh
# End-to-end: gst-inspect-1.0 loads libgstdepthtouch.so from GST_PLUGIN_PATH (the build folder,
# set by CTest) and lists hapticsink (its always sink pad `sink`, its caps: GRAY8 and GRAY16_LE
# video, its properties) and depthtouchsink (its always sink pads `color`, I420, and `depth`,
# GRAY8/GRAY16_LE/I420, its properties). Exit 77 (skip) without gst-inspect-1.0.
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
    contact-force contact-force-z hip-z servo-rate updates safety-trips watchdog-trips; do
    grep -Eq "^  $prop *:" "$work/inspect.out" || { cat "$work/inspect.out"; fail "no property $prop"; }
done
# the stiffness's range is play's (app/options/option_range.h: 100..3000 N/m, default 800)
grep -A2 "^  stiffness " "$work/inspect.out" | grep -q "Range: *100 - *3000 Default: *800" ||
    { grep -A2 "^  stiffness " "$work/inspect.out"; fail "stiffness range"; }
grep -q "depthtouchsink" "$work/plugin.out" || { cat "$work/plugin.out"; fail "the plugin lists depthtouchsink"; }

gst-inspect-1.0 depthtouchsink >"$work/sink.out" 2>"$work/sink.err" ||
    { cat "$work/sink.err"; fail "gst-inspect-1.0 depthtouchsink exited $?"; }
for text in "SINK template: 'color'" "SINK template: 'depth'" "Availability: Always" "video/x-raw" \
    "format: I420" "GRAY8" "GRAY16_LE" "libgstdepthtouch.so"; do
    grep -qF "$text" "$work/sink.out" || { cat "$work/sink.out"; fail "depthtouchsink: no '$text'"; }
done
[ "$(grep -c "Availability: Always" "$work/sink.out")" -eq 2 ] || fail "depthtouchsink: two always pads"
for prop in haptic-device haptic-device-options stiffness method display display-options control async \
    frames-paired frames-presented depth-unpaired depth-missing updates servo-rate contact-force \
    contact-force-z safety-trips watchdog-trips haptics; do
    grep -Eq "^  $prop *:" "$work/sink.out" || { cat "$work/sink.out"; fail "depthtouchsink: no property $prop"; }
done
grep -A2 "^  stiffness " "$work/sink.out" | grep -q "Range: *100 - *3000 Default: *800" ||
    { grep -A2 "^  stiffness " "$work/sink.out"; fail "depthtouchsink: stiffness range"; }
echo "gst-inspect-1.0: hapticsink and depthtouchsink with their pads, caps and properties"
