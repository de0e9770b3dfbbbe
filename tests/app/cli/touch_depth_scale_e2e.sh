#!/bin/sh
# End-to-end: `depthtouch touch --near --far --depth-scale` on 16-bit metric depth in TUM's units
# (0.2 mm, --depth-scale 0.0002). A flat wall 0.9 m away (4500 units) is pressed by a HIP going
# from z = 0.02 m to z = -0.01 m in 1 s at 1000 Hz. The test works out where the wall lies in the
# scene box itself (docs/architecture.md §3: inverse-Z nearness between near and far, then
# z = (nearness - 0.5) * box depth) and checks what a user reads against it: the share of updates in
# contact (summary and force log), the force at the deepest point (k x penetration, force log and
# the summary's max force), and the same wall written in millimetres with the default scale gives
# the same force log. Exit 77 (skip) without the ffmpeg CLI. Usage: touch_depth_scale_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start touch-scale ffmpeg

near=0.5; far=2; wall=0.9; k=800; z0=0.02; z1=-0.01; box_depth=0.04
# plane FILE-PATTERN UNITS: 16-bit PNGs of the wall at UNITS everywhere, 2 s at 30 fps.
plane() {
    ff -f lavfi -i color=c=black:size=64x48:rate=30:duration=2 -vf "format=gray16le,geq=lum='$2'" \
        -pix_fmt gray16be -start_number 0 "$1" || fail "ffmpeg depth $2"
}
plane "$work/tum-%06d.depth.png" "$(awk -v d=$wall 'BEGIN { printf "%d", d / 0.0002 + 0.5 }')"
plane "$work/mm-%06d.depth.png" "$(awk -v d=$wall 'BEGIN { printf "%d", d / 0.001 + 0.5 }')"
printf 't,x,y,z\n0,0,0,%s\n1,0,0,%s\n' "$z0" "$z1" >"$work/traj.csv"

# Where the wall is (z, m), when the HIP reaches it, the share of the 1001 updates below it and the
# force at the end: from the geometry alone.
zs=$(awk -v d=$wall -v n=$near -v f=$far -v b=$box_depth \
    'BEGIN { t = (1 / d - 1 / f) / (1 / n - 1 / f); printf "%.9f", (t - 0.5) * b }')
share=$(awk -v zs="$zs" -v a=$z0 -v b=$z1 'BEGIN { tc = (a - zs) / (a - b); printf "%.4f", 100 * (1 - tc) }')
force=$(awk -v zs="$zs" -v b=$z1 -v k=$k 'BEGIN { printf "%.6f", k * (zs - b) }')
echo "wall at z = $zs m: want $share % of the updates in contact, $force N at the deepest point"

touch_run() { # name, depth pattern, extra args...
    name="$1"; depth="$2"; shift 2
    "$exe" touch "$depth" --trajectory "$work/traj.csv" --out "$work/$name.csv" --fps 30 --stiffness $k \
        "$@" >"$work/$name.out" 2>"$work/$name.err" || { cat "$work/$name.err"; fail "$name: touch exited $?"; }
    cat "$work/$name.out"
}
touch_run tum "$work/tum-%06d.depth.png" --near $near --far $far --depth-scale 0.0002
touch_run mm "$work/mm-%06d.depth.png" --near $near --far $far

# The summary's share in contact and max force against the geometry (one update is 0.1 %; the
# force within 1 %).
line=$(grep '^touch: 1001 updates' "$work/tum.out") || fail "tum: no summary line"
got_share=$(echo "$line" | sed -n 's/.*: \([0-9]*\) % in contact.*/\1/p')
got_max=$(echo "$line" | sed -n 's/.*max force \([0-9.]*\) N.*/\1/p')
awk -v g="$got_share" -v w="$share" 'BEGIN { d = g - w; exit !(d < 1 && d > -1) }' ||
    fail "tum: summary says $got_share % in contact, the wall at $zs m gives $share %"
awk -v g="$got_max" -v w="$force" 'BEGIN { exit !(g > 0.99 * w && g < 1.01 * w) }' ||
    fail "tum: summary says max force $got_max N, k x penetration is $force N"
# The force log: the rows in contact and the last row's force.
rows=$(awk -F, 'NR > 1 { n++ } END { print n + 0 }' "$work/tum.csv")
contact=$(awk -F, 'NR > 1 && $11 == 1 { n++ } END { print n + 0 }' "$work/tum.csv")
awk -v c="$contact" -v n="$rows" -v w="$share" 'BEGIN { d = 100 * c / n - w; exit !(d < 0.3 && d > -0.3) }' ||
    fail "tum: $contact of $rows rows in contact, the wall at $zs m gives $share %"
last=$(tail -n 1 "$work/tum.csv" | awk -F, '{ printf "%.6f", sqrt($8 * $8 + $9 * $9 + $10 * $10) }')
awk -v g="$last" -v w="$force" 'BEGIN { exit !(g > 0.99 * w && g < 1.01 * w) }' ||
    fail "tum: force $last N at the deepest point, k x penetration is $force N"
echo "tum: $contact of $rows rows in contact, $last N at the deepest point"
# The same wall in millimetres: the same force log.
cmp -s "$work/tum.csv" "$work/mm.csv" || fail "the wall in 0.2 mm units and in mm give different force logs"
echo PASS
