#!/bin/sh
# A real mpv IPC client's messages against `play --idle` (issue 61, item 6: "mpv IPC clients fail
# on their first command"). The player starts with no file, as `mpv --idle` does for a UI, and the
# JSON lines below are the ones node-mpv 2.x sends, replayed in its order; they come from
# j-holub/Node-MPV (npm's node-mpv):
#   lib/ipcInterface/ipcInterface.js  send(): {"command": [...], "request_id": N}, N from 0
#   lib/mpv/_startStop.js   start(): a second connection waits for the "idle" event, then
#                           observe_property of time-pos and of the properties util.js lists
#                           (observedProperties(): mute ... loop, and, for video (node-mpv's
#                           default), fullscreen and sub-visibility, which this player does not
#                           have: as mpv, observed all the same, sent once without data)
#   lib/mpv/mpv.js          load(): ["loadfile", file, mode], its end told by start-file then
#                           file-loaded (lib/mpv/_playlist.js waits for them on another connection)
#   lib/mpv/_information.js getTimeRemaining(): get_property time-remaining
#   lib/mpv/_controls.js    pause()/resume(): set_property pause true/false; seek(): ["seek", s,
#                           mode, "exact"], done at "seek" then "playback-restart"
#   lib/mpv/_playlist.js    append(): loadfile FILE append; next(): get_property playlist-pos-1
#                           and playlist-count, then ["playlist-next", "weak"], done at
#                           start-file then playback-restart; getPlaylistSize(): playlist-count
#   lib/mpv/_controls.js    play() on an idle player: get_property idle-active, playlist-count
# Only the messages are taken, not the code. Then, as mpv: at the end of the last file end-file
# (reason eof) then idle; quit ends the player with exit 0.
# Usage: mpv_client_e2e.sh /path/to/depthtouch
set -u
exe="$1"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../../e2e_lib.sh"
e2e_start mpv-client python3
mkdir -p "$work/etc" "$work/xdg"
export DT_SYSTEM_CONFIG_DIR="$work/etc" XDG_CONFIG_HOME="$work/xdg"
unset DT_LOG JOURNAL_STREAM
sock="$work/mpv.sock"

# Without --idle a missing file is still the one-line error (exit 2).
"$exe" play --no-config --haptic none --remote none --no-audio >/dev/null 2>"$work/nourl.err"
rc=$?
[ "$rc" -eq 2 ] && grep -q "url is required" "$work/nourl.err" ||
    fail "play without a file and without --idle: exit $rc, '$(cat "$work/nourl.err")'"

"$exe" play --idle --source mock --decoder mock --display headless --haptic none --remote none \
    --no-audio --no-config --control "$sock" >/dev/null 2>"$work/play.err" </dev/null &
e2e_bg=$!
i=0
until [ -S "$sock" ]; do
    i=$((i + 1))
    if [ "$i" -ge 100 ] || ! kill -0 "$e2e_bg" 2>/dev/null; then
        grep -q "display" "$work/play.err" && { echo "no headless display: skipped"; exit 77; }
        fail "play --idle did not start: '$(cat "$work/play.err")'"
    fi
    sleep 0.1
done

python3 - "$sock" <<'EOF' || fail "the node-mpv sequence failed (player: '$(cat "$work/play.err")')"
import json, socket, sys, time

path = sys.argv[1]
# A plays 60 s, longer than the test waits on a busy machine: it is still playing at the seek
# (a 4 s A had ended there under load); playlist-next leaves it early.
A = "mock://clip?frames=600&fps=10&width=64&height=48"  # 60 s
B = "mock://clip?frames=10&fps=10&width=64&height=48"  # 1 s


class Conn:
    def __init__(self):
        self.s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.s.connect(path)
        self.buf = b""
        self.seen = []  # every message, in order

    def send(self, msg):
        self.s.sendall((json.dumps(msg) + "\n").encode())

    def next(self, deadline):
        while b"\n" not in self.buf:
            left = deadline - time.time()
            if left <= 0:
                return None
            self.s.settimeout(left)
            try:
                data = self.s.recv(65536)
            except socket.timeout:
                return None
            if not data:
                return None
            self.buf += data
        line, self.buf = self.buf.split(b"\n", 1)
        msg = json.loads(line)
        self.seen.append(msg)
        return msg

    def wait(self, what, pred, timeout=10.0):
        deadline = time.time() + timeout
        while True:
            msg = self.next(deadline)
            if msg is None:
                sys.exit("no %s in %d s; seen: %s" % (what, timeout, self.seen[-24:]))
            if pred(msg):
                return msg

    def events(self, *names, timeout=10.0):
        for name in names:
            self.wait("event " + name, lambda m: m.get("event") == name, timeout)


