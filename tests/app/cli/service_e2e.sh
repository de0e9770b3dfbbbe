#!/bin/sh
# `play` as the box's service runs it (packaging/depthtouch.service.in, issue 61):
#  - a stop (SIGTERM, as `systemctl stop` sends) of a player that stays up (--idle) while it waits
#    for a sender, or after the wait timed out, is exit 0: systemd marks a unit whose stop exits
#    non-zero failed;
#  - the shipped configuration (packaging/play.toml) starts without a Falcon and a remote: a
#    missing one is a warning line, not a failure (Restart=on-failure would loop), and is waited
#    for (hot-plug) rather than replaced by `none`;
#  - with stderr the journal's stream (JOURNAL_STREAM), the one failure line has the error priority
#    prefix "<3>" (sd-daemon(3)) and a warning "<4>", as the log's lines.
# Usage: service_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
e2e_work service
mkdir -p "$work/etc" "$work/xdg"
# No system or user configuration of this machine takes part.
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg"
unset DT_LOG JOURNAL_STREAM
e2e_port
clip="mock://clip?frames=6&fps=30&width=64&height=48"

# stopped_in STATE ARGS...: `play udp://127.0.0.1:PORT --idle ARGS` (nothing is sent there), SIGTERM
# once its control socket says STATE (its stop signals are set by then: the socket is served by the
# loop that watches them), however long a busy machine takes to get there (at most 60 s); prints
# the exit code, its stderr in $work/err.
stopped_in() {
    state=$1
    shift
    sock="$work/ctl.sock"
    rm -f "$sock"
    "$exe" play "udp://127.0.0.1:$port" --idle --display mock --haptic none --no-audio \
        --control "$sock" "$@" >"$work/out" 2>"$work/err" </dev/null &
    e2e_bg=$!
    i=0
    until [ -S "$sock" ] && echo '{"command":["get","state"]}' |
        socat -t 2 - "UNIX-CONNECT:$sock" 2>/dev/null | grep -q "\"data\":\"$state\""; do
        i=$((i + 1))
        [ "$i" -lt 600 ] || { kill -KILL "$e2e_bg"; fail "the idle player never got to '$state'"; }
        sleep 0.1
    done
    kill -TERM "$e2e_bg"
    wait "$e2e_bg"
    rc=$?
    e2e_bg=""
    echo "$rc"
}

# 1. SIGTERM while it waits for a sender (opening), and once the wait timed out (error)
rc=$(stopped_in opening)
[ "$rc" -eq 0 ] || fail "SIGTERM while an idle player waits for a sender: exit $rc, '$(cat "$work/err")'"
rc=$(stopped_in error --source-options timeout_ms=300)
[ "$rc" -eq 0 ] || fail "SIGTERM after an idle player's wait timed out: exit $rc, '$(cat "$work/err")'"
grep -q "open failed" "$work/err" || fail "the timed-out wait was not reported: '$(cat "$work/err")'"

# 2. the shipped configuration, with what this machine lacks given on the command line (a display,
# SCHED_FIFO, the control socket's folder): the Falcon and the remote are its own
config="$here/../../../packaging/play.toml"
[ -f "$config" ] || fail "no $config"
"$exe" play --config "$config" --display mock --require-rt=false --control "$work/ctl.sock" \
    "$clip" --source mock --decoder mock --no-audio --duration 1 --stats "$work/shipped.json" \
    >"$work/out" 2>"$work/err" </dev/null
rc=$?
[ "$rc" -eq 0 ] || fail "play --config packaging/play.toml: exit $rc, '$(cat "$work/err")'"
if grep -v "warning: " "$work/err" | grep -q .; then
    fail "play --config packaging/play.toml printed more than warnings: '$(cat "$work/err")'"
fi
# without a Falcon (a machine that runs tests has none), a warning says so, and the player waits
# for one (hot-plug: the haptic task opens it when it is plugged in) instead of settling for none;
# --stats says it was not connected
if grep -q "haptic device 'falcon'" "$work/err"; then
    grep -q "^depthtouch play: warning: no haptic device 'falcon' connected: playing without it until it is plugged in$" \
        "$work/err" || fail "the missing Falcon's line: '$(cat "$work/err")'"
    python3 - "$work/shipped.json" <<'PY' || fail "the awaited Falcon in --stats: $(cat "$work/shipped.json")"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["haptic_device"] == "falcon", j["haptic_device"]
