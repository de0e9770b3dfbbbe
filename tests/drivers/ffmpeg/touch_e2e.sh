#!/bin/sh
# End-to-end: `depthtouch touch` on depth videos made with the ffmpeg CLI (gray H.264, FFV1 gray16
# nearness, 16-bit metric PNG sequence with --near/--far), then holes (docs/architecture.md §3
# "Holes": pressing over a hole of a camera's PNG sequence or of an encoded file gives no force,
# over the --fill-holes file it does; probe shows the threshold, widened for 10-bit depth), then a
# bad input. Exit 77 (skip) without the ffmpeg CLI. Usage: touch_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start touch-e2e ffmpeg

# A flat surface at mid nearness (z = 0 in the scene box); the HIP goes from 2 cm above it to 1 cm
# below in 1 s: contact from about t = 0.67 s.
ff -f lavfi -i color=c=0x808080:size=64x48:rate=30:duration=2 -c:v libx264 -pix_fmt gray "$work/gray264.mkv" || fail "ffmpeg gray h264"
ff -f lavfi -i color=c=0x808080:size=64x48:rate=30:duration=2 -c:v ffv1 -pix_fmt gray16le -metadata:s:v:0 title=depth "$work/ffv1.mkv" || fail "ffmpeg ffv1"
# Metric depth, 16-bit PNG in mm: 1000 mm everywhere, a hole (0) in the top-left corner.
ff -f lavfi -i color=c=black:size=64x48:rate=30:duration=2 -vf "format=gray16le,geq=lum='if(lt(X,8)*lt(Y,8),0,1000)'" \
    -pix_fmt gray16be -start_number 0 "$work/frame-%06d.depth.png" || fail "ffmpeg png sequence"
printf 't,x,y,z\n0,0,0,0.02\n1,0,0,-0.01\n' > "$work/traj.csv"

check() { # name, depth, extra args...
    name="$1"; depth="$2"; shift 2
    "$exe" touch "$depth" --trajectory "$work/traj.csv" --out "$work/$name.csv" "$@" 2>"$work/$name.err" \
        >"$work/$name.out" || { cat "$work/$name.err"; fail "$name: depthtouch touch exited $?"; }
    head -n 1 "$work/$name.csv" | grep -qx 't,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released' \
        || fail "$name: force log header"
    rows=$(($(wc -l <"$work/$name.csv") - 1))
    [ "$rows" -eq 1001 ] || fail "$name: $rows rows, want 1001 (1 s at 1000 Hz, both ends)"
    contact=$(awk -F, 'NR > 1 && $11 == 1 { n++ } END { print n + 0 }' "$work/$name.csv")
    first=$(awk -F, 'NR > 1 && $11 == 1 { print $1; exit }' "$work/$name.csv")
    [ "$contact" -gt 100 ] || fail "$name: $contact contact rows"
    # The summary agrees with the force log: updates and the share in contact.
    share=$(awk -v c="$contact" -v n="$rows" 'BEGIN { printf "%.0f", 100 * c / n }')
    grep -q "^touch: $rows updates over 1.000 s at 1000 Hz (finger): $share % in contact, max force " \
        "$work/$name.out" || { cat "$work/$name.out"; fail "$name: summary line (want $rows updates, $share % in contact)"; }
    echo "$name: $rows rows, $contact in contact, first contact at t=$first s"
}
check gray264 "$work/gray264.mkv"
check ffv1 "$work/ffv1.mkv"
# 1000 mm between near 0.5 m and far 2 m (inverse Z): nearness 1/3 of v_max → z = -0.0067 m.
check metric "$work/frame-%06d.depth.png" --near 0.5 --far 2 --fps 30
# The same sequence without planes: metric depth over the first frame's robust range (a flat 1 m
# widened to +-1 %: the surface near mid nearness), said in the summary.
check metric-auto "$work/frame-%06d.depth.png" --fps 30
grep -q "^touch: depth: 16-bit samples read as metric depth (0.001 m per unit), near 0.99 m, far 1.01 m" \
    "$work/metric-auto.out" || { cat "$work/metric-auto.out"; fail "metric-auto: no reading note"; }
