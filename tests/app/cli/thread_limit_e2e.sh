#!/bin/sh
# `play` when the system will not start its threads (RLIMIT_NPROC, issue 60): that is a failure of
# the machine, not of the input, so exit 1 with one line that says which thread, not exit 2 (bad
# input). Runs the player as `nobody` under `prlimit --nproc` (root's threads are never limited):
# skips unless run as root with runuser and prlimit. Usage: thread_limit_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root to run the player as nobody under a process limit"; exit 77; }
e2e_need runuser
e2e_need prlimit
runuser -u nobody -- test -x "$exe" || { echo "SKIP: nobody cannot run $exe"; exit 77; }
e2e_work thread-limit
mkdir -p "$work/etc" "$work/xdg"
chmod 755 "$work" "$work/etc" "$work/xdg"
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg" # no config of this machine
clip="mock://clip?frames=6&fps=30&width=64&height=48"

# play_as_nobody OUT [PRLIMIT ARGS...]: the mock clip as nobody; its exit status.
play_as_nobody() {
    o="$1"
    shift
    runuser -u nobody -- prlimit "$@" -- "$exe" play "$clip" --source mock --decoder mock \
        --display mock --haptic none --no-audio --quiet >"$work/$o.out" 2>"$work/$o.err" </dev/null
}

play_as_nobody free || fail "as nobody without a limit: exit $? ($(cat "$work/free.err"))"

# One process for the user: the player itself. Its first thread cannot start.
play_as_nobody one --nproc=1
rc=$?
[ "$rc" = 1 ] || fail "no thread could start: exit $rc, not 1 ($(cat "$work/one.err"))"
[ "$(wc -l <"$work/one.err")" = 1 ] || fail "no thread could start: not one line: $(cat "$work/one.err")"
grep -q "cannot start the .*thread" "$work/one.err" ||
    fail "no thread could start: the line does not say which: $(cat "$work/one.err")"
echo "thread limit: exit 1 and '$(cat "$work/one.err")'"
