#!/bin/sh
# End-to-end (issue 60, class 4): a live MPEG-TS with a private-data PID tunes in. The clip that
# `depthtouch encode` writes (color, depth, timed metadata; a key frame every 0.5 s) gets one more
# PID in its PMT, stream type 0x06 (PES private data) with no descriptor, and a private_stream_1
# PES of 100 bytes on it every 20 TS packets, as a broadcast's private PID; a sender paces the TS
# packets over UDP loopback at the file's own rate (188 x 7 bytes a datagram).
# libavformat probes the codec of such a PID and holds back every packet of the input while it
# does (until 2 500 of that PID's packets or `probesize` bytes came): the player used to see no
# picture, and after its 10 s I/O time-out said "Frame size of the stream is zero or too large"
# (exit 2). It must now ignore the data PID and play about every frame sent (the first GOP may be
# lost), exit 0. The tune-in time is printed, a figure and not a check (a busy machine is slower).
# Exit 77 (skip) without the ffmpeg CLI or python3. Usage: live_private_pid_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start live_private_pid ffmpeg python3
e2e_port

# 6 s, 180 frame pairs.
e2e_color_pngs 64x48 6
e2e_metric_depth_pngs 6
"$exe" encode --color "$work/c-%03d.png" --depth "$work/d-%03d.png" --gop 15 --preset ultrafast \
    -o "$work/clip.ts" >"$work/encode.log" 2>&1 || { cat "$work/encode.log"; fail "encode"; }

# The PMT rewritten with the private PID 0x1ff (its CRC computed again) and the PID's packets
# woven in; then the packets paced out over UDP.
cat >"$work/send.py" <<'PY'
import socket, sys, time, zlib

src, port, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
data = open(src, "rb").read()
pkts = [bytearray(data[i:i + 188]) for i in range(0, len(data) - 187, 188)]
PRIV = 0x1FF


def pid(p):
    return (p[1] & 0x1F) << 8 | p[2]


def crc32_mpeg(b):
    crc = 0xFFFFFFFF
    for byte in b:
        crc ^= byte << 24
        for _ in range(8):
            crc = (crc << 1) ^ 0x04C11DB7 if crc & 0x80000000 else crc << 1
            crc &= 0xFFFFFFFF
    return crc


pmt_pid = None
for p in pkts:
    if pid(p) == 0 and p[1] & 0x40:  # the PAT: its first program's PMT PID
        sec = p[5:]
        pmt_pid = (sec[10] & 0x1F) << 8 | sec[11]
        break
assert pmt_pid is not None, "no PAT"
for p in pkts:
    if pid(p) == pmt_pid and p[1] & 0x40:
        off = 5 + p[4]  # the pointer field
        length = (p[off + 1] & 0x0F) << 8 | p[off + 2]
        body = p[off:off + 3 + length - 4]  # without the CRC
        body += bytes([0x06, 0xE0 | PRIV >> 8, PRIV & 0xFF, 0xF0, 0x00])
        length += 5
        body[1] = (body[1] & 0xF0) | (length >> 8)
        body[2] = length & 0xFF
        section = body + crc32_mpeg(body).to_bytes(4, "big")
        p[off:] = (section + b"\xff" * 188)[:188 - off]

cc = 0


def private_packet():
    global cc
    payload = bytes(100)
    pes = b"\x00\x00\x01\xbd" + (3 + len(payload)).to_bytes(2, "big") + b"\x80\x00\x00" + payload
    head = bytes([0x47, 0x40 | PRIV >> 8, PRIV & 0xFF, 0x30 | cc])  # adaptation field, payload
    cc = (cc + 1) & 0x0F
    stuffing = 184 - len(pes) - 1
    return head + bytes([stuffing, 0x00]) + b"\xff" * (stuffing - 1) + pes


out = []
for i, p in enumerate(pkts):
    if i % 20 == 10:
        out.append(private_packet())
    out.append(bytes(p))
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
step = seconds * 7 / len(out)
start = time.monotonic()
for k in range(0, len(out), 7):
    s.sendto(b"".join(out[k:k + 7]), ("127.0.0.1", port))
    wait = start + (k // 7 + 1) * step - time.monotonic()
    if wait > 0:
        time.sleep(wait)
print("sent %d TS packets, %d of them on the private PID" % (len(out), len(out) - len(pkts)))
PY

"$exe" play "udp://127.0.0.1:$port" --display mock --haptic none --no-config --audio-device none \
    --stats "$work/play.json" >"$work/play.log" 2>&1 &
e2e_bg=$!
# The sender starts once the player listens (its port bound), not after a fixed time: a busy
# machine must not cost the clip's first pairs.
e2e_wait_udp "$port" "$e2e_bg"
python3 "$work/send.py" "$work/clip.ts" "$port" 6 >"$work/send.log" 2>&1 ||
    { cat "$work/send.log"; fail "the sender"; }
wait "$e2e_bg"
rc=$?
e2e_bg=""
[ "$rc" -eq 0 ] || { cat "$work/play.log"; fail "play exited $rc, want 0 (tuned in despite the private PID)"; }
received=$(sed -n 's/.*"frames_received": *\([0-9]*\).*/\1/p' "$work/play.json")
presented=$(sed -n 's/.*"frames_presented": *\([0-9]*\).*/\1/p' "$work/play.json")
tunein=$(sed -n 's/.*"tune_in_s": *\([0-9.]*\).*/\1/p' "$work/play.json")
[ "${received:-0}" -ge 165 ] && [ "${presented:-0}" -gt 0 ] && grep -q '"mode": *"color+depth"' "$work/play.json" ||
    { cat "$work/play.log" "$work/play.json"; fail "$received of 180 pairs received, want 165 or more with depth"; }
echo "$(cat "$work/send.log"); $received of 180 pairs received, $presented presented; tune-in $tunein s"
echo PASS
