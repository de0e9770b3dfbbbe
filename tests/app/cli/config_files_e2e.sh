#!/bin/sh
# `play` reads its settings as mpv does: the system file (DT_SYSTEM_CONFIG_DIR stands for
# /etc/depthtouch), then the user's ($XDG_CONFIG_HOME/depthtouch/play.toml), then --config, then the
# command line, each later one winning key by key; --no-config leaves the first two out;
# --show-config prints the settings in effect with where each came from. Checked on the values a
# short mock play writes to --stats (haptic_rate_hz), and on --show-config's lines.
# Usage: config_files_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_work config-files
mkdir -p "$work/etc" "$work/xdg/depthtouch"
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg"
sys="$work/etc/play.toml"
user="$work/xdg/depthtouch/play.toml"
printf 'rate = 500\nstiffness = 1234\ndisplay = "mock"\nhaptic = "mock"\nquiet = true\n' >"$sys"
clip="mock://clip?frames=6&fps=30&width=64&height=48"

# rate_of ARGS...: the haptic_rate_hz of a mock play with ARGS.
rate_of() {
    rm -f "$work/stats.json"
    "$exe" play "$clip" --source mock --decoder mock --stats "$work/stats.json" "$@" \
        >"$work/out" 2>"$work/err" </dev/null || { cat "$work/err"; fail "play $*: exit $?"; }
    python3 -c 'import json,sys; print("%g" % json.load(open(sys.argv[1]))["haptic_rate_hz"])' \
        "$work/stats.json"
}
# line KEY: the --show-config line of KEY (without the origin); origin KEY: its origin.
line() { grep "^$1 = " "$work/show" | sed 's/  # .*//'; }
origin() { grep "^$1 = " "$work/show" | sed 's/.*  # //'; }
# refused WANT ARGS...: play ARGS is exit 2 with one stderr line holding WANT.
refused() {
    want="$1"; shift
    "$exe" play "$clip" "$@" >"$work/out" 2>"$work/err" </dev/null
    rc=$?
    [ "$rc" -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -qF -- "$want" "$work/err" ||
        fail "play $*: exit $rc, '$(cat "$work/err")', want '$want'"
}
show() { "$exe" play --show-config "$@" >"$work/show" 2>"$work/err" </dev/null ||
    { cat "$work/err"; fail "--show-config $*: exit $?"; }; }

r=$(rate_of) && [ "$r" = 500 ] || fail "the system file's rate: haptic_rate_hz $r, want 500"
printf 'rate = 250\n' >"$user"
r=$(rate_of) && [ "$r" = 250 ] || fail "the user file over the system's: $r, want 250"
printf 'rate = 2000\n' >"$work/given.toml"
r=$(rate_of --config "$work/given.toml") && [ "$r" = 2000 ] || fail "--config over the user's: $r"
r=$(rate_of --config "$work/given.toml" --rate 400) && [ "$r" = 400 ] ||
    fail "the command line over --config: $r, want 400"
r=$(rate_of --no-config --display mock --haptic mock --quiet) && [ "$r" = 1000 ] ||
    fail "--no-config: $r, want the default 1000"
echo "haptic_rate_hz: system 500, user 250, --config 2000, --rate 400, --no-config 1000"

show --config "$work/given.toml" --stiffness 900
[ "$(line rate)" = "rate = 2000.0" ] && [ "$(origin rate)" = "$work/given.toml" ] ||
    fail "show rate: $(grep '^rate' "$work/show")"
[ "$(line stiffness)" = "stiffness = 900.0" ] && [ "$(origin stiffness)" = "command line" ] ||
    fail "show stiffness: $(grep '^stiffness' "$work/show")"
[ "$(line display)" = 'display = "mock"' ] && [ "$(origin display)" = "$sys" ] ||
    fail "show display: $(grep '^display' "$work/show")"
[ "$(origin stereo)" = default ] || fail "show stereo: $(grep '^stereo' "$work/show")"
grep -qx "# read: $sys" "$work/show" && grep -qx "# read: $user" "$work/show" ||
    fail "the files read are not named"
rm "$user"
show
grep -qx "# not found: $user" "$work/show" || fail "a missing user file is not named"
[ "$(origin rate)" = "$sys" ] || fail "without the user file: rate from $(origin rate)"
show --no-config
[ "$(line rate)" = "rate = 1000.0" ] && [ "$(origin rate)" = default ] || fail "--no-config show"

# A broken system file is an error that names it (exit 2, one line); so is a missing --config.
printf 'stifness = 1\n' >"$sys"
refused "config file '$sys': unknown key 'stifness'" --source mock --decoder mock
refused "--config '$work/none.toml'" --no-config --config "$work/none.toml"

# The key map (mpv's input.conf) is found the same way: the blue key, unbound by default, quits
# where the system input.conf binds it, and plays on where the user's unbinds it again (ignore).
rm -f "$sys"
long="mock://clip?frames=900&fps=30&width=64&height=48"
# playing_of ARGS...: playing_s of a mock play of 30 s with the blue key pressed at 0.3 s, ended
# after 5 s: a bound key ends it under 1.5 s, an unbound one plays on (robust to a start of up to
# 3.5 s on a loaded or sanitized build).
playing_of() {
    rm -f "$work/stats.json"
    "$exe" play "$long" --source mock --decoder mock --display mock --haptic mock --quiet \
        --remote mock --remote-options keys=KEY_BLUE@0.3 --duration 5 \
        --stats "$work/stats.json" "$@" >"$work/out" 2>"$work/err" </dev/null ||
        { cat "$work/err"; fail "play $*: exit $?"; }
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["playing_s"])' "$work/stats.json"
}
quick() { python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) < 1.5 else 1)' "$1"; }
p=$(playing_of) && ! quick "$p" || fail "the blue key is bound by default: played $p s"
printf '# the blue key quits\nBLUE   quit   # as EXIT does\n' >"$work/etc/input.conf"
p=$(playing_of) && quick "$p" || fail "the system input.conf's BLUE quit: played $p s"
printf 'KEY_BLUE ignore\n' >"$work/xdg/depthtouch/input.conf"
p=$(playing_of) && ! quick "$p" || fail "the user's BLUE ignore: played $p s"
printf 'blue quit\n' >"$work/keys.conf"
p=$(playing_of --input-conf "$work/keys.conf") && quick "$p" || fail "--input-conf: played $p s"
p=$(playing_of --no-config) && ! quick "$p" || fail "--no-config read input.conf: played $p s"
echo "key map: BLUE unbound by default, bound by the system input.conf, unbound by the user's"
printf 'BLUE quit\nFOO quit\n' >"$work/etc/input.conf"
refused "key map '$work/etc/input.conf': line 2: unknown key 'FOO'" --source mock --decoder mock
echo "config files: system, user, --config, command line in that order; errors name the file"
