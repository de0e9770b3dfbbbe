#!/bin/sh
# End-to-end: the material track (docs/materials.md) through `depthtouch encode` and
# `probe`. Color and depth are made with the ffmpeg CLI, material pictures written as binary PPM
# here (exact codes). For MKV, MP4 and MPEG-TS: `--material` (a still, a two-picture sequence whose
# last picture holds, stripes shrunk by a non-integer ratio) and `--material-map` with a
# materials.toml; stream 2 must be H.264 gbrp (titled `material` in MKV), and the ffmpeg CLI's
# rgb24 decode of it must equal, byte for byte, the codes expected (lossless, nearest-neighbour).
# Bad tables, a label colour the table lacks, a missing file and conflicting options: exit 2, one
# stderr line, no output file. Skipped (77) without the ffmpeg CLI tools.
# Usage: material_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start material-e2e ffmpeg ffprobe cmp od

# octal R G B: the printf escapes of one pixel.
octal() { printf '\\%03o\\%03o\\%03o' "$1" "$2" "$3"; }
# row N PIXEL: PIXEL (escapes) N times.
row() { r=""; i=0; while [ "$i" -lt "$1" ]; do r="$r$2"; i=$((i + 1)); done; printf '%s' "$r"; }
# quads W H TL TR BL BR: raw RGB24, W x H in four quadrants of the given pixels (escapes).
quads() {
    top="$(row $(($1 / 2)) "$3")$(row $(($1 / 2)) "$4")"
    bottom="$(row $(($1 / 2)) "$5")$(row $(($1 / 2)) "$6")"
    y=0; while [ "$y" -lt $(($2 / 2)) ]; do printf "$top"; y=$((y + 1)); done
    y=0; while [ "$y" -lt $(($2 / 2)) ]; do printf "$bottom"; y=$((y + 1)); done
}
# ppm W H FILE <raw: a binary PPM of the raw RGB24 on stdin.
ppm() { { printf 'P6\n%d %d\n255\n' "$1" "$2"; cat; } >"$3"; }
# repeat N FILE OUT: FILE repeated N times.
repeat() { : >"$3"; i=0; while [ "$i" -lt "$1" ]; do cat "$2" >>"$3"; i=$((i + 1)); done; }

e2e_color_pngs 64x48 0.4
ff -f lavfi -i color=c=gray:size=64x48:rate=30:duration=0.4 -pix_fmt gray -start_number 0 "$work/d-%03d.png" \
    || fail "ffmpeg depth"
frames=12

# Material codes (R: stiffness scale x64, G: mu_s x100, B: mu_d x100).
A=$(octal 64 50 40); B=$(octal 128 20 10); C=$(octal 16 0 0); D=$(octal 255 255 255)
quads 32 24 "$A" "$B" "$C" "$D" | ppm 32 24 "$work/still.ppm"
quads 64 48 "$A" "$B" "$C" "$D" >"$work/still.raw"   # the still, doubled nearest-neighbour
repeat $frames "$work/still.raw" "$work/still.expected"
# A two-picture sequence: picture 0 uniform A, picture 1 the quadrants, held to the end.
quads 32 24 "$A" "$A" "$A" "$A" | ppm 32 24 "$work/seq-000.ppm"
cp "$work/still.ppm" "$work/seq-001.ppm"
quads 64 48 "$A" "$A" "$A" "$A" >"$work/seq.expected"
repeat $((frames - 1)) "$work/still.raw" "$work/seq.rest"
cat "$work/seq.rest" >>"$work/seq.expected"
# Stripes one pixel wide, 21x16 -> 64x48: no pixel may be a blend of the two materials.
S1=$(octal 10 20 30); S2=$(octal 200 150 100)
stripe="$(row 10 "$S1$S2")$S1"
y=0; while [ "$y" -lt 16 ]; do printf "$stripe"; y=$((y + 1)); done \
    | ppm 21 16 "$work/stripes.ppm"
# Labels: red, green, blue, white quadrants; the table below gives their codes.
quads 32 24 "$(octal 255 0 0)" "$(octal 0 255 0)" "$(octal 0 0 255)" "$(octal 255 255 255)" \
    | ppm 32 24 "$work/labels.ppm"
cat >"$work/materials.toml" <<'EOF'
[skin]
label = "#ff0000"
stiffness_scale = 0.5
static_friction = 0.6
dynamic_friction = 0.5
[cloth]
label = "#00FF00"
preset = "cloth"
[steel]
label = "#0000ff"
preset = "metal"
dynamic_friction = 0.25
[hard]
label = "#ffffff"
stiffness_scale = 3.984375
static_friction = 2.55
dynamic_friction = 0
EOF
# skin 32/60/50; cloth preset 0.25, 0.5, 0.4 -> 16/50/40; metal 3.0, 0.3 and 0.25 -> 192/30/25.
quads 64 48 "$(octal 32 60 50)" "$(octal 16 50 40)" "$(octal 192 30 25)" "$(octal 255 255 0)" >"$work/map.raw"
repeat $frames "$work/map.raw" "$work/map.expected"

