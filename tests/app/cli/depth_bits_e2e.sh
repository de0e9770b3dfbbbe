#!/bin/sh
# End-to-end: a flat depth picture 1.5 m away (near 1 m, far 3 m) encoded with 8-, 10- and 16-bit
# depth (H.264 4:0:0 8 and 10 bits, HEVC Main10 4:2:0, FFV1 16 bits) and played with the simulated
# hand pressing on it: the finger must rest on the same surface in all four (the proxy's height in
# the force log, within one 8-bit nearness level, 0.16 mm). Before, 10-bit depth reached the player
# as 8-bit samples and the surface was 20 mm off. The HEVC stream's chroma is neutral (512) and its
# encode prints nothing but the summary (x265 logs by itself unless told not to).
# Usage: depth_bits_e2e.sh DEPTHTOUCH   (exit 77 without the ffmpeg CLI)
exe=$1
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start depth-bits ffmpeg

e2e_color_pngs 64x48 1
ff -f lavfi -i color=c=black:size=64x48:rate=30:duration=1 -vf "format=gray16le,geq=lum='1500'" \
    -pix_fmt gray16be -start_number 0 "$work/d-%03d.png" || fail "ffmpeg depth"

# The median height of the proxy while in contact (force log column 7: proxy_z, column 11: contact).
proxy_z() {
    awk -F, 'NR > 1 && $11 == 1 { print $7 }' "$1" | sort -g | awk '{ v[NR] = $1 } END { if (NR) print v[int((NR + 1) / 2)] }'
}

for bits in 8 10 16 hevc; do
    if [ "$bits" = hevc ]; then codec="--depth-codec hevc"; else codec="--depth-bits $bits"; fi
    # shellcheck disable=SC2086 # $codec is two words
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/d$bits.mkv" \
        $codec --near 1 --far 3 --preset ultrafast >/dev/null 2>"$work/enc$bits.err" ||
        { cat "$work/enc$bits.err"; fail "encode $codec"; }
    "$exe" play "$work/d$bits.mkv" --display mock --haptic sim --haptic-options intent=press \
        --duration 1.2 --force-log "$work/f$bits.csv" >/dev/null 2>"$work/play$bits.err" ||
        { cat "$work/play$bits.err"; fail "play of the $bits-bit file"; }
    z=$(proxy_z "$work/f$bits.csv")
    [ -n "$z" ] || fail "$bits-bit depth: the finger never touched"
    echo "depth $bits bits: finger rests at z = $z m"
    eval "z$bits=$z"
done
[ ! -s "$work/enchevc.err" ] || { cat "$work/enchevc.err"; fail "encode --depth-codec hevc wrote to stderr"; }
[ "$(ffprobe -v error -select_streams v:1 -show_entries stream=codec_name,profile,pix_fmt -of csv=p=0 \
    "$work/dhevc.mkv")" = "hevc,Main 10,yuv420p10le" ] || fail "--depth-codec hevc is not HEVC Main 10 4:2:0"
for plane in u v; do
    ff -i "$work/dhevc.mkv" -map 0:v:1 -frames:v 1 -vf "extractplanes=$plane" -f rawvideo -pix_fmt gray10le \
        "$work/$plane.raw" || fail "ffmpeg extractplanes $plane"
    levels=$(od -An -v -tu2 -w2 "$work/$plane.raw" | tr -d ' ' | sort -u | tr '\n' ' ')
    [ "$levels" = "512 " ] || fail "HEVC depth chroma $plane holds levels $levels, want 512 alone"
done
for bits in 10 16 hevc; do
    eval "z=\$z$bits"
    awk -v a="$z8" -v b="$z" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 0.04 / 255) }' ||
        fail "$bits-bit depth puts the surface at $z m, 8-bit at $z8 m (more than one 8-bit level apart)"
done
echo "PASS"
