#!/bin/sh
# Fault suite of the tools: `touch`, `encode`, `probe` and `play` run against hostile
# inputs and outputs, each under a time bound. Every run must end in time with the documented exit
# code (2 bad input, 1 lost output), print exactly one line on stderr, and leave every output path
# that was not a regular file as it was (a device, a FIFO, a directory, a link).
# Inputs are made with the ffmpeg CLI (exit 77, skipped, without it).
# Usage: faults_tools_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start faults ffmpeg timeout
w="$work"

# Inputs: an untitled gray H.264 clip (depth by its 4:0:0 SPS), color and depth PNG sequences with
# a gap (0-9, 20-29), trajectories.
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -pix_fmt gray -c:v libx264 "$w/gray.mkv" \
    || fail "ffmpeg gray"
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -pix_fmt gray -c:v libx264 \
    -metadata:s:v:0 depth_bits=inf "$w/inf.mkv" || fail "ffmpeg inf"
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.34 -start_number 0 "$w/c-%03d.png" || fail "png"
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.34 -pix_fmt gray -start_number 0 \
    "$w/d-%03d.png" || fail "png"
for i in 0 1 2 3 4 5 6 7 8 9; do
    cp "$w/c-00$i.png" "$w/gc-02$i.png"; cp "$w/d-00$i.png" "$w/gd-02$i.png"
    cp "$w/c-00$i.png" "$w/gc-00$i.png"; cp "$w/d-00$i.png" "$w/gd-00$i.png"
done
printf 't,x,y,z\n0,0,0,0.01\n0.2,0.001,0.001,-0.005\n' >"$w/t.csv"
printf 't,x,y,z\n0,0,0,0\n1e9,0,0,0\n' >"$w/t1e9.csv"
printf 't,x,y,z\n0,0,0,0\n1e300,0,0,0\n' >"$w/t1e300.csv"
printf 't,x,y,z\n0,0,0,0\n0.1,1.7e308,-1.7e308,0\n' >"$w/huge.csv"
printf 't,x,y,z\n0,0,0,0\n0.1,-1e300,-1e300,-1e300\n' >"$w/neg.csv"
printf 't,x,y,z\n0,0,0,0\n100000,0,0,-0.01\n' >"$w/long.csv"
mkfifo "$w/fifo" "$w/outfifo" || fail "mkfifo"
mkdir "$w/dir"
echo old >"$w/target.csv"
ln -s "$w/target.csv" "$w/link.csv"
if [ "$(id -u)" -eq 0 ]; then mknod "$w/null" c 1 3 || fail "mknod"; fi

# run NAME WANT_RC BOUND_S CMD...: exit WANT_RC within BOUND_S seconds, one stderr line.
run() {
    name="$1"; want="$2"; bound="$3"; shift 3
    start=$(date +%s)
    timeout -k 5 "$bound" "$@" >"$w/out" 2>"$w/err" </dev/null
    rc=$?
    took=$(( $(date +%s) - start ))
    [ "$rc" -ne 124 ] && [ "$rc" -ne 137 ] || { cat "$w/err"; fail "$name: still running after $bound s"; }
    [ "$rc" -eq "$want" ] || { cat "$w/err"; fail "$name: exit $rc, want $want"; }
    if [ "$want" -ne 0 ]; then
        [ "$(wc -l <"$w/err")" -eq 1 ] || { cat "$w/err"; fail "$name: want one stderr line"; }
    fi
    echo "$name: exit $rc in ${took}s: $(head -c 200 "$w/err")"
}
kind() { stat -c %F "$1"; }
T="$exe touch $w/gray.mkv --trajectory"

# --- outputs that are not regular files are never replaced (item 2) ---
run "touch --out FIFO without reader" 2 10 $T "$w/t.csv" --out "$w/outfifo"
[ "$(kind "$w/outfifo")" = "fifo" ] || fail "touch replaced the FIFO"
run "touch --out DIR" 2 10 $T "$w/t.csv" --out "$w/dir"
[ -d "$w/dir" ] || fail "touch replaced the directory"
run "touch --out link" 0 30 $T "$w/t.csv" --out "$w/link.csv"
[ -L "$w/link.csv" ] && grep -q '^t,hip_x' "$w/target.csv" || fail "touch replaced the link"
run "touch --out /dev/full" 1 30 $T "$w/t.csv" --out /dev/full
[ "$(kind /dev/full)" = "character special file" ] || fail "/dev/full replaced"
run "encode -o FIFO without reader" 2 10 "$exe" encode --color "$w/c-%03d.png" \
    --depth "$w/d-%03d.png" -o "$w/outfifo" --preset ultrafast
[ "$(kind "$w/outfifo")" = "fifo" ] || fail "encode replaced the FIFO"
run "encode -o DIR" 2 10 "$exe" encode --color "$w/c-%03d.png" --depth "$w/d-%03d.png" -o "$w/dir"
run "encode -o /dev/full" 1 60 "$exe" encode --color "$w/c-%03d.png" --depth "$w/d-%03d.png" \
    -o /dev/full --format mkv --preset ultrafast