# check NAME FILE EXT EXPECTED: stream 2 is H.264 gbrp (titled in MKV) and decodes to EXPECTED.
check() {
    s=$(probe -select_streams 2 -show_entries stream=codec_name,pix_fmt -of csv=p=0 "$2" | grep . | head -n 1)
    [ "$s" = "h264,gbrp" ] || fail "$1: stream 2 is '$s', want h264,gbrp"
    if [ "$3" = mkv ]; then
        t=$(probe -select_streams 2 -show_entries stream_tags=title -of csv=p=0 "$2")
        [ "$t" = material ] || fail "$1: stream 2 title '$t'"
    fi
    ff -i "$2" -map 0:2 -f rawvideo -pix_fmt rgb24 "$work/$1.raw" || fail "$1: decode"
    cmp -s "$work/$1.raw" "$4" || fail "$1: material codes differ from the expected ($(cmp "$work/$1.raw" "$4" 2>&1))"
    "$exe" probe "$2" >"$work/$1.probe" 2>&1 || fail "$1: probe"
    grep -q "^material: stream #2 64x48 h264 gbrp, lossless yes.*has materials" "$work/$1.probe" \
        || { cat "$work/$1.probe"; fail "$1: probe's material line"; }
}

for ext in mkv mp4 ts; do
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material "$work/still.ppm" \
        -o "$work/still.$ext" --preset ultrafast >"$work/out.txt" 2>&1 || { cat "$work/out.txt"; fail "still.$ext"; }
    check "still-$ext" "$work/still.$ext" $ext "$work/still.expected"
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material "$work/seq-%03d.ppm" \
        -o "$work/seq.$ext" --preset ultrafast >"$work/out.txt" 2>&1 || { cat "$work/out.txt"; fail "seq.$ext"; }
    check "seq-$ext" "$work/seq.$ext" $ext "$work/seq.expected"
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material-map "$work/labels.ppm" \
        --materials "$work/materials.toml" -o "$work/map.$ext" --preset ultrafast >"$work/out.txt" 2>&1 \
        || { cat "$work/out.txt"; fail "map.$ext"; }
    check "map-$ext" "$work/map.$ext" $ext "$work/map.expected"
done
grep -q "material first frame: stiffness scale 0.25..3.984, static friction 0.3..2.55, dynamic friction 0..0.5" \
    "$work/map-mkv.probe" || { cat "$work/map-mkv.probe"; fail "probe's first-frame ranges"; }
echo "material: $(grep '^material' "$work/map-mkv.probe" | tr '\n' ';')"

# Stripes shrunk and enlarged by 64/21: only the two materials' codes come out.
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material "$work/stripes.ppm" \
    -o "$work/stripes.mkv" --preset ultrafast >/dev/null 2>&1 || fail "stripes encode"
ff -i "$work/stripes.mkv" -map 0:2 -f rawvideo -pix_fmt rgb24 "$work/stripes.raw" || fail "stripes decode"
triples=$(od -An -v -tu1 -w3 "$work/stripes.raw" | sort -u | tr -s ' ' | tr '\n' ';')
[ "$triples" = " 10 20 30; 200 150 100;" ] || fail "stripes: blended codes: $triples"

# A file without the track prints no material line.
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/plain.mkv" --preset ultrafast \
    >/dev/null 2>&1 || fail "plain encode"
"$exe" probe "$work/plain.mkv" | grep -q "^material" && fail "plain: a material line"

# Bad input: exit 2, one stderr line naming the problem, no output file.
bad() { # name, expected text, args...
    name="$1"; want="$2"; shift 2
    rm -f "$work/bad.mkv"
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/bad.mkv" \
        --preset ultrafast "$@" >/dev/null 2>"$work/bad.err"
    rc=$?
    [ "$rc" -eq 2 ] || { cat "$work/bad.err"; fail "$name: exit $rc, want 2"; }
    [ "$(wc -l <"$work/bad.err")" -eq 1 ] || { cat "$work/bad.err"; fail "$name: want one stderr line"; }
    grep -q -- "$want" "$work/bad.err" || { cat "$work/bad.err"; fail "$name: want '$want'"; }
    [ -e "$work/bad.mkv" ] && fail "$name: output written"
    [ -z "$(ls "$work" | grep '\.tmp\.')" ] || fail "$name: temporary file left"
}
printf '[a]\nlabel = "#ff0000"\nstifness = 1\n' >"$work/unknown.toml"
bad "unknown key" "unknown key 'stifness'" --material-map "$work/labels.ppm" --materials "$work/unknown.toml"
printf '[a]\nlabel = "#ff0000"\nstatic_friction = 3\n' >"$work/range.toml"
bad "out of range" "static_friction must be a number in 0..2.55" --material-map "$work/labels.ppm" \
    --materials "$work/range.toml"
head -n 8 "$work/materials.toml" >"$work/partial.toml" # skin and cloth only
bad "missing label" "label colour #0000ff (pixel 0, 12) has no material" --material-map "$work/labels.ppm" \
    --materials "$work/partial.toml"
bad "missing table" "--materials '$work/none.toml'" --material-map "$work/labels.ppm" --materials "$work/none.toml"
bad "missing labels" "--material-map '$work/none.png'" --material-map "$work/none.png" --materials "$work/materials.toml"
bad "missing material" "cannot open material input" --material "$work/none.png"
bad "both" "exclude each other" --material "$work/still.ppm" --material-map "$work/labels.ppm" \
    --materials "$work/materials.toml"
bad "table alone" "go together" --materials "$work/materials.toml"
echo "material e2e: ok"
