#!/bin/sh
# End-to-end: the depth metadata `depthtouch probe --json` reports against the planes, mapping and
# bits the test passed to `depthtouch encode` and against ffprobe's reading of the file's tags:
# "depth_metadata" near_m, far_m, mapping, bits and occupancy, and the text report's line, for two
# files that differ in every key (MP4: inverse_z 10-bit with a hole; MKV: linear 16-bit, filled), and
# a file of 8-bit nearness without planes (unknown: null and "unknown", not 0 m).
# Exit 77 (skip) without the ffmpeg CLI tools. Usage: probe_json_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start probe-json ffmpeg ffprobe

e2e_color_pngs 64x48 0.4
# 1.0 .. 2.26 m in mm with a hole (0) in the top-left corner.
e2e_metric_depth_pngs 0.4

# key NAME JSON: the value of "NAME" in the one-line "depth_metadata" object (strings unquoted).
key() { printf '%s\n' "$2" | sed -n "s/.*\"$1\":\"\{0,1\}\([^,\"}]*\).*/\1/p"; }
# tag NAME FILE: the file's tag NAME as ffprobe reads it (any case; container or stream tags).
tag() {
    ffprobe -v error -show_entries format_tags:stream_tags -of default=nw=1 "$2" |
        sed -n "s/^TAG:$1=//Ip" | head -n 1
}
same() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; exit !(a != "" && b != "" && d < 1e-9 && d > -1e-9) }'; }

check() { # file, near, far, mapping, bits, encode args...
    file="$1"; near="$2"; far="$3"; mapping="$4"; bits="$5"; shift 5
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/$file" --preset ultrafast \
        --near "$near" --far "$far" --depth-mapping "$mapping" --depth-bits "$bits" "$@" \
        >"$work/$file.enc" 2>&1 || { cat "$work/$file.enc"; fail "encode $file"; }
    "$exe" probe "$work/$file" --json >"$work/$file.json" 2>"$work/$file.err" ||
        { cat "$work/$file.err"; fail "probe --json $file"; }
    md=$(tr -d ' \n' <"$work/$file.json" | sed -n 's/.*"depth_metadata":{\([^}]*\)}.*/\1/p')
    [ -n "$md" ] || { cat "$work/$file.json"; fail "$file: no depth_metadata object"; }
    # Against what encode was told.
    same "$(key near_m "$md")" "$near" || fail "$file: near_m $(key near_m "$md"), encoded with --near $near ($md)"
    same "$(key far_m "$md")" "$far" || fail "$file: far_m $(key far_m "$md"), encoded with --far $far ($md)"
    [ "$(key mapping "$md")" = "$mapping" ] || fail "$file: mapping $(key mapping "$md"), encoded $mapping ($md)"
    [ "$(key bits "$md")" = "$bits" ] || fail "$file: bits $(key bits "$md"), encoded $bits ($md)"
    # Against ffprobe's reading of the tags.
    same "$(key near_m "$md")" "$(tag depth_near "$work/$file")" || fail "$file: near_m against the depth_near tag"
    same "$(key far_m "$md")" "$(tag depth_far "$work/$file")" || fail "$file: far_m against the depth_far tag"
    [ "$(key mapping "$md")" = "$(tag depth_mapping "$work/$file")" ] || fail "$file: mapping against its tag"
    [ "$(key bits "$md")" = "$(tag depth_bits "$work/$file")" ] || fail "$file: bits against its tag"
    occupancy=$(tag depth_occupancy "$work/$file")
    [ "$(key occupancy "$md")" = "${occupancy:-0}" ] ||
        fail "$file: occupancy $(key occupancy "$md"), the depth_occupancy tag says '${occupancy}'"
    # The text report says the same.
    "$exe" probe "$work/$file" >"$work/$file.txt" 2>&1 || fail "probe $file"
    grep -q "^depth metadata: near $near m, far $far m, mapping $mapping, $bits bits" "$work/$file.txt" ||
        { cat "$work/$file.txt"; fail "$file: the text report's depth metadata line"; }
    echo "$file: $md"
}
check a.mp4 0.8 3 inverse_z 10
check b.mkv 0.6 2.5 linear 16 --fill-holes
# 8-bit nearness without planes: its tags say "unknown", and so must the report (null in the JSON,
# "unknown" in the text), not a plane at 0 m.
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=0.4 -vf format=gray -c:v ffv1 "$work/n.mkv" ||
    fail "ffmpeg nearness"
"$exe" encode --color "$work/c-%03d.png" --depth "$work/n.mkv" -o "$work/c.mkv" --preset ultrafast \
    >"$work/c.enc" 2>&1 || { cat "$work/c.enc"; fail "encode c.mkv"; }
[ "$(tag depth_near "$work/c.mkv")" = unknown ] || fail "c.mkv: depth_near tag '$(tag depth_near "$work/c.mkv")'"
"$exe" probe "$work/c.mkv" --json | tr -d ' \n' | grep -q '"far_m":null' &&
    "$exe" probe "$work/c.mkv" --json | tr -d ' \n' | grep -q '"near_m":null' &&
    "$exe" probe "$work/c.mkv" | grep -q "^depth metadata: near unknown, far unknown, mapping" ||
    { "$exe" probe "$work/c.mkv"; fail "c.mkv: unknown planes reported as distances"; }
echo PASS
