#!/bin/sh
# End-to-end: `depthtouch encode --material-map` with label colours that differ from their neighbour
# in one channel only (red, then blue, then green: each pair tells a label from the previous one by
# that channel alone), read back from the file's material track and checked region by region
# against the codes docs/materials.md gives the table's values (R = stiffness scale x 64,
# G = static friction x 100, B = dynamic friction x 100, rounded). Exit 77 (skip) without the ffmpeg
# CLI tools. Usage: material_labels_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start material-labels ffmpeg od

e2e_color_pngs 64x48 0.2
ff -f lavfi -i color=c=gray:size=64x48:rate=30:duration=0.2 -pix_fmt gray -start_number 0 "$work/d-%03d.png" \
    || fail "ffmpeg depth"

# Four materials in four vertical stripes 16 pixels wide, left to right; each label differs from the
# one on its left in one channel: skin #ff0000, cloth #ff00ff (blue), wood #ffffff (green),
# steel #00ffff (red). name, label (R G B), stiffness scale, static and dynamic friction:
cat >"$work/materials.txt" <<'EOF'
skin 255 0 0 0.5 0.6 0.5
cloth 255 0 255 0.25 0.5 0.4
wood 255 255 255 1.5 0.45 0.35
steel 0 255 255 3 0.3 0.25
EOF
awk '{ printf "[%s]\nlabel = \"#%02x%02x%02x\"\nstiffness_scale = %s\nstatic_friction = %s\ndynamic_friction = %s\n",
       $1, $2, $3, $4, $5, $6, $7 }' "$work/materials.txt" >"$work/materials.toml"
# The label picture (binary PPM, exact colours): each row is the four stripes.
row=$(while read -r _ r g b _; do
    px=$(printf '\\%03o\\%03o\\%03o' "$r" "$g" "$b"); i=0
    while [ "$i" -lt 16 ]; do printf '%s' "$px"; i=$((i + 1)); done
done <"$work/materials.txt")
{ printf 'P6\n64 48\n255\n'; y=0; while [ "$y" -lt 48 ]; do printf "$row"; y=$((y + 1)); done; } >"$work/labels.ppm"
[ "$(wc -c <"$work/labels.ppm")" -eq $((13 + 64 * 48 * 3)) ] || fail "label picture size"

"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material-map "$work/labels.ppm" \
    --materials "$work/materials.toml" -o "$work/out.mkv" --preset ultrafast >"$work/enc.txt" 2>&1 ||
    { cat "$work/enc.txt"; fail "encode --material-map"; }
# The summary calls the label map what it is: one still for every frame (not "N frames read").
grep -q "^material: .* (the label map '$work/labels.ppm', one still for every frame)$" "$work/enc.txt" ||
    { cat "$work/enc.txt"; fail "encode's material summary line"; }
ff -i "$work/out.mkv" -map 0:2 -frames:v 1 -f rawvideo -pix_fmt rgb24 "$work/codes.raw" || fail "decode the material track"

# Each stripe's codes as read back (every pixel of the stripe must be one triple) against the table.
od -An -v -tu1 -w3 "$work/codes.raw" | awk -v table="$work/materials.txt" '
    BEGIN {
        n = 0
        while ((getline line < table) > 0) {
            split(line, f, " ")
            name[n] = f[1]; label[n] = sprintf("#%02x%02x%02x", f[2], f[3], f[4])
            want[n] = sprintf("%d %d %d", int(f[5] * 64 + 0.5), int(f[6] * 100 + 0.5), int(f[7] * 100 + 0.5))
            n++
        }
    }
    {
        x = (NR - 1) % 64; s = int(x / 16); got = $1 " " $2 " " $3
        if (got != want[s] && !(s in bad)) {
            bad[s] = 1; errors++
            printf "FAIL: %s (label %s, pixel %d, %d): codes %s, want %s\n", name[s], label[s], x, int((NR - 1) / 64), got, want[s]
        }
        seen++
    }
    END {
        if (seen != 64 * 48) { printf "FAIL: %d material pixels, want %d\n", seen, 64 * 48; exit 1 }
        for (s = 0; s < n; ++s) if (!(s in bad)) printf "%s (label %s): codes %s\n", name[s], label[s], want[s]
        exit errors > 0
    }' || fail "material codes differ from the table's"
echo PASS
