#!/bin/sh
# End-to-end: `encode --renditions` makes an HLS ladder (three renditions, each with color, depth
# and the material track at its own size) and a multivariant playlist; `play` of that playlist
# over HTTP keeps one rendition by the source option `rendition` (highest by default, lowest, or the
# tallest at most a height) and fetches that rendition's segments alone (the others' first
# segment only, which libavformat reads to learn their sizes: counted in the server's log).
# A bad `rendition` value is bad input: exit 2, one line.
# Usage: ladder_e2e.sh DEPTHTOUCH   (exit 77 without the ffmpeg CLI or python3)
exe=$1
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start ladder ffmpeg python3

e2e_color_pngs 160x120 6
ff -f lavfi -i "gradients=size=160x120:rate=30:duration=6,format=gray" -start_number 0 "$work/d-%03d.png" ||
    fail "ffmpeg depth"
ff -f lavfi -i color=c=0x010000:size=160x120:rate=1:duration=1 -frames:v 1 "$work/m.png" || fail "ffmpeg material"
mkdir "$work/www"
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --material "$work/m.png" \
    --renditions 120,90,60 -o "$work/www/show.m3u8" --preset ultrafast >"$work/enc.out" 2>&1 ||
    { cat "$work/enc.out"; fail "encode --renditions exited $?"; }
grep -c '^#EXT-X-STREAM-INF:' "$work/www/show.m3u8" | grep -qx 3 ||
    { cat "$work/www/show.m3u8"; fail "the multivariant playlist names 3 renditions"; }
for r in 120 90 60; do
    # (ffprobe lists a stream once under its program and once alone: sort -u by its index)
    probe -show_entries stream=index,codec_name,width,height -of csv=p=0 "$work/www/show_${r}p.m3u8" |
        sort -u >"$work/s$r.csv"
    [ "$(grep -c "^[0-9]*,h264,[0-9]*,$r\$" "$work/s$r.csv")" -eq 3 ] ||
        { cat "$work/s$r.csv"; fail "rendition ${r}p carries color, depth and material at its height"; }
done
# The size the master gives the shortest rendition, by its own RESOLUTION.
lowest=$(sed -n 's/.*RESOLUTION=\([0-9]*\)x60.*/\1,60/p' "$work/www/show.m3u8")
[ "$lowest" = "80,60" ] || { cat "$work/www/show.m3u8"; fail "the 60p rendition keeps the aspect: $lowest"; }

# probe lists the renditions from the multivariant playlist, the one it reads marked, and reads the
# one the source option asks for (JSON: width, height, BANDWIDTH as the playlist gives it).
"$exe" probe "$work/www/show.m3u8" >"$work/probe0.txt" 2>&1 || { cat "$work/probe0.txt"; fail "probe exited $?"; }
grep -q '^renditions: 3 ' "$work/probe0.txt" && grep -q '^  160x120, .* (read below)$' "$work/probe0.txt" &&
    grep -q '^  #0 color .* 160x120 ' "$work/probe0.txt" ||
    { cat "$work/probe0.txt"; fail "probe lists 3 renditions and reads the tallest"; }
"$exe" probe --json --source-options rendition=lowest "$work/www/show.m3u8" >"$work/probe1.json" 2>&1 ||
    { cat "$work/probe1.json"; fail "probe --source-options rendition=lowest exited $?"; }
bw60=$(sed -n 's/^#EXT-X-STREAM-INF:BANDWIDTH=\([0-9]*\),.*RESOLUTION=80x60,.*/\1/p' "$work/www/show.m3u8")
python3 - "$work/probe1.json" "$bw60" <<'PY' || fail "probe --json: the renditions and the kept one"
import json, sys
j = json.load(open(sys.argv[1]))
r = j["renditions"]
assert [(x["width"], x["height"]) for x in r] == [(160, 120), (120, 90), (80, 60)], r
assert [x["kept"] for x in r] == [False, False, True], r
assert r[2]["bandwidth"] == int(sys.argv[2]), (r[2], sys.argv[2])
assert j["streams"][0]["width"] == 80, j["streams"][0]
PY

e2e_port
(cd "$work/www" && exec python3 -m http.server --bind 127.0.0.1 "$port") >"$work/http.log" 2>&1 &
e2e_bg=$!
e2e_wait_served "$exe" "http://127.0.0.1:$port/show.m3u8" "$work/probe.txt"
play_size() { # $1: the source option's value or "" (the default); prints the played color size
    opt=""
    [ -n "$1" ] && opt="--source-options rendition=$1"
    : >"$work/http.log"
    # shellcheck disable=SC2086 # $opt is two words or none
    "$exe" play "http://127.0.0.1:$port/show.m3u8" $opt --display mock --haptic none \
        --stats "$work/p.json" >"$work/play.out" 2>&1 || { cat "$work/play.out"; fail "play rendition=$1 exited $?"; }
    tr -d ' \n' <"$work/p.json" | sed -n 's/.*"color_size":\[\([0-9]*\),\([0-9]*\)\].*/\1x\2/p'
}
[ "$(play_size "")" = "160x120" ] || fail "the default keeps the tallest rendition"
[ "$(play_size lowest)" = "80x60" ] || fail "rendition=lowest keeps 80x60"
segs120=$(grep -c 'GET /show_120p[0-9]*\.ts' "$work/http.log")
segs60=$(grep -c 'GET /show_60p[0-9]*\.ts' "$work/http.log")
[ "$segs60" -eq 3 ] && [ "$segs120" -le 1 ] ||
    { cat "$work/http.log"; fail "rendition=lowest fetched $segs60 of its 3 segments and $segs120 of 120p's (want 3, at most 1)"; }
[ "$(play_size 100)" = "120x90" ] || fail "rendition=100 keeps the tallest at most 100 pixels: 120x90"
"$exe" play "$work/www/show.m3u8" --source-options rendition=tallest --display mock --haptic none \
    >"$work/bad.out" 2>&1
rc=$?
[ $rc -eq 2 ] && [ "$(wc -l <"$work/bad.out")" -eq 1 ] && grep -q "rendition" "$work/bad.out" ||
    { cat "$work/bad.out"; fail "rendition=tallest: exit $rc, want 2 and one line naming the option"; }
echo "ladder: 3 renditions; played 160x120 (default), 80x60 (lowest, $segs60 of its segments, $segs120 of 120p's), 120x90 (100)"