assert j["device_connected"] is False, j["device_connected"]
PY
    # the control socket says so too (mpv's get_property), while it plays and waits for one
    sock="$work/ctl2.sock"
    "$exe" play "mock://clip?frames=3000&fps=30&width=64&height=48" --source mock --decoder mock \
        --display mock --haptic falcon --remote evdev --idle --no-audio --no-config --control "$sock" \
        --duration 60 >"$work/out" 2>"$work/err-ipc" </dev/null &
    e2e_bg=$!
    i=0
    answer=""
    until echo "$answer" | grep -q '"data"'; do
        i=$((i + 1))
        [ "$i" -lt 600 ] || { kill -KILL "$e2e_bg"; fail "no haptic-device-connected: '$answer'"; }
        sleep 0.1
        [ -S "$sock" ] && answer=$(echo '{"command":["get_property","haptic-device-connected"]}' |
            socat -t 2 - "UNIX-CONNECT:$sock" 2>/dev/null)
    done
    remote=$(echo '{"command":["get_property","remote-connected"]}' |
        socat -t 2 - "UNIX-CONNECT:$sock" 2>/dev/null)
    echo '{"command":["quit"]}' | socat -t 2 - "UNIX-CONNECT:$sock" >/dev/null 2>&1
    wait "$e2e_bg"
    e2e_bg=""
    echo "$answer" | grep -q '"data":false' ||
        fail "haptic-device-connected of an awaited Falcon: '$answer'"
    # so does the remote's, where no input device with media keys is there (its warning said so)
    if grep -q "no remote input 'evdev' connected" "$work/err-ipc"; then
        echo "$remote" | grep -q '"data":false' ||
            fail "remote-connected of an awaited remote: '$remote'"
    fi
    # a player that does not stay up still says at once that its Falcon is missing (exit 1)
    "$exe" play "$clip" --source mock --decoder mock --display mock --haptic falcon --no-audio \
        --no-config --duration 1 >"$work/out" 2>"$work/err-once" </dev/null
    rc=$?
    [ "$rc" -eq 1 ] && grep -q "No Novint Falcon" "$work/err-once" ||
        fail "play --haptic falcon without one and without --idle: exit $rc, '$(cat "$work/err-once")'"
fi
if grep -q "remote input 'evdev'" "$work/err"; then
    grep -q "^depthtouch play: warning: no remote input 'evdev' connected: playing without it until it is plugged in$" \
        "$work/err" || fail "the missing remote's line: '$(cat "$work/err")'"
    python3 -c 'import json, sys; sys.exit(json.load(open(sys.argv[1]))["remote_connected"] is not False)' \
        "$work/shipped.json" || fail "the awaited remote in --stats: $(cat "$work/shipped.json")"
fi

# 3. the journal's priorities: stderr a file whose device and inode JOURNAL_STREAM names
# journal FILE ARGS...: `depthtouch ARGS` with stderr appended to FILE, the journal's stream.
journal() {
    j=$1
    shift
    : >"$j"
    JOURNAL_STREAM=$(stat -c %d:%i "$j") "$exe" "$@" >"$work/out" 2>>"$j" </dev/null
}
journal "$work/j1" play /nonexistent/x.mkv --display mock --haptic none --no-audio
rc=$?
[ "$rc" -eq 2 ] || fail "play of a missing file: exit $rc, '$(cat "$work/j1")'"
[ "$(wc -l <"$work/j1")" -eq 1 ] || fail "play of a missing file: '$(cat "$work/j1")'"
grep -q "^<3>depthtouch play: " "$work/j1" ||
    fail "the failure line under JOURNAL_STREAM has no <3> prefix: '$(cat "$work/j1")'"
journal "$work/j2" play "$clip" --no-such-option
if [ ! -s "$work/j2" ] || grep -qv "^<3>depthtouch: " "$work/j2"; then
    fail "a bad option's line under JOURNAL_STREAM: '$(cat "$work/j2")'"
fi
# the warning of a fallback (--idle: a service), and the log's own lines, with theirs
journal "$work/j3" play "$clip" --source mock --decoder mock --display mock --haptic mock,none \
    --no-audio --idle --duration 1 --haptic-options no_such_option=1
rc=$?
[ "$rc" -eq 0 ] || fail "play with a fallback under JOURNAL_STREAM: exit $rc, '$(cat "$work/j3")'"
grep -q "^<4>depthtouch play: warning: no haptic device 'mock'" "$work/j3" ||
    fail "the fallback's warning under JOURNAL_STREAM: '$(cat "$work/j3")'"
! grep -qv "^<[0-7]>" "$work/j3" || fail "a line without a priority: '$(cat "$work/j3")'"
# --verbose's state lines (opening, playing, end of stream, stopped) with theirs too
journal "$work/j4" play "$clip" --source mock --decoder mock --display mock --haptic none \
    --no-audio --no-config --verbose
rc=$?
[ "$rc" -eq 0 ] || fail "play --verbose under JOURNAL_STREAM: exit $rc, '$(cat "$work/j4")'"
grep -q "^<6>depthtouch play: playing$" "$work/j4" ||
    fail "the state line of --verbose under JOURNAL_STREAM: '$(cat "$work/j4")'"
! grep -qv "^<[0-7]>" "$work/j4" || fail "a --verbose line without a priority: '$(cat "$work/j4")'"
# A fallback list's options are the first backend's: null, after an ALSA device that is not
# there, takes none of them and does not refuse ALSA's "device" (it failed "'null': Unknown audio
# output option", exit 2).
"$exe" play "$clip" --source mock --decoder mock --display mock --haptic none --audio-device alsa,null \
    --audio-device-options device=hw:99 --quiet >"$work/fallback-options" 2>&1 ||
    fail "--audio-device alsa,null with ALSA's device option: exit $?, '$(cat "$work/fallback-options")'"
echo "service: ok"
