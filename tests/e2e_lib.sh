# Shared steps of the end-to-end scripts (POSIX sh; sourced, not run):
#   . "$(dirname "$0")/../../e2e_lib.sh"
# e2e_need TOOL...  exit 77 (ctest's skip) with one line when a tool is not on PATH.
# e2e_work NAME     a fresh folder in $work (under $TMPDIR), removed at exit after e2e_cleanup,
#                   which kills $e2e_bg (the one process a script started in the background, a
#                   sender or a server: set it to $! and back to "" once it is reaped); a script
#                   that must stop something else redefines e2e_cleanup.
# e2e_start NAME TOOL...  e2e_need TOOL... then e2e_work NAME: the opening of most scripts.
# ff ARGS...        the ffmpeg CLI, quiet, overwriting, never reading stdin.
# probe ARGS...     ffprobe, errors only.
# e2e_color_pngs SIZE SECONDS  the ffmpeg test pattern, WxH at 30 fps, as $work/c-000.png, c-001.png...
# e2e_metric_depth_pngs SECONDS  64x48 16-bit metric depth at 30 fps as $work/d-000.png...: 1.0 m
#                   at the left edge to 2.26 m at the right (mm), with an 8x8 hole (0) in the
#                   top-left corner.
# fail MESSAGE      "FAIL: MESSAGE" on stdout and exit 1.
# e2e_wait_served EXE URL OUT  `EXE probe URL` (output in OUT) until it succeeds, for a server just
#                   started: up to 5 s, then fail with its output.
# e2e_port          sets $port to the first of four consecutive loopback ports that no socket uses
#                   now, from a block of four that the script's process id picks (two scripts
#                   started one after the other under ctest -j get different blocks; a used one is
#                   skipped). The script may use $port to $((port + 3)).
# e2e_wait_udp PORT PID  until a UDP socket is bound to 127.0.0.1 or any address at PORT (a
#                   listener or a player just started: /proc/net/udp, so nothing connects to it), up
#                   to 10 s, or until process PID has exited; then returns (the step that follows
#                   reports what went wrong). A fixed sleep lost the race on a loaded machine.

e2e_need() {
    for tool in "$@"; do
        command -v "$tool" >/dev/null 2>&1 || { echo "$tool not on PATH: skipped"; exit 77; }
    done
}
e2e_bg=""
e2e_cleanup() { [ -n "$e2e_bg" ] && kill "$e2e_bg" 2>/dev/null; }
e2e_work() {
    work=$(mktemp -d "${TMPDIR:-/tmp}/dt-$1.XXXXXX") || exit 1
    trap 'e2e_cleanup; rm -rf "$work"' EXIT
}
e2e_start() {
    e2e_name=$1
    shift
    e2e_need "$@"
    e2e_work "$e2e_name"
}
ff() { ffmpeg -nostdin -hide_banner -v error -y "$@" </dev/null; }
probe() { ffprobe -v error "$@"; }
e2e_color_pngs() {
    ff -f lavfi -i "testsrc=size=$1:rate=30:duration=$2" -start_number 0 "$work/c-%03d.png" || fail "ffmpeg color"
}
e2e_metric_depth_pngs() {
    ff -f lavfi -i "color=c=black:size=64x48:rate=30:duration=$1" \
        -vf "format=gray16le,geq=lum='if(lt(X,8)*lt(Y,8),0,1000+20*X)'" -pix_fmt gray16be \
        -start_number 0 "$work/d-%03d.png" || fail "ffmpeg depth"
}
fail() { echo "FAIL: $*"; exit 1; }
e2e_wait_served() {
    tries=0
    until "$1" probe "$2" >"$3" 2>&1; do
        tries=$((tries + 1))
        [ $tries -lt 25 ] || { cat "$3"; fail "no server answers at $2"; }
        sleep 0.2
    done
}
e2e_wait_udp() {
    hex=$(printf '%04X' "$1")
    for _ in $(seq 1 200); do
        grep -q ":$hex " /proc/net/udp /proc/net/udp6 2>/dev/null && return 0
        kill -0 "$2" 2>/dev/null || return 0
        sleep 0.05
    done
}
e2e_in_use() {
    hex=$(printf '%04X' "$1")
    grep -q ":$hex " /proc/net/tcp /proc/net/tcp6 /proc/net/udp /proc/net/udp6 2>/dev/null
}
e2e_port() {
    port=$((20000 + ($$ % 9000) * 4))
    for _ in $(seq 1 100); do
        e2e_in_use "$port" || e2e_in_use $((port + 1)) || e2e_in_use $((port + 2)) ||
            e2e_in_use $((port + 3)) || return 0
        port=$((port + 4))
        [ "$port" -lt 56000 ] || port=20000
    done
}