[ "$(kind /dev/full)" = "character special file" ] || fail "/dev/full replaced"
if [ -e "$w/null" ]; then
    run "touch --out device node" 0 30 $T "$w/t.csv" --out "$w/null"
    [ "$(kind "$w/null")" = "character special file" ] || fail "touch replaced the device node"
    run "encode -o device node" 0 60 "$exe" encode --color "$w/c-%03d.png" \
        --depth "$w/d-%03d.png" -o "$w/null" --format mkv --preset ultrafast
    [ "$(kind "$w/null")" = "character special file" ] || fail "encode replaced the device node"
fi
[ -z "$(ls "$w" | grep '\.tmp\.')" ] || fail "a temporary file was left"

# --- FIFOs and silent URLs: bounded waits (items 3, 4) ---
run "touch --trajectory FIFO without writer" 2 30 $T "$w/fifo" --out "$w/f.csv"
run "touch FIFO depth" 2 10 "$exe" touch "$w/fifo" --trajectory "$w/t.csv" --out "$w/f.csv"
run "probe FIFO without writer" 2 30 "$exe" probe "$w/fifo"
run "probe --decode FIFO" 2 10 "$exe" probe --decode "$w/fifo"
run "encode --color FIFO without writer" 2 30 "$exe" encode --color "$w/fifo" \
    --depth "$w/d-%03d.png" -o "$w/x.mkv"
# With a writer, probe reads the stream once and ends.
cat "$w/gray.mkv" >"$w/fifo" & e2e_bg=$!
run "probe FIFO with writer" 0 30 "$exe" probe "$w/fifo"
wait "$e2e_bg" 2>/dev/null; e2e_bg=""
run "encode from a silent URL" 2 40 "$exe" encode --color udp://127.0.0.1:9 \
    --depth udp://127.0.0.1:9 -o "$w/x.mkv" --duration 3
[ ! -e "$w/x.mkv" ] || fail "encode left an output"

# --- what an input may make touch allocate or compute (items 7, 8, 10) ---
run "touch trajectory to 1e9 s" 2 10 $T "$w/t1e9.csv" --out "$w/f.csv"
run "touch trajectory to 1e300 s" 2 10 $T "$w/t1e300.csv" --out "$w/f.csv"
run "touch trajectory of 1e5 s" 2 10 $T "$w/long.csv" --out "$w/f.csv"
run "touch --rate 1e9" 2 10 $T "$w/t.csv" --out "$w/f.csv" --rate 1e9
run "touch --trajectory /dev/zero" 2 20 $T /dev/zero --out "$w/f.csv"
run "touch /dev/zero --size 64x48" 2 30 "$exe" touch /dev/zero --size 64x48 \
    --trajectory "$w/t.csv" --out "$w/f.csv"
run "touch coordinates 1.7e308" 2 10 $T "$w/huge.csv" --out "$w/f.csv"
run "touch coordinates -1e300" 2 10 $T "$w/neg.csv" --out "$w/f.csv"
run "touch --stiffness 1e308" 2 10 $T "$w/t.csv" --out "$w/f.csv" --no-safety --stiffness 1e308
run "touch --damping 1e308" 2 10 $T "$w/t.csv" --out "$w/f.csv" --no-safety --damping 1e308
[ ! -e "$w/f.csv" ] || fail "a refused touch left an output"

# --- encode: gaps, nonsense options, sizes (items 13, 14) ---
run "encode sequence with a gap" 0 60 "$exe" encode --color "$w/gc-%03d.png" \
    --depth "$w/gd-%03d.png" -o "$w/gap.mkv" --preset ultrafast
grep -q "encoded 20 frame pairs" "$w/out" || { cat "$w/out"; fail "gap: want 20 frame pairs"; }
run "encode --fps 1e-9" 2 10 "$exe" encode --color "$w/c-%03d.png" --depth "$w/d-%03d.png" \
    -o "$w/x.mkv" --fps 1e-9
run "encode --frames -1" 2 10 "$exe" encode --color "$w/c-%03d.png" --depth "$w/d-%03d.png" \
    -o "$w/x.mkv" --frames -1
grep -q "At Most" "$w/err" && fail "--frames -1: CLI11's parse message"
run "encode --size 16384x16384" 2 3 "$exe" encode --color "$w/c-%03d.png" \
    --depth "$w/d-%03d.png" -o "$w/x.mkv" --size 16384x16384

# --- probe: gray H.264 is depth, nonsense tags are not printed (items 16, 14) ---
run "probe gray H.264" 0 30 "$exe" probe "$w/gray.mkv"
grep -q "depth (" "$w/out" || { cat "$w/out"; fail "gray H.264 4:0:0 not taken as depth"; }
run "probe depth_bits=inf" 0 30 "$exe" probe "$w/inf.mkv"
grep -q -- "-2147483648" "$w/out" && { cat "$w/out"; fail "depth_bits=inf printed as INT_MIN"; }

