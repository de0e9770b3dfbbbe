#!/bin/sh
# `play` with its default display and remote (mpv's habit: a screen when there is one, the
# terminal's keys when it runs in one; issue 61): on a machine with no X server, no DRM card and no
# terminal (CI), it plays on headless and says in the summary that no screen was found and how to
# name one; with `--display headless` asked for, it says nothing of it (a build without EGL has no
# headless to fall back on: it skips). An X server named by
# $DISPLAY that does not answer is no screen either. Usage: play_defaults_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
e2e_work play-defaults
mkdir -p "$work/etc" "$work/xdg"
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg" # no config of this machine
clip="mock://clip?frames=6&fps=30&width=64&height=48"
[ -e /dev/dri/card0 ] && { echo "SKIP: this machine has a DRM card: kms would show the picture"; exit 77; }
"$exe" backends | grep -q headless || { echo "SKIP: no headless display in this build"; exit 77; }

# play_default OUT [ARGS...]: the clip with the default display and remote, stdin not a terminal.
play_default() {
    o="$1"
    shift
    "$exe" play "$clip" --source mock --decoder mock --haptic none --no-audio "$@" \
        >"$work/$o.out" 2>"$work/$o.err" </dev/null
}

unset DISPLAY
play_default none || fail "default display, no screen: exit $? ($(cat "$work/none.err"))"
grep -q "on headless" "$work/none.out" || fail "no screen: not played on headless: $(head -1 "$work/none.out")"
grep -q "note .*no screen found.*--display x11 or kms" "$work/none.out" ||
    fail "no screen: the summary does not say how to see the picture: $(cat "$work/none.out")"
[ -s "$work/none.err" ] && fail "no screen: stderr is not empty: $(cat "$work/none.err")"

DISPLAY=:97 play_default silent || fail "an X server that does not answer: exit $?"
grep -q "on headless" "$work/silent.out" || fail "a silent X server: not headless"
grep -q "no screen found" "$work/silent.out" || fail "a silent X server: no note"

play_default asked --display headless || fail "--display headless: exit $?"
grep -q "no screen found" "$work/asked.out" && fail "--display headless asked for: a note all the same"
echo "play defaults: headless with the note without a screen, none when headless is asked for"
