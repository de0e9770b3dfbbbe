#!/bin/sh
# Fault suite of the outputs, run on the `depthtouch` executable:
# - an output that names an input, or another output, however spelled (a link, `..`), is bad input
#   (exit 2, one stderr line) before any work, and the input keeps its bytes;
# - an output that cannot be completed (a full disk, simulated with RLIMIT_FSIZE and SIGXFSZ
#   ignored; /dev/full; a reader that leaves) is lost output: exit 1, one stderr line, and nothing
#   under its final name (no cut file, no temporary file left);
# - an output folder that takes no file (read-only) is found before the work, not after it.
# Plays on the headless EGL display with the simulated hand (label gl).
# Usage: faults_outputs_e2e.sh /path/to/depthtouch
set -u
exe="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")" # absolute: the runs are in the work folder
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_need timeout
ro=""
e2e_cleanup() { [ -n "$ro" ] && { chattr -i "$ro" 2>/dev/null; chmod 0755 "$ro"; }; }
e2e_work outputs
w="$work"
cd "$w" || exit 1

# run NAME WANT_RC BOUND_S CMD...: exit WANT_RC within BOUND_S seconds, one stderr line unless 0
# (or any number of lines with lines=any).
lines=one
run() {
    name="$1"; want="$2"; bound="$3"; shift 3
    timeout -k 5 "$bound" "$@" >"$w/out" 2>"$w/err" </dev/null
    rc=$?
    [ "$rc" -ne 124 ] && [ "$rc" -ne 137 ] || { cat "$w/err"; fail "$name: still running after $bound s"; }
    [ "$rc" -eq "$want" ] || { cat "$w/err"; fail "$name: exit $rc, want $want"; }
    if [ "$want" -ne 0 ] && [ "$lines" = one ]; then
        [ "$(wc -l <"$w/err")" -eq 1 ] || { cat "$w/err"; fail "$name: want one stderr line"; }
    fi
    echo "$name: exit $rc: $(head -c 200 "$w/err")"
}
# $L BLOCKS CMD...: CMD with at most BLOCKS blocks per file written, SIGXFSZ ignored (so a write
# past the limit fails with EFBIG, as on a full disk).
L="$w/limited"
printf '#!/bin/sh\ntrap "" XFSZ\nulimit -f "$1" || exit 99\nshift\nexec "$@"\n' >"$L"
chmod +x "$L"
# no_temporary DIR: no `.tmp` file of an output is left in DIR.
no_temporary() {
    [ -z "$(ls -a "$1" | grep '\.tmp')" ] || { ls -la "$1"; fail "a temporary file was left in $1"; }
}

"$exe" encode --color synthetic:head,size=160x120,frames=30 \
    --depth synthetic:head,size=160x120,frames=30 --preset ultrafast -o "$w/head.mkv" \
    >/dev/null 2>&1 || fail "cannot make the clip"
cp head.mkv clip.mkv
printf 't,x,y,z\n0,0,0,0.01\n0.2,0.001,0.001,-0.005\n' >t.csv
cp t.csv t.orig
printf 't,x,y,z\n0,0,0,0.01\n10,0.001,0.001,-0.005\n' >long.csv
printf 'duration = 1\n' >play.toml
cp play.toml play.orig
mkdir sub
ln -s clip.mkv link.mkv
P="$exe play --haptic sim --duration 2"

# --- group 3: an output never has the identity of an input or of another output ---
unchanged() {
    cmp -s head.mkv clip.mkv || fail "$1: the input clip.mkv was changed"
    cmp -s t.orig t.csv || fail "$1: the trajectory t.csv was changed"
    cmp -s play.orig play.toml || fail "$1: the config play.toml was changed"
}
for opt in --force-log --stats --record; do
    run "play clip.mkv $opt clip.mkv" 2 10 $P clip.mkv $opt clip.mkv
    grep -q "same file" "$w/err" || fail "play $opt: the line does not say why"
    unchanged "play $opt"
done
run "play link.mkv --record ./sub/../clip.mkv" 2 10 $P link.mkv --record ./sub/../clip.mkv
unchanged "play through a link and .."
run "play --stats X --force-log ./X" 2 10 $P clip.mkv --stats X --force-log ./X
[ ! -e X ] || fail "play --stats X --force-log X wrote X"
run "play --config play.toml --stats play.toml" 2 10 $P clip.mkv --config play.toml \
    --stats "$w/play.toml"