# --quiet: nothing on stdout; --out /dev/stdout: the force log alone on stdout, the summary on stderr.
"$exe" touch "$work/ffv1.mkv" --trajectory "$work/traj.csv" --out "$work/q.csv" --quiet >"$work/q.out" ||
    fail "--quiet run"
[ ! -s "$work/q.out" ] || { cat "$work/q.out"; fail "--quiet printed something"; }
"$exe" touch "$work/ffv1.mkv" --trajectory "$work/traj.csv" --out /dev/stdout >"$work/s.csv" 2>"$work/s.err" ||
    fail "--out /dev/stdout run"
cmp -s "$work/s.csv" "$work/ffv1.csv" || fail "--out /dev/stdout: the force log differs from the file's"
grep -q "^touch: 1001 updates" "$work/s.err" || fail "--out /dev/stdout: no summary on stderr"
# --material: a still map of stiffness scale 2 (R = 128, docs/materials.md) doubles the force felt.
ff -f lavfi -i color=c=0x800000:size=16x12 -frames:v 1 "$work/stiff2.png" || fail "ffmpeg material png"
"$exe" touch "$work/ffv1.mkv" --trajectory "$work/traj.csv" --stiffness 200 --out "$work/k1.csv" --quiet ||
    fail "--stiffness 200 run"
"$exe" touch "$work/ffv1.mkv" --trajectory "$work/traj.csv" --stiffness 200 --material "$work/stiff2.png" \
    --out "$work/k2.csv" >"$work/k2.out" || fail "--material run"
grep -q "^touch: material: 1 frames read from '$work/stiff2.png' (the last holds)" "$work/k2.out" ||
    { cat "$work/k2.out"; fail "--material: no material line in the summary"; }
f1=$(tail -n 1 "$work/k1.csv" | cut -d, -f10)
f2=$(tail -n 1 "$work/k2.csv" | cut -d, -f10)
awk -v a="$f1" -v b="$f2" 'BEGIN { exit !(a > 1.0 && b > 1.95 * a && b < 2.05 * a) }' ||
    fail "--material: final force $f2 N, want twice the $f1 N without it"
echo "material: final force $f1 N without, $f2 N with stiffness scale 2"
"$exe" touch "$work/ffv1.mkv" --trajectory "$work/traj.csv" --material "$work/missing.png" \
    --out "$work/bad.csv" 2>"$work/bad.err"
[ $? -eq 2 ] && [ "$(wc -l <"$work/bad.err")" -eq 1 ] && [ ! -e "$work/bad.csv" ] ||
    { cat "$work/bad.err"; fail "missing --material input"; }
first=$(awk -F, 'NR > 1 && $11 == 1 { print $1; exit }' "$work/metric.csv")
awk -v t="$first" 'BEGIN { exit !(t > 0.85 && t < 0.93) }' || fail "metric: first contact at $first s, want about 0.89 s"

# Holes: 1000 mm with a 23x19 hole (0) where the finger presses (the box centre); colour for encode.
ff -f lavfi -i color=c=black:size=64x48:rate=30:duration=2 \
    -vf "format=gray16le,geq=lum='if(lt(abs(X-32),12)*lt(abs(Y-24),10),0,1000)'" \
    -pix_fmt gray16be -start_number 0 "$work/hole-%06d.depth.png" || fail "ffmpeg hole sequence"
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=2 -start_number 0 "$work/hole-%06d.color.png" ||
    fail "ffmpeg colour"
