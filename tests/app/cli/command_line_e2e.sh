#!/bin/sh
# The command line's mistakes as a user types them: each is refused with exit 2 and one
# stderr line that names the mistyped word and, where one is near, the word meant (as git and mpv
# do), not CLI11's generic "A subcommand is required" or "arguments were not expected".
# Usage: command_line_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_work cmdline

# says WANT_TEXT ARGS...: exit 2, exactly one stderr line, and it holds WANT_TEXT.
says() {
    want="$1"; shift
    "$exe" "$@" >"$work/out" 2>"$work/err" </dev/null
    rc=$?
    [ "$rc" -eq 2 ] || { cat "$work/err"; fail "'$*': exit $rc, want 2"; }
    [ "$(wc -l <"$work/err")" -eq 1 ] || { cat "$work/err"; fail "'$*': want one stderr line"; }
    grep -qF -- "$want" "$work/err" || fail "'$*' said '$(cat "$work/err")', want '$want'"
    echo "'$*': $(cat "$work/err")"
}

says "'plya' is not a command; did you mean 'play'?" plya x.mkv
says "'version' is not a command; did you mean '--version'?" version
says "unknown option '--frobnicate'" --frobnicate
says "unknown option '--stifness' of 'play'; did you mean '--stiffness'?" play --stifness 3 x.mkv
says "unknown option '--colr' of 'encode'; did you mean '--color'?" encode --colr a.mkv --out b.mkv
says "'fel' is not a command of 'bench'; did you mean 'feel'?" bench fel
says "'bench' needs a command: haptics, render, rt, media, feel" bench
says "a command is needed: demo, play, backends, touch, encode, probe, bench"
says "unexpected argument 'extra' of 'play'" play x.mkv extra
# a word far from every command is named without a guess
says "'xyzzyplugh' is not a command (see --help)" xyzzyplugh
# what CLI11 says well stays: a missing value, a value that is not a number
says "url is required" play
says "--stiffness" play x.mkv --stiffness abc
# --help shows no parser artefacts: no "--no-fifo{false}" default, no validator name after a type
# ("INT:N >= 0"), in any command's help
for c in "" demo play backends touch encode probe completion "bench haptics" "bench render" \
    "bench rt" "bench media" "bench feel" "bench stability"; do
    # shellcheck disable=SC2086 # the command words are split on purpose
    "$exe" $c --help >"$work/help" 2>&1 || fail "'$c --help': exit $?"
    if grep -nE '\{(true|false)\}|\b(INT|UINT|FLOAT|TEXT):' "$work/help"; then
        fail "'$c --help' shows a parser artefact"
    fi
done
"$exe" bench haptics --help | grep -q -- "^  --no-fifo " || fail "bench haptics --help lacks --no-fifo"
# and what is right still works
"$exe" --version | grep -q "^depthtouch " || fail "--version"
"$exe" play --help | grep -q -- "--stiffness" || fail "play --help"
echo "command line: every mistake named"
