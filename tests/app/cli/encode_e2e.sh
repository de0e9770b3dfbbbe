#!/bin/sh
# End-to-end: `depthtouch encode` through the executable. Inputs are made with the ffmpeg CLI, the
# output is checked with ffprobe (exit 77, skipped, without them): a color PNG sequence + a 16-bit
# metric depth PNG sequence with a hole → MKV with two titled streams and the depth tags; lossless
# depth; MP4 by extension; each bad input (one error line, exit 2, no output or temporary file);
# SIGINT during an endless encode (exit 130, complete playable file).
# Usage: encode_e2e.sh /path/to/depthtouch
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start encode-e2e ffmpeg ffprobe

e2e_color_pngs 64x48 0.4
e2e_metric_depth_pngs 0.4

# 1. Success: MKV with both streams, titles, tags; quiet on a non-terminal stderr.
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/out.mkv" \
    --preset ultrafast >"$work/ok.out" 2>"$work/ok.err" || { cat "$work/ok.err"; fail "encode exited $?"; }
[ -s "$work/ok.err" ] && { cat "$work/ok.err"; fail "stderr not quiet when not a terminal"; }
grep -q "encoded 12 frame pairs 64x48" "$work/ok.out" || { cat "$work/ok.out"; fail "summary line"; }
[ "$(probe -show_entries stream=index -of csv=p=0 "$work/out.mkv" | wc -l)" -eq 2 ] || fail "want two streams"
[ "$(probe -show_entries stream_tags=title -of csv=p=0 "$work/out.mkv" | tr '\n' ' ')" = "color depth " ] \
    || fail "stream titles"
tags=$(probe -show_entries format_tags -of flat "$work/out.mkv")
for t in DEPTH_NEAR DEPTH_FAR DEPTH_MAPPING DEPTH_BITS; do
    echo "$tags" | grep -qi "$t" || fail "container tag $t missing: $tags"
done
counts=$(probe -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$work/out.mkv" | tr '\n' ' ')
[ "$counts" = "12 12 " ] || fail "frame counts: $counts"
[ -z "$(ls "$work" | grep '\.tmp\.')" ] || fail "temporary file left"
echo "mkv: $(probe -show_entries stream=codec_name,profile -of csv=p=0 "$work/out.mkv" | tr '\n' ' ')"

# 1b. A depth scale that puts the scene beyond any depth camera's range (as the default 1 mm does
# on TUM RGB-D's 0.2 mm units): encoded, with one warning naming --depth-scale.
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/far.mkv" \
    --preset ultrafast --depth-scale 0.02 >"$work/far.out" 2>"$work/far.err" || fail "far encode exited $?"
[ "$(wc -l <"$work/far.err")" -eq 1 ] && grep -q "warning: the depth reaches .* check --depth-scale" "$work/far.err" \
    || { cat "$work/far.err"; fail "far: want one warning naming --depth-scale"; }

# 1c. One still pair: one frame at --fps (30 by default), not the image demuxer's 25.
"$exe" encode --color "$work/c-000.png" --depth "$work/d-000.png" -o "$work/still.mkv" \
    --preset ultrafast >/dev/null 2>&1 || fail "still encode"
[ "$(probe -show_entries stream=r_frame_rate -of csv=p=0 "$work/still.mkv" | tr '\n' ' ')" = "30/1 30/1 " ] \
    || fail "still: rates $(probe -show_entries stream=r_frame_rate -of csv=p=0 "$work/still.mkv" | tr '\n' ' ')"

# 2. Lossless depth: x264 picks High 4:4:4 Predictive. MP4 by extension.
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/lossless.mp4" \
    --preset ultrafast --depth-lossless >/dev/null 2>&1 || fail "lossless mp4"
probe -show_entries format=format_name -of csv=p=0 "$work/lossless.mp4" | grep -q mp4 || fail "not mp4"
probe -select_streams v:1 -show_entries stream=profile -of csv=p=0 "$work/lossless.mp4" \
    | grep -q "High 4:4:4 Predictive" || fail "lossless profile"

# 2b. The roles and depth metadata come back from every container: MKV titles and tags, MP4 handler
# names and tags, DepthTouch's MPEG-TS timed metadata (MPEG-TS carries no titles or free tags).
for ext in mkv mp4 ts; do
    "$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" -o "$work/roles.$ext" \
        --preset ultrafast >/dev/null 2>&1 || fail "roles.$ext encode"
    "$exe" probe "$work/roles.$ext" >"$work/roles.$ext.txt" 2>&1 || { cat "$work/roles.$ext.txt"; fail "probe roles.$ext"; }
    case $ext in mkv) from="title" ;; mp4) from="MP4 handler name" ;; ts) from="MPEG-TS timed metadata" ;; esac
    grep -q "color ($from)" "$work/roles.$ext.txt" && grep -q "depth ($from)" "$work/roles.$ext.txt" \
        && grep -q "^depth metadata: near " "$work/roles.$ext.txt" \
        || { cat "$work/roles.$ext.txt"; fail "roles.$ext: roles from $from and the depth metadata"; }