encode() { # output, extra args...
    out="$1"; shift
    "$exe" encode --color "$work/hole-%06d.color.png" --depth "$work/hole-%06d.depth.png" -o "$out" \
        --near 0.5 --far 2 --preset ultrafast "$@" >"$out.txt" 2>&1 || { cat "$out.txt"; fail "encode $out"; }
}
encode "$work/holes.mkv"
encode "$work/filled.mkv" --fill-holes
encode "$work/holes10.mkv" --depth-bits 10
encode "$work/holes.ts"
grep -q "holes 14.2 % of the samples (26220)" "$work/holes.mkv.txt" || { cat "$work/holes.mkv.txt"; fail "encode summary: hole share"; }
# The finger goes 1 cm behind the box's back (z = -0.02 m, the far plane, the code of a hole read
# as depth): only a hole that is free space gives no force there.
printf 't,x,y,z\n0,0,0,0.02\n1,0,0,-0.03\n' > "$work/deep.csv"
press() { # name, depth -> prints the largest |fz| and the contact rows
    "$exe" touch "$2" --trajectory "$work/deep.csv" --out "$work/$1.csv" --quiet --fps 30 ||
        fail "$1: depthtouch touch exited $?"
    awk -F, 'NR > 1 { f = $10 < 0 ? -$10 : $10; if (f > m) m = f; n += $11 } END { printf "%g %d", m, n }' "$work/$1.csv"
}
for case in "camera:$work/hole-%06d.depth.png" "tagged:$work/holes.mkv" "tagged10:$work/holes10.mkv"; do
    set -- $(press "${case%%:*}" "${case#*:}")
    [ "$1" = 0 ] && [ "$2" = 0 ] || fail "${case%%:*}: pressing over the hole gave force $1 N, $2 contact rows"
    echo "${case%%:*}: no force over the hole"
done
set -- $(press filled "$work/filled.mkv")
awk -v f="$1" 'BEGIN { exit !(f > 0.1) }' && [ "$2" -gt 100 ] ||
    fail "--fill-holes: pressing where the hole was gave force $1 N, $2 contact rows"
echo "--fill-holes: force $1 N where the hole was filled"
json() { "$exe" probe "$@" --json | tr -d ' \n'; }
json "$work/holes.mkv" | grep -q '"occupancy":24[,}]' || fail "probe: depth_occupancy of the 8-bit file"
json "$work/holes.ts" | grep -q '"occupancy":24[,}]' || fail "probe: depth_occupancy of the MPEG-TS file"
json "$work/filled.mkv" | grep -q '"occupancy":0[,}]' || fail "probe: --fill-holes file has a threshold"
json "$work/gray264.mkv" --decode | grep -q '"hole_below":0,' || fail "probe: an old file has holes"
json "$work/holes10.mkv" --decode | grep -q '"hole_below":6144,' ||
    fail "probe: 10-bit threshold 96 not widened to 6144 ($(json "$work/holes10.mkv" --decode))"
holes=$(json "$work/holes.mkv" --decode | sed -n 's/.*"hole_samples":\([0-9]*\).*/\1/p')
[ "$holes" -eq $((60 * 23 * 19)) ] || fail "probe --decode: $holes hole samples, want $((60 * 23 * 19))"
"$exe" probe "$work/holes.mkv" | grep -q "holes below 24 (depth_occupancy)" || fail "probe text: threshold"

# Bad input: one error line, exit 2, no output file.
echo "not a video" > "$work/bad.mkv"
"$exe" touch "$work/bad.mkv" --trajectory "$work/traj.csv" --out "$work/bad.csv" 2>"$work/bad.err"
rc=$?
[ "$rc" -eq 2 ] || fail "bad input: exit $rc, want 2"
[ "$(wc -l <"$work/bad.err")" -eq 1 ] || { cat "$work/bad.err"; fail "bad input: want one error line"; }
[ ! -e "$work/bad.csv" ] || fail "bad input left an output file"
ls "$work" | grep -q 'bad.csv.tmp' && fail "bad input left a temporary file"
echo "bad input: $(cat "$work/bad.err")"
"$exe" touch "$work/missing.mkv" --trajectory "$work/traj.csv" --out "$work/bad.csv" 2>"$work/bad.err"
[ $? -eq 2 ] && [ "$(wc -l <"$work/bad.err")" -eq 1 ] || fail "missing input"
echo "missing input: $(cat "$work/bad.err")"
echo PASS