unchanged "play --config"
run "touch clip.mkv --out clip.mkv" 2 10 "$exe" touch clip.mkv --trajectory t.csv --out clip.mkv
run "touch --trajectory t.csv --out t.csv" 2 10 "$exe" touch clip.mkv --trajectory t.csv \
    --out ./t.csv
run "touch --material m --out m" 2 10 "$exe" touch head.mkv --trajectory t.csv \
    --material clip.mkv --out link.mkv
unchanged "touch"
run "encode -o the colour input" 2 10 "$exe" encode --color clip.mkv --depth head.mkv \
    -o "$w/sub/../clip.mkv"
unchanged "encode"
no_temporary "$w"
# Outputs on two devices are fine (written in place, never replaced).
run "touch --out /dev/null" 0 30 "$exe" touch head.mkv --trajectory t.csv --out /dev/null

# --- group 4: an output that cannot be completed is exit 1 with nothing under its name ---
"$L" 40 true || { echo "ulimit -f unavailable: skipped"; exit 77; }
run "play --record on a full disk" 1 30 "$L" 8 $P head.mkv --record r.mkv
[ ! -e r.mkv ] || fail "a lost recording was left as r.mkv"
grep -q "r.mkv" "$w/out" && fail "the summary names the lost recording"
run "play --force-log on a full disk" 1 30 "$L" 40 $P head.mkv --force-log f.csv \
    --stats s.json
[ ! -e f.csv ] || fail "a cut force log was left as f.csv"
[ -s s.json ] || fail "the stats that fit were not written"
run "play --snapshot-dir on a full disk" 1 30 "$L" 20 $P head.mkv --snapshot-dir snap \
    --snapshot-every 10
[ -z "$(ls snap 2>/dev/null)" ] || { ls -la snap; fail "cut snapshots were left"; }
mkdir hls
run "encode -o HLS on a full disk" 1 60 "$L" 8 "$exe" encode \
    --color synthetic:head,size=160x120,frames=150 --depth synthetic:head,size=160x120,frames=150 \
    --preset ultrafast -o hls/stream.m3u8
[ -z "$(ls hls)" ] || { ls -la hls; fail "a cut HLS output was left"; }
run "encode -o HLS" 0 60 "$exe" encode --color synthetic:head,size=160x120,frames=90 \
    --depth synthetic:head,size=160x120,frames=90 --preset ultrafast -o hls/stream.m3u8
tail -n 1 hls/stream.m3u8 | grep -q ENDLIST || fail "the HLS playlist is not complete"
no_temporary hls
run "probe --json > /dev/full" 1 30 sh -c '"$0" probe head.mkv --json >/dev/full' "$exe"
# touch's force log into a pipe whose reader leaves: EPIPE, not a silent death by SIGPIPE.
{ "$exe" touch head.mkv --trajectory long.csv --out /dev/stdout 2>"$w/err"; echo $? >"$w/rc"; } \
    | head -c 100 >/dev/null
[ "$(cat "$w/rc")" -eq 1 ] || { cat "$w/err"; fail "touch | head: exit $(cat "$w/rc"), want 1"; }
[ "$(wc -l <"$w/err")" -eq 1 ] || { cat "$w/err"; fail "touch | head: want one stderr line"; }
echo "touch --out /dev/stdout | head -c 100: exit 1: $(cat "$w/err")"
lines=any # the demo logs what it does
run "demo --out on a full disk" 1 120 "$L" 150 "$exe" demo --out dm --duration 3 \
    --frames 30 --size 160x120
lines=one
[ ! -e dm/force-log.csv ] || fail "demo left a cut force log"
grep -q "force-log.csv" "$w/out" && fail "the demo's summary names the lost force log"
no_temporary dm

# --- a folder that takes no file is found before the work ---
ro="$w/ro"
mkdir "$ro"
if [ "$(id -u)" -eq 0 ]; then
    chattr +i "$ro" 2>/dev/null || { echo "root without chattr +i here: read-only cases skipped"; ro=""; }
else
    chmod 0555 "$ro"
fi
if [ -n "$ro" ]; then
    run "play --snapshot-dir read-only" 2 10 $P head.mkv --snapshot-dir "$ro/snap"
    run "play --stats in a read-only folder" 2 10 $P head.mkv --stats "$ro/s.json"
    run "bench haptics --out read-only" 2 10 "$exe" bench haptics --quick --out "$ro/b"
    run "bench rt --out read-only" 2 10 "$exe" bench rt --out "$ro/b"
fi
echo PASS