done
# MPEG-TS: the service keeps a plain name (a TV shows it as the channel's), the tags ride in a timed
# ID3 stream (stream type 0x15), read here by ffprobe and ffmpeg, not by DepthTouch.
[ "$(probe -show_entries program_tags=service_name -of default=nw=1:nk=1 "$work/roles.ts" | head -1)" = "DepthTouch" ] ||
    fail "ts: the service name is not plain"
[ "$(probe -show_entries stream=codec_name -of csv=p=0 "$work/roles.ts" | sed -n 3p)" = "timed_id3" ] ||
    fail "ts: no timed ID3 stream"
ff -i "$work/roles.ts" -map 0:2 -c copy -f data "$work/roles.id3" || fail "ffmpeg: the ID3 stream"
grep -q "depth_near" "$work/roles.id3" && grep -q "depth_mapping" "$work/roles.id3" ||
    fail "ts: the ID3 tag lacks the depth tags"
# Joined mid-stream (the file cut at a third, on a TS packet boundary, a 15-frame GOP): the tags come
# with the next key frame, and no packet read ahead for them is lost (probe's frame count = ffprobe's).
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=2 -start_number 0 "$work/long-%03d.png" || fail "ffmpeg long"
"$exe" encode --color "$work/long-%03d.png" --depth "$work/d-%03d.png" --loop --frames 60 -o "$work/gop.ts" \
    -g 15 --preset ultrafast >/dev/null 2>&1 || fail "gop.ts encode"
size=$(wc -c <"$work/gop.ts")
dd if="$work/gop.ts" of="$work/mid.ts" bs=188 skip=$((size / 188 / 3)) 2>/dev/null
"$exe" probe "$work/mid.ts" >"$work/mid.txt" 2>&1 || { cat "$work/mid.txt"; fail "probe mid.ts"; }
want=$(probe -count_packets -select_streams v:0 -show_entries stream=nb_read_packets -of csv=p=0 "$work/mid.ts")
grep -q "color (MPEG-TS timed metadata)" "$work/mid.txt" && grep -q "^depth metadata: near " "$work/mid.txt" &&
    grep -q "yuv420p  30 fps, $want frames" "$work/mid.txt" ||
    { cat "$work/mid.txt"; fail "mid.ts: the tags, and $want color frames"; }
echo "roles: $(grep -h 'color (' "$work"/roles.*.txt | awk '{print $3, $4, $5, $6}' | tr '\n' ';')"

# 2c. MPEG-TS interleaving: a clip shorter than x264's lookahead at the default preset (every packet
# comes out when the encoders are flushed, color's first) and x265 depth beside x264 color (x265
# holds its frames longer) must still come back paired frame for frame: before, the last frames of
# every TS lost their partners and HEVC depth ran 0.3 s ahead of its color (8 of 150 decoded).
ff -f lavfi -i testsrc=size=64x48:rate=30:duration=1 "$work/c1.mkv" || fail "ffmpeg 1 s color"
ff -f lavfi -i "testsrc=size=64x48:rate=30:duration=1,format=gray" "$work/d1.mkv" || fail "ffmpeg 1 s depth"
for codec in h264 hevc; do
    "$exe" encode --color "$work/c1.mkv" --depth "$work/d1.mkv" -o "$work/tail-$codec.ts" \
        --depth-codec "$codec" >/dev/null 2>"$work/tail.err" || { cat "$work/tail.err"; fail "TS $codec"; }
    line=$("$exe" probe "$work/tail-$codec.ts" --decode 2>&1 | grep '^decode')
    case "$line" in
    *"30 color + 30 depth frames -> 30 paired"*"0 without depth, 0 reused depth"*) echo "ts $codec: $line" ;;
    *) fail "TS with $codec depth: $line" ;;
    esac
