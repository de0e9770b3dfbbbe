#!/bin/sh
# End-to-end: `depthtouch encode --color X --depth X -o Y` of a DepthTouch file X keeps what X
# carries (issue 61): its holes stay holes (Y's depth_occupancy tag, and the hole share `probe
# --json --decode` counts in Y within 0.5 percentage points of the share the test put into X), and
# its material track comes over with the same codes (decoded by ffmpeg, byte for byte), for 8-bit
# lossy and 16-bit FFV1 depth in X; `--fill-holes` still fills them (no holes, no tag) and
# `--material-map` replaces the carried track. X as MP4 and MPEG-TS too (8- and 10-bit H.264
# depth; the streams found as play finds them: MP4 handler names, MPEG-TS timed metadata and
# order): Y, as MKV and as X's own container, has X's hole share (within 0.1 points), planes and
# material codes. Exit 77 (skip) without the ffmpeg CLI tools.
# Usage: transcode_holes_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start transcode-holes ffmpeg ffprobe cmp

# 6 frames of 64x48: metric depth 1.0 .. 2.26 m (mm) with a 16x20 hole (0) in the top-left corner.
e2e_color_pngs 64x48 0.2
ff -f lavfi -i "color=c=black:size=64x48:rate=30:duration=0.2" \
    -vf "format=gray16le,geq=lum='if(lt(X,16)*lt(Y,20),0,1000+20*X)'" -pix_fmt gray16be \
    -start_number 0 "$work/d-%03d.png" || fail "ffmpeg depth"
want_share=$(awk 'BEGIN { printf "%.4f", 100 * 16 * 20 / (64 * 48) }')

# Two materials, left and right half.
printf '[skin]\nlabel = "#ff0000"\npreset = "skin"\n[wood]\nlabel = "#00ff00"\npreset = "wood"\n' \
    >"$work/materials.toml"
ff -f lavfi -i "color=c=red:size=32x48,format=rgb24" -f lavfi -i "color=c=lime:size=32x48,format=rgb24" \
    -filter_complex hstack -frames:v 1 "$work/labels.png" || fail "ffmpeg labels"

# key NAME FILE: the number "NAME": N of a probe --json output.
key() { tr -d ' \n' <"$2" | sed -n "s/.*\"$1\":\([0-9.]*\).*/\1/p"; }
# share FILE: the hole share (%) probe --decode counts in FILE; also checks the JSON's other keys.
share() {
    "$exe" probe "$1" --json --decode >"$1.json" 2>"$1.err" || { cat "$1.err"; fail "probe $1"; }
    awk -v h="$(key hole_samples "$1.json")" -v n="$(key depth_samples "$1.json")" \
        'BEGIN { if (n > 0) printf "%.4f", 100 * h / n; else print "none" }'
}
near() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; exit !(d < 0.5 && d > -0.5) }'; }
# codes FILE OUT: the first material frame of FILE as raw RGB (found by its MKV title, its MP4
# handler name, or in MPEG-TS as the third video stream).
codes() {
    case "$1" in
    *.mp4) m=0:m:handler_name:material ;;
    *.ts) m=0:v:2 ;;
    *) m=0:m:title:material ;;
    esac
    ff -i "$1" -map "$m" -frames:v 1 -f rawvideo -pix_fmt rgb24 "$2" || fail "decode $1's material"
}

enc() { # output, encode args...
    out="$work/$1"; shift
    "$exe" encode -o "$out" --preset ultrafast --no-audio "$@" >"$out.enc" 2>&1 ||
        { cat "$out.enc"; fail "encode $(basename "$out")"; }
}

