#!/bin/sh
# The on-screen display says when the remote is missing (issue 61: the remote's state shown in the
# OSD, as the haptic device's "HAPTICS: NO DEVICE"): a player that waits for its remote (--idle
# --remote evdev, where no input device with media keys is plugged in) draws the line
# "REMOTE: NO DEVICE" into its frames; the same run with --remote none draws the plain OSD. Seen in
# the snapshots of a headless display: the two runs' last frame differ, where two runs without a
# remote are byte for byte the same (else the comparison says nothing: skipped).
# Usage: osd_remote_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
e2e_start osd-remote socat
mkdir -p "$work/etc" "$work/xdg"
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg"
unset DT_LOG JOURNAL_STREAM
clip="mock://clip?frames=5&fps=10&width=64&height=48"

# run NAME REMOTE: plays the clip with the remote REMOTE, a snapshot of every frame in
# $work/NAME/, until the five are written, then quits over the control socket; its stderr in
# $work/NAME.err.
run() {
    name=$1
    sock="$work/$name.sock"
    mkdir -p "$work/$name"
    "$exe" play "$clip" --source mock --decoder mock --display headless --haptic none \
        --remote "$2" --no-audio --no-config --size 240x160 --snapshot-dir "$work/$name" \
        --snapshot-every 1 --idle --control "$sock" >/dev/null 2>"$work/$name.err" </dev/null &
    e2e_bg=$!
    i=0
    until [ -f "$work/$name/frame-000004.png" ] && [ -S "$sock" ]; do
        i=$((i + 1))
        if [ "$i" -ge 600 ] || ! kill -0 "$e2e_bg" 2>/dev/null; then
            grep -q "display" "$work/$name.err" && { echo "no headless display: skipped"; exit 77; }
            fail "$name: no fifth snapshot: '$(cat "$work/$name.err")'"
        fi
        sleep 0.1
    done
    sleep 0.3 # the last PNG written out
    echo '{"command":["quit"]}' | socat -t 2 - "UNIX-CONNECT:$sock" >/dev/null 2>&1
    wait "$e2e_bg"
    rc=$?
    e2e_bg=""
    [ "$rc" -eq 0 ] || fail "$name: exit $rc, '$(cat "$work/$name.err")'"
}

run awaited evdev
grep -q "no remote input 'evdev' connected" "$work/awaited.err" ||
    { echo "this machine has a remote with media keys (or no evdev): skipped"; exit 77; }
run none1 none
run none2 none
last=frame-000004.png
cmp -s "$work/none1/$last" "$work/none2/$last" ||
    { echo "two runs without a remote drew different frames: nothing to compare, skipped"; exit 77; }
cmp -s "$work/none1/$last" "$work/awaited/$last" &&
    fail "the OSD of a player waiting for its remote looks as one without a remote"
echo "OK: the awaited remote's line is drawn"
