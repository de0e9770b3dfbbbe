# Shared steps of the end-to-end scripts (POSIX sh; sourced, not run):
#   . "$(dirname "$0")/../../e2e_lib.sh"
# e2e_need TOOL...  exit 77 (ctest's skip) with one line when a tool is not on PATH.
# e2e_work NAME     a fresh folder in $work (under $TMPDIR), removed at exit after e2e_cleanup,
#                   which a script redefines to stop what it started (a sender, a server).
# ff ARGS...        the ffmpeg CLI, quiet, overwriting, never reading stdin.
# probe ARGS...     ffprobe, errors only.
# fail MESSAGE      "FAIL: MESSAGE" on stdout and exit 1.
# e2e_wait_served EXE URL OUT  `EXE probe URL` (output in OUT) until it succeeds, for a server just
#                   started: up to 5 s, then fail with its output.

e2e_need() {
    for tool in "$@"; do
        command -v "$tool" >/dev/null 2>&1 || { echo "$tool not on PATH: skipped"; exit 77; }
    done
}
e2e_cleanup() { :; }
e2e_work() {
    work=$(mktemp -d "${TMPDIR:-/tmp}/dt-$1.XXXXXX") || exit 1
    trap 'e2e_cleanup; rm -rf "$work"' EXIT
}
ff() { ffmpeg -nostdin -hide_banner -v error -y "$@" </dev/null; }
probe() { ffprobe -v error "$@"; }
fail() { echo "FAIL: $*"; exit 1; }
e2e_wait_served() {
    tries=0
    until "$1" probe "$2" >"$3" 2>&1; do
        tries=$((tries + 1))
        [ $tries -lt 25 ] || { cat "$3"; fail "no server answers at $2"; }
        sleep 0.2
    done
}
