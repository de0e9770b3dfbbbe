#!/bin/sh
# End-to-end: the force log's force columns fx, fy, fz on a tilted plane, in the documented frame
# (docs/architecture.md §3: scene box, x right, y up, z toward the viewer; the device frame has the
# same axes). The plane's nearness rises to the right and changes with the row, so its outward
# normal has a different x, y and z component; the test works it out from the samples it wrote
# (sample (c, r) is x = (c - (W-1)/2) s, y = ((H-1)/2 - r) s, z = (v / 65535 - 0.5) box depth) and
# checks, column by column, that the force of each pressed update points along it, out of the
# surface. Both writers of the log: `touch --out` (a raw 16-bit nearness file, a HIP pressing
# straight down) and `play --force-log` (a file made by `encode` from metric depth with the linear
# mapping, the simulated hand pressing, mock display). Exit 77 (skip) without the ffmpeg CLI.
# Usage: force_direction_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start force-direction ffmpeg

W=64; H=48; box_width=0.1; box_depth=0.04
# normal DV_DC DV_DR: the unit outward normal "nx ny nz" of a plane whose nearness changes by DV_DC
# per column and DV_DR per row (z = h(x, y): n = (-dh/dx, -dh/dy, 1) / |...|).
normal() {
    awk -v a="$1" -v b="$2" -v W=$W -v bw=$box_width -v bd=$box_depth 'BEGIN {
        s = bw / (W - 1); p = a * bd / (65535 * s); q = -b * bd / (65535 * s)
        l = sqrt(p * p + q * q + 1); printf "%.6f %.6f %.6f", -p / l, -q / l, 1 / l }'
}
# check NAME LOG NX NY NZ: every update in contact pushing 0.5 N or more pushes along the normal
# (each column of the unit force within 0.02 of the normal's), and there are at least 100 of them.
check() {
    awk -F, -v name="$1" -v nx="$3" -v ny="$4" -v nz="$5" '
        NR > 1 && $11 == 1 {
            f = sqrt($8 * $8 + $9 * $9 + $10 * $10)
            if (f < 0.5) next
            n++
            ux = $8 / f; uy = $9 / f; uz = $10 / f
            if ((ux - nx) ^ 2 > 0.0004 || (uy - ny) ^ 2 > 0.0004 || (uz - nz) ^ 2 > 0.0004) {
                if (!bad++) printf "FAIL: %s: t = %s: fx, fy, fz = %s, %s, %s N: direction %.4f %.4f %.4f, the surface normal is %s %s %s\n", name, $1, $8, $9, $10, ux, uy, uz, nx, ny, nz
            }
        }
        END {
            if (n < 100) { printf "FAIL: %s: %d updates pressing 0.5 N or more, want 100 or more\n", name, n; exit 1 }
            if (bad) { printf "FAIL: %s: %d of %d pressed updates off the normal\n", name, bad, n; exit 1 }
            printf "%s: %d pressed updates along the normal %s %s %s\n", name, n, nx, ny, nz
        }' "$2" || exit 1
}

# touch: nearness 10624 + 512 c + 256 r (the box centre at mid nearness), 2 s of raw frames.
ff -f lavfi -i color=c=black:size=${W}x${H}:rate=30:duration=2 -vf "format=gray16le,geq=lum='10624+512*X+256*Y'" \
    -f rawvideo -pix_fmt gray16le "$work/plane.raw" || fail "ffmpeg raw plane"
printf 't,x,y,z\n0,0,0,0.02\n1,0,0,-0.008\n' >"$work/press.csv"
"$exe" touch "$work/plane.raw" --size ${W}x$H --bits 16 --trajectory "$work/press.csv" --out "$work/touch.csv" \
    --quiet 2>"$work/touch.err" || { cat "$work/touch.err"; fail "touch exited $?"; }
check touch "$work/touch.csv" $(normal 512 256)

# play: metric depth 2000 mm - 16 mm per column + 8 mm per row, linear between 1 and 3 m: nearness
# (3000 - d) / 2000 x 65535, so 524.28 per column and -262.14 per row.
e2e_color_pngs "${W}x$H" 1
ff -f lavfi -i color=c=black:size=${W}x$H:rate=30:duration=1 -vf "format=gray16le,geq=lum='2000-16*(X-32)+8*(Y-24)'" \
    -pix_fmt gray16be -start_number 0 "$work/d-%03d.png" || fail "ffmpeg depth"
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/plane.mkv" --depth-bits 16 \
    --near 1 --far 3 --depth-mapping linear --preset ultrafast >"$work/enc.txt" 2>&1 ||
    { cat "$work/enc.txt"; fail "encode"; }
"$exe" play "$work/plane.mkv" --display mock --haptic sim --haptic-options intent=press --duration 1.5 \
    --force-log "$work/play.csv" >"$work/play.txt" 2>&1 || { cat "$work/play.txt"; fail "play exited $?"; }
check play "$work/play.csv" $(normal 524.28 -262.14)
echo PASS