# --- demo and numbers: every option is checked before the clip is rendered; an empty or
# non-finite number is refused when the command line is read (CLI11 read "" as 0) ---
for args in "--rate 0" "--stiffness nan" "--haptic bogus" "--display bogus" "--size 161x121" \
    "--size 160x120x" "--scene bogus" "--frames 1" "--duration ''"; do
    eval "run \"demo $args\" 2 10 \"\$exe\" demo --out \"\$w/demo\" $args"
    [ ! -e "$w/demo" ] || fail "demo $args: made $w/demo before refusing"
done
run "touch --finger-radius nan" 2 10 $T "$w/t.csv" --out "$w/f.csv" --finger-radius nan
run "touch --near ''" 2 10 $T "$w/t.csv" --out "$w/f.csv" --near ''
run "encode --enhance-tolerance inf" 2 10 "$exe" encode --color "$w/c-%03d.png" \
    --depth "$w/d-%03d.png" -o "$w/x.mkv" --enhance-tolerance inf
[ ! -e "$w/f.csv" ] && [ ! -e "$w/x.mkv" ] || fail "a refused run left an output"
run "play --remote evdev on a file that is not an input device" 2 10 "$exe" play \
    'mock://clip?frames=3' --source mock --decoder mock --display mock --haptic none \
    --remote evdev --remote-options device=/dev/null

# --- touch finds depth as play and probe do: an untagged MPEG-TS of colour and gray H.264 (no
# titles: the gray pixel format says depth), and a single gray stream in MPEG-TS, read to its end
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 \
    -map 0 -map 1 -c:v libx264 -pix_fmt:v:0 yuv420p -pix_fmt:v:1 gray "$w/untagged.ts" || fail "ffmpeg ts"
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -pix_fmt gray -c:v libx264 "$w/gray.ts" \
    || fail "ffmpeg gray ts"
for clip in untagged.ts gray.ts; do
    run "touch $clip" 0 30 "$exe" touch "$w/$clip" --trajectory "$w/t.csv" --out "$w/ts.csv"
    # every update of the 0.2 s trajectory at 1 kHz: the depth was read to the end
    [ "$(wc -l <"$w/ts.csv")" -eq 202 ] || fail "touch $clip: want 201 updates"
done

# --- a FIFO output with an ordinary reader: the reader gets the whole force log (the check for a
# reader closed its write end and gave the reader an end of file before the output was written)
mkfifo "$w/readfifo" || fail "mkfifo"
cat "$w/readfifo" >"$w/fromfifo.csv" &
reader=$!
run "touch --out FIFO with a reader" 0 30 $T "$w/t.csv" --out "$w/readfifo"
wait "$reader"
[ "$(wc -l <"$w/fromfifo.csv")" -eq 202 ] || fail "the FIFO's reader got $(wc -l <"$w/fromfifo.csv") lines, want 202"
# --- bench options out of range are refused at once, before any measurement (each bound, and a
# value inside it that is then measured: bench media's depth CRF is x264's 0..51)
for crf in -1 52; do
    run "bench media --depth-crfs $crf" 2 10 "$exe" bench media --synthetic --depth-crfs "$crf" --out "$w/bm"
    grep -q -- "--depth-crfs values must be in 0..51" "$w/err" || fail "bench media --depth-crfs $crf: not the range"
done
[ ! -e "$w/bm" ] || fail "a refused bench wrote its folder"
# --- bench rt measures the cases asked for, no more: one rate, one policy, one lock give a bare
# loop row and a haptic task row, each with that rate, policy and lock (not the defaults besides)
run "bench rt, one case" 0 60 "$exe" bench rt --duration 0.2 --rates 1000 --policies other --locks none \
    --out "$w/brt"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { n++; loops = loops " " $col["loop"]
      if ($col["rate_hz"] != 1000 || $col["policy"] != "SCHED_OTHER" || $col["memory_lock"] != "none") bad = bad " " $0 }
    END { if (n != 2 || loops != " bare task" || bad != "") { printf "rows %d (%s):%s\n", n, loops, bad; exit 1 } }' \
    "$w/brt/rt_bench.csv" || fail "bench rt: not the one case asked for"
# --- an address space limit too small for the EGL driver (`ulimit -v 600000`: a crash or a hang in
# Mesa before) is said up front, exit 1; the mock display still plays under it. (A sanitizer build
# cannot start under such a limit at all: its shadow memory is terabytes of address space.)
if sh -c 'ulimit -v 600000 && exec "$0" --version' "$exe" >/dev/null 2>&1; then
    run "play --display headless under ulimit -v 600000" 1 20 sh -c \
        'ulimit -v 600000 && exec "$0" play "mock://clip?frames=3" --source mock --decoder mock --display headless --haptic none' "$exe"
    grep -q "ulimit -v" "$w/err" || fail "the line does not name the limit"
    run "play --display mock under ulimit -v 600000" 0 20 sh -c \
        'ulimit -v 600000 && exec "$0" play "mock://clip?frames=3" --source mock --decoder mock --display mock --haptic none --quiet' "$exe"
else
    echo "ulimit -v 600000: this build cannot start under it (a sanitizer build): cases skipped"
fi
echo PASS
