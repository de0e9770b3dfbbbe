#!/bin/bash
# Shell completion, as a user pressing Tab meets it: `depthtouch completion bash` is
# sourced into bash and _depthtouch is called with COMP_WORDS as bash fills them; what it offers is
# compared with sources of their own: the commands of `--help` and of the "needs a command" line,
# the long options of `play --help`, and the words of `touch --method`'s refusal. The zsh function
# is checked by zsh itself (syntax) and by running it with _arguments and _describe recording
# their specs. Usage: completion_e2e.sh /path/to/depthtouch
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@" # ctest runs it with sh
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_work completion
"$exe" completion bash >"$work/c.bash" || fail "completion bash: exit $?"
"$exe" completion zsh >"$work/_depthtouch" || fail "completion zsh: exit $?"

# offers WORDS...: what _depthtouch offers with the cursor after the last word (sorted, one a line).
offers() {
    bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _depthtouch
             printf "%s\n" "${COMPREPLY[@]}" | sort -u' _ "$work/c.bash" depthtouch "$@"
}
sorted() { tr ' ,' '\n\n' | sed '/^$/d' | sort -u; }
# long_options ARGS...: the long option names `depthtouch ARGS --help` lists (its option lines).
long_options() {
    "$exe" "$@" --help | sed -n 's/^  \(-[a-zA-Z],\)\{0,1\}\(--[a-z][a-z0-9-]*\).*/\2/p' | sort -u
}

# The commands, against --help's "Subcommands:" list.
"$exe" --help | sed -n '/^Subcommands:/,$p' | sed -n 's/^  \([a-z][a-z0-9-]*\).*/\1/p' | sort -u \
    >"$work/want"
offers "" >"$work/got"
diff "$work/want" "$work/got" || fail "the commands offered are not --help's"
[ "$(offers pl)" = play ] || fail "'pl' completes to '$(offers pl)'"

# bench's commands, against its own "needs a command" line.
"$exe" bench 2>&1 | sed 's/.*needs a command: //; s/ (see --help)//' | sorted >"$work/want"
offers bench "" >"$work/got"
diff "$work/want" "$work/got" || fail "bench's commands"
[ "$(offers bench fe)" = feel ] || fail "'bench fe': '$(offers bench fe)'"

# play's options, against the long options play --help lists.
long_options play >"$work/want"
[ "$(wc -l <"$work/want")" -gt 20 ] || fail "play --help lists $(wc -l <"$work/want") options"
offers play x.mkv -- | grep -- '^--' >"$work/got"
diff "$work/want" "$work/got" || fail "play's options offered are not play --help's"
[ "$(offers play --stif)" = --stiffness ] || fail "'play --stif': '$(offers play --stif)'"
# A value is skipped when walking the words: the option after it is play's again.
[ "$(offers play --stiffness 900 --ra)" = --rate ] || fail "after a value: '$(offers play --stiffness 900 --ra)'"

# touch --method's words, against the refusal of a wrong one.
"$exe" touch x --trajectory t.csv --out o.csv --method bogus 2>&1 | sed 's/.*--method must be //' |
    sed 's/ or /,/' | sorted >"$work/want"
[ -s "$work/want" ] || fail "touch --method bogus named no methods"
offers touch --method "" >"$work/got"
diff "$work/want" "$work/got" || fail "touch --method's words"
# A number offers nothing; a path offers files.
[ -z "$(offers play x.mkv --stiffness "")" ] || fail "a number's value offered '$(offers play --stiffness "")'"
touch "$work/forces-log.csv"
[ "$(offers play x.mkv --force-log "$work/forces-")" = "$work/forces-log.csv" ] || fail "--force-log: files"
[ "$(offers probe "$work/forces-")" = "$work/forces-log.csv" ] || fail "probe's file"
echo "bash: commands, bench's, play's options, touch --method's words, files and numbers as expected"

# zsh: the file parses, and _depthtouch_play hands _arguments a spec per option of play --help.
zsh -n "$work/_depthtouch" || fail "zsh -n: the zsh function does not parse"
zsh -f -c 'source "$1" 2>/dev/null
    _arguments() { print -rl -- "$@"; }; _describe() { :; }; _files() { :; }
    _depthtouch_play' _ "$work/_depthtouch" >"$work/zspecs" || fail "zsh: _depthtouch_play"
sed -n "s/^\(--[a-z][a-z0-9-]*\)\[.*/\1/p" "$work/zspecs" | sort -u >"$work/got"
long_options play >"$work/want"
diff "$work/want" "$work/got" || fail "zsh: play's option specs are not play --help's"
grep -q -- '^--method\[.*\]:method:(finger' <(zsh -f -c 'source "$1" 2>/dev/null
    _arguments() { print -rl -- "$@"; }; _depthtouch_touch' _ "$work/_depthtouch") ||
    fail "zsh: touch --method's words"
echo "zsh: parses; play's option specs are play --help's; --method offers its words"
