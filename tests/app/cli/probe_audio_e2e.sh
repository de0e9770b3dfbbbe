#!/bin/sh
# End-to-end: `depthtouch probe` lists a file's audio streams, each against
# ffprobe's reading of the same file: codec, sample rate, channels, language and length (MKV: the
# stream's DURATION tag; MP4: the stream's duration), and how long each overlaps the picture
# (computed here from the lengths); a file without audio lists none. Exit 77 (skip) without the
# ffmpeg CLI tools. Usage: probe_audio_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start probe-audio ffmpeg ffprobe python3

# A 1 s DepthTouch clip (30 pairs), then the same with a 1.5 s mono 44.1 kHz AAC track tagged
# English (MKV) and with a 3 s stereo 48 kHz AAC track (MP4).
"$exe" encode --color synthetic:head,size=64x48,frames=30 --depth synthetic:head,size=64x48,frames=30 \
    -o "$work/clip.mkv" --preset ultrafast >"$work/enc" 2>&1 || { cat "$work/enc"; fail "encode"; }
ff -i "$work/clip.mkv" -f lavfi -i "sine=frequency=440:duration=1.5" -map 0 -map 1 -c copy \
    -c:a aac -metadata:s:a:0 language=eng "$work/a.mkv" || fail "ffmpeg mkv"
ff -i "$work/clip.mkv" -f lavfi -i "sine=frequency=440:sample_rate=48000:duration=3" -map 0 \
    -map 1 -c copy -c:a aac -ac 2 "$work/a.mp4" || fail "ffmpeg mp4"

cat >"$work/check.py" <<'PY'
import json, subprocess, sys
exe, path = sys.argv[1:3]
ours = json.loads(subprocess.run([exe, "probe", path, "--json"], check=True, capture_output=True,
                                 text=True).stdout)
theirs = json.loads(subprocess.run(["ffprobe", "-v", "error", "-select_streams", "a",
                                    "-show_streams", "-of", "json", path], check=True,
                                   capture_output=True, text=True).stdout)["streams"]
text = subprocess.run([exe, "probe", path], check=True, capture_output=True, text=True).stdout
audio = ours["audio"]
bad = []
if len(audio) != len(theirs):
    sys.exit("%s: %d audio streams, ffprobe %d" % (path, len(audio), len(theirs)))
picture = max(s["duration_s"] for s in ours["streams"])
def seconds(hms):  # "00:00:01.523000000"
    h, m, s = hms.split(":")
    return int(h) * 3600 + int(m) * 60 + float(s)
for a, t in zip(audio, theirs):
    tags = {k.lower(): v for k, v in t.get("tags", {}).items()}
    want = {"stream": t["index"], "codec": t["codec_name"], "sample_rate": int(t["sample_rate"]),
            "channels": t["channels"],
            "language": None if tags.get("language", "und") == "und" else tags["language"]}
    for k, v in want.items():
        if a[k] != v:
            bad.append("%s = %r, ffprobe %r" % (k, a[k], v))
    length = float(t["duration"]) if "duration" in t else seconds(tags["duration"])
    if abs(a["duration_s"] - length) > 1e-3:
        bad.append("duration_s = %r, ffprobe %r" % (a["duration_s"], length))
    overlap = max(0.0, min(picture, a["start_s"] + length) - max(0.0, a["start_s"]))
    if abs(a["overlap_s"] - overlap) > 2e-3:
        bad.append("overlap_s = %r, want %r" % (a["overlap_s"], overlap))
    line = "audio: stream #%d %s, %d Hz, %d channel" % (want["stream"], want["codec"],
                                                      want["sample_rate"], want["channels"])
    if line not in text:
        bad.append("the text report lacks '%s'" % line)
if bad:
    sys.exit("%s: %s" % (path, "; ".join(bad)))
print("%s: %s" % (path, ", ".join("%s %d Hz %d ch %.3f s, %.3f s over the picture"
      % (a["codec"], a["sample_rate"], a["channels"], a["duration_s"], a["overlap_s"]) for a in audio)
      or "no audio"))
PY
for f in a.mkv a.mp4 clip.mkv; do
    python3 "$work/check.py" "$exe" "$work/$f" || fail "$f"
done
"$exe" probe "$work/clip.mkv" | grep -q "^audio:" && fail "a file without audio lists some"
echo "probe: audio streams as ffprobe reads them"