done

# 3. Bad input: one error line, exit 2, no output file, no temporary file.
echo "not a video" >"$work/junk.mkv"
ff -f lavfi -i sine=duration=0.2 "$work/audio.wav" || fail "ffmpeg wav"
bad() { # name, args...
    name="$1"; shift
    rm -f "$work/bad.mkv"
    "$exe" encode "$@" >/dev/null 2>"$work/bad.err"
    rc=$?
    [ "$rc" -eq 2 ] || { cat "$work/bad.err"; fail "$name: exit $rc, want 2"; }
    [ "$(wc -l <"$work/bad.err")" -eq 1 ] || { cat "$work/bad.err"; fail "$name: want one error line"; }
    [ ! -e "$work/bad.mkv" ] || fail "$name: left an output file"
    [ -z "$(ls "$work" | grep '\.tmp\.')" ] || fail "$name: left a temporary file"
    echo "$name: $(cat "$work/bad.err")"
}
D="$work/d-%03d.png"
bad "missing source" --color "$work/none-%03d.png" --depth "$D" -o "$work/bad.mkv"
bad "missing file" --color "$work/none.mkv" --depth "$D" -o "$work/bad.mkv"
bad "not media" --color "$work/junk.mkv" --depth "$D" -o "$work/bad.mkv"
bad "no video stream" --color "$work/audio.wav" --depth "$D" -o "$work/bad.mkv"
bad "negative crf" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mkv" --crf -1
bad "near >= far" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mkv" --near 2 --far 1
bad "unwritable output" --color "$work/c-%03d.png" --depth "$D" -o "$work/no/such/dir/bad.mkv"
bad "bad preset" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mkv" --preset turbo
bad "ffv1 in mp4" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mp4" --depth-bits 16
bad "8-bit hevc" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mkv" --depth-codec hevc --depth-bits 8
bad "unknown depth codec" --color "$work/c-%03d.png" --depth "$D" -o "$work/bad.mkv" --depth-codec vp9
bad "no camera" --color v4l2:/dev/video99 --depth "$D" -o "$work/bad.mkv"
# A missing required option is CLI11's parse error (its message plus a --help hint), exit 2.
"$exe" encode --color "$work/c-%03d.png" -o "$work/bad.mkv" >/dev/null 2>&1
[ $? -eq 2 ] && [ ! -e "$work/bad.mkv" ] || fail "missing --depth: want exit 2 and no file"

# 4. SIGINT during an endless encode: the file is complete and playable.
"$exe" encode --color "$work/c-000.png" --depth "$work/d-000.png" --loop -o "$work/int.mkv" \
    --preset ultrafast >"$work/int.out" 2>"$work/int.err" &
e2e_bg=$!
i=0
while [ $i -lt 200 ]; do  # until the encoder has opened its output (at most 20 s)
    ls "$work" | grep -q '^int\.mkv\.tmp\.' && break
    sleep 0.1; i=$((i + 1))
done
sleep 1  # let it encode a while
kill -INT "$e2e_bg"
wait "$e2e_bg"
rc=$?
e2e_bg=""
[ "$rc" -eq 130 ] || { cat "$work/int.err"; fail "interrupted encode: exit $rc, want 130"; }
[ -s "$work/int.mkv" ] || fail "interrupted encode left no file"
counts=$(probe -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$work/int.mkv" | tr '\n' ' ')
set -- $counts
[ "$#" -eq 2 ] && [ "$1" -gt 0 ] && [ "$1" -eq "$2" ] || fail "interrupted file frame counts: $counts"
errs=$(ffmpeg -nostdin -v error -i "$work/int.mkv" -f null - 2>&1)
[ -z "$errs" ] || fail "interrupted file does not decode cleanly: $errs"
echo "interrupted: $1 frame pairs, $(tail -n 1 "$work/int.err")"
echo PASS