rid = [0]


def request(conn, *command):
    """node-mpv's send(): the command with the next request_id; returns the reply."""
    n = rid[0]
    rid[0] += 1
    conn.send({"command": list(command), "request_id": n})
    reply = conn.wait("reply %d" % n, lambda m: m.get("request_id") == n and "event" not in m)
    if reply.get("error") != "success":
        sys.exit("%s -> %s" % (command, reply))
    return reply.get("data")


def watcher():
    """node-mpv's second socket, which it opens to wait for a command's events. Its first request
    is answered only once the player has it as a client: a connect() the player has not yet
    accepted when the command goes on the other socket misses that command's events (in mpv too,
    whose IPC accepts in its own thread), and on a busy machine the seek's did here."""
    conn = Conn()
    request(conn, "client_name")
    return conn


# start(): the player is up when a client sees "idle".
probe = Conn()
probe.events("idle", timeout=5)
probe.s.close()
main = Conn()
request(main, "observe_property", 0, "time-pos")
for i, name in enumerate(["mute", "pause", "duration", "volume", "filename", "path",
                          "media-title", "playlist-pos", "playlist-count", "loop",
                          "fullscreen", "sub-visibility"], 1):
    request(main, "observe_property", i, name)

# load(A, "replace")
watch = watcher()
request(main, "loadfile", A, "replace")
watch.events("start-file", "file-loaded")
watch.s.close()
remaining = request(main, "get_property", "time-remaining")
if not isinstance(remaining, (int, float)) or not 0 < remaining <= 60.5:
    sys.exit("time-remaining %r" % remaining)

request(main, "set_property", "pause", True)
if request(main, "get_property", "pause") is not True:
    sys.exit("not paused")
request(main, "set_property", "pause", False)

watch = watcher()
request(main, "seek", 1, "absolute", "exact")
watch.events("seek", "playback-restart")
watch.s.close()

request(main, "loadfile", B, "append")
if request(main, "get_property", "playlist-count") != 2:
    sys.exit("playlist-count is not 2")
if request(main, "get_property", "playlist-pos-1") != 1:
    sys.exit("playlist-pos-1 is not 1")
watch = watcher()
request(main, "playlist-next", "weak")
start = watch.wait("start-file", lambda m: m.get("event") == "start-file")
watch.events("playback-restart")
watch.s.close()
if start.get("playlist_entry_id") != 2:
    sys.exit("start-file of entry %r" % start.get("playlist_entry_id"))

# B ends: end-file with reason eof, then idle (mpv --idle).
end = main.wait("end-file eof", lambda m: m.get("event") == "end-file" and m.get("reason") == "eof")
main.events("idle")
if end.get("playlist_entry_id") != 2:
    sys.exit("end-file of entry %r" % end.get("playlist_entry_id"))
if request(main, "get_property", "idle-active") is not True:
    sys.exit("not idle-active after the last file")
if request(main, "get_property", "playlist-count") != 2:
    sys.exit("the playlist was not kept")

# The observed properties came as property-change events (ints for the playlist's).
changes = {m["name"]: m.get("data") for m in main.seen if m.get("event") == "property-change"}
for name in ["pause", "duration", "filename", "playlist-pos", "playlist-count", "loop"]:
    if name not in changes:
        sys.exit("no property-change of %s: %s" % (name, sorted(changes)))
for name in ["fullscreen", "sub-visibility"]:
    said = [m for m in main.seen if m.get("event") == "property-change" and m["name"] == name]
    if len(said) != 1 or "data" in said[0]:
        sys.exit("%s: %r, not one property-change without data" % (name, said))
if not any(m.get("event") == "end-file" and m.get("reason") == "stop" for m in main.seen):
    sys.exit("playlist-next did not end the first file with reason stop")

main.send({"command": ["quit"], "request_id": rid[0]})
main.events("shutdown")
print("node-mpv's sequence answered as mpv")
EOF
wait "$e2e_bg"
rc=$?
e2e_bg=""
[ "$rc" -eq 0 ] || fail "play --idle quit with exit $rc: '$(cat "$work/play.err")'"
echo "OK: play --idle served node-mpv's messages and quit with exit 0"