for bits in 8 16; do
    x="x$bits.mkv"
    enc "$x" --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --depth-bits "$bits" \
        --material-map "$work/labels.png" --materials "$work/materials.toml"
    sx=$(share "$work/$x")
    near "$sx" "$want_share" || fail "$x: holes $sx %, put in $want_share %"
    codes "$work/$x" "$work/$x.rgb"

    # The transcode keeps the holes and the material track.
    y="y$bits.mkv"
    enc "$y" --color "$work/$x" --depth "$work/$x"
    sy=$(share "$work/$y")
    [ "$(key occupancy "$work/$y.json")" -gt 0 ] 2>/dev/null ||
        { cat "$work/$y.enc"; fail "$y: no depth_occupancy (holes lost)"; }
    near "$sy" "$want_share" || { cat "$work/$y.enc"; fail "$y: holes $sy %, $x has $sx % ($want_share % put in)"; }
    grep -q '"material":{' "$work/$y.json" || tr -d ' \n' <"$work/$y.json" | grep -q '"material":{' ||
        { cat "$work/$y.enc"; fail "$y: no material track (X has one)"; }
    codes "$work/$y" "$work/$y.rgb"
    cmp -s "$work/$x.rgb" "$work/$y.rgb" || fail "$y: material codes differ from $x's"
    grep -q "^material: .*carried over from '$work/$x'" "$work/$y.enc" ||
        { cat "$work/$y.enc"; fail "$y: encode does not say the material track was carried over"; }

    # --fill-holes fills them: no hole left, no tag.
    f="f$bits.mkv"
    enc "$f" --color "$work/$x" --depth "$work/$x" --fill-holes
    sf=$(share "$work/$f")
    [ "$sf" = "0.0000" ] || fail "$f: holes $sf % after --fill-holes"
    [ "$(key occupancy "$work/$f.json")" = "0" ] || fail "$f: depth_occupancy after --fill-holes"
    echo "$bits-bit: holes put in $want_share %, X $sx %, Y $sy %, --fill-holes $sf %"
done

# --material-map replaces the carried track: Y's codes are the new map's (one material: wood).
printf '[wood]\nlabel = "#0000ff"\npreset = "wood"\n' >"$work/wood.toml"
ff -f lavfi -i "color=c=blue:size=64x48,format=rgb24" -frames:v 1 "$work/wood.png" || fail "ffmpeg wood"
enc r.mkv --color "$work/x8.mkv" --depth "$work/x8.mkv" --material-map "$work/wood.png" \
    --materials "$work/wood.toml"
codes "$work/r.mkv" "$work/r.rgb"
enc w.mkv --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material-map "$work/wood.png" \
    --materials "$work/wood.toml"
codes "$work/w.mkv" "$work/w.rgb"
cmp -s "$work/r.rgb" "$work/w.rgb" || fail "--material-map did not replace the carried material track"

# MP4 and MPEG-TS inputs: Y (MKV, and X's own container) keeps X's holes, planes and material.
same() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; exit !(d < 0.1 && d > -0.1) }'; }
for ext in mp4 ts; do
    for bits in 8 10; do
        x="x$bits.$ext"
        enc "$x" --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --depth-bits "$bits" \
            --material-map "$work/labels.png" --materials "$work/materials.toml"
        sx=$(share "$work/$x")
        near "$sx" "$want_share" || fail "$x: holes $sx %, put in $want_share %"
        codes "$work/$x" "$work/$x.rgb"
        for out in mkv "$ext"; do
            y="y$bits-$ext.$out"
            enc "$y" --color "$work/$x" --depth "$work/$x" --depth-bits "$bits"
            sy=$(share "$work/$y")
            [ "$(key occupancy "$work/$y.json")" -gt 0 ] 2>/dev/null ||
                { cat "$work/$y.enc"; fail "$y: no depth_occupancy (holes of $x lost)"; }
            same "$sy" "$sx" || { cat "$work/$y.enc"; fail "$y: holes $sy %, $x has $sx %"; }
            for plane in near_m far_m; do
                [ "$(key $plane "$work/$y.json")" = "$(key $plane "$work/$x.json")" ] ||
                    fail "$y: $plane $(key $plane "$work/$y.json"), $x has $(key $plane "$work/$x.json")"
            done
            tr -d ' \n' <"$work/$y.json" | grep -q '"material":{' ||
                { cat "$work/$y.enc"; fail "$y: no material track ($x has one)"; }
            codes "$work/$y" "$work/$y.rgb"
            cmp -s "$work/$x.rgb" "$work/$y.rgb" || fail "$y: material codes differ from $x's"
            grep -q "^material: .*carried over from '$work/$x'" "$work/$y.enc" ||
                { cat "$work/$y.enc"; fail "$y: encode does not say the material track was carried over"; }
            echo "$x -> $y: holes $sx % -> $sy %"
        done
    done
done
echo PASS
