#!/bin/sh
# End-to-end: the VALUE of every key of `play --stats FILE` (docs/architecture.md §4), each against
# what the test asked for, on the mock source and decoder (deterministic clips: mock://clip?frames,
# fps, width, height, color; drivers/mock mock_media_source.h). Four short plays, one cause each:
#  1. clean clip, sim hand pressing with force=3 on a device limited to max_force=1.5, --rate 500,
#     --force-log: frames received = the clip's, presented + dropped = received, decoded = 2 per
#     pair, sizes, fps, output 2 x depth width (sbs), haptic_rate_hz = 500 and the updates it
#     implies, device_max_force_n = 1.5 and max_force_n clamped to it; the haptic counters against
#     the force log (rows = rendered updates, contact and released columns, max |F|, last play_t =
#     haptic_run_s).
#  2. headless display, --haptic none, --size 200x100, --snapshot-dir, --snapshot-every 10:
#     output_size and each PNG's size = 200x100, snapshots_written = the PNGs in the folder = the
#     count the options imply, no haptic keys, the no-haptics note, nothing published to haptics.
#  3. --loop --duration 1.6 on a 0.5 s clip: seeks = the loops the frames played imply, frames
#     left in flight at most 2, playing_s and haptic_run_s within --duration, the default 1000 Hz.
#  4. depth-only clip (color=0), --haptic mock: mode, color_size 0x0, one decoded frame per pair.
# Every run: url, display, haptic_device, final_state "stopped", mode, no errors or concealment, no
# zero-copy on the mock decoder, no material track, nothing recorded, rss_mib_after_5s = -1 (runs
# under 5 s), presented_fps = frames_presented / playing_s, the key set itself (a new key must get a
# check here). Real-time figures (tune-in, render and latency times, frames dropped or late, overruns,
# watchdog trips, memory) are checked for type and ordering only. Usage: stats_values_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_work stats-values
mock="--source mock --decoder mock --quiet"

cat >"$work/check.py" <<'EOF'
import csv, glob, json, math, os, struct, sys
run, path, url, frames, fps, w, h = sys.argv[1:8]
frames, fps, w, h = int(frames), float(fps), int(w), int(h)
opt = dict(a.split("=", 1) for a in sys.argv[8:])
d = json.load(open(path))
bad = []
def want(key, ok, expect):
    if not ok:
        bad.append("%s = %r, want %s" % (key, d.get(key), expect))
def eq(key, value):
    want(key, d.get(key) == value and type(d.get(key)) is type(value), repr(value))
def near(key, value, tol):
    want(key, isinstance(d.get(key), (int, float)) and abs(d[key] - value) <= tol, "%s +- %s" % (value, tol))
def count(key):  # a non-negative integer
    v = d.get(key)
    if not (type(v) is int and v >= 0):
        bad.append("%s = %r, want a count" % (key, v))
        return 0
    return v
haptic = opt["haptic"] != "none"
hkeys = {"haptic_updates", "haptic_run_s", "haptic_rate_hz", "rendered_updates", "contact_updates",
         "overruns", "missed_periods", "wake_latency_us", "update_time_us", "period_error_us",
         "safety_releases", "watchdog_trips", "device_losses", "reconnects", "device_connected",
         "telemetry_dropped",
         "max_force_n", "max_force_step_n", "device_max_force_n", "device_call_max_us", "force_log_lost", "haptic_thread",
         "haptic_page_faults", "haptic_locked_mib", "energy_into_hand_mj", "energy_peak_mj"}
pkeys = {"url", "mode", "depth_size", "color_size", "output_size", "fps", "display", "haptic_device",
         "frames_decoded", "frames_received", "frames_presented", "frames_dropped", "frames_late",
         "late_ms_max", "frames_concealed", "decode_errors", "zero_copy", "color_frames_dmabuf",
         "color_frames_imported", "color_frames_dmabuf_uploaded", "color_frames_hardware",
         "depth_frames_hardware", "depth_pairs_published",
         "material_frames", "material_held", "material_missing", "material_damaged", "render_ms_p50",
         "render_ms_p99", "mesh_triangles_p50", "lod_budget_blocks", "frames_lod_limited",
         "presented_fps", "playing_s", "tune_in_s", "seeks", "snapshots_written", "frames_recorded",
         "frames_prepared_ahead", "rss_mib_start", "rss_mib_after_5s", "rss_mib_end", "locked_mib",
         "notes", "final_state", "audio", "audio_device", "audio_underruns", "audio_delay_ms",
         "av_offset_ms_p50", "av_offset_ms_p99", "remote_connected"}
keys = pkeys | (hkeys if haptic else set())
if set(d) != keys:
    bad.append("keys: unexpected %s, missing %s" % (sorted(set(d) - keys), sorted(keys - set(d))))
# What the run asked for.
eq("url", url); eq("display", opt["display"]); eq("haptic_device", opt["haptic"])
eq("final_state", "stopped"); eq("mode", opt.get("mode", "color+depth"))
eq("depth_size", [w, h]); eq("color_size", [0, 0] if opt.get("mode") == "depth-only" else [w, h])
eq("output_size", [int(v) for v in opt["size"].split("x")] if "size" in opt else [2 * w, h])
near("fps", fps, 1e-3)
eq("notes", json.loads(opt.get("notes", "[]")))
# Frames: every frame of a clean clip received, each presented or dropped, none damaged.
rec, pre, drop = count("frames_received"), count("frames_presented"), count("frames_dropped")
want("frames_presented", pre > 0, "> 0")
streams = 1 if opt.get("mode") == "depth-only" else 2
if "loop" in opt:  # up to 2 frames taken but not yet shown when --duration stopped it
    want("frames_received", pre + drop <= rec <= pre + drop + 2, "presented + dropped .. + 2")
    want("frames_decoded", count("frames_decoded") >= streams * rec, ">= %d x received" % streams)
    # The player seeks to the start after the last frame of each pass has been shown.
    lo, hi = math.ceil((pre + drop) / frames) - 1, math.ceil(rec / frames)
    want("seeks", lo <= count("seeks") <= hi, "%d..%d (loops of %d frames)" % (lo, hi, frames))
else:
    eq("frames_received", frames); want("frames_dropped", pre + drop == frames, "frames - presented")
    eq("frames_decoded", streams * frames); eq("seeks", 0)
# The mock decoder is software: no frame of it counts as a hardware decoder's.
for k in ("frames_concealed", "decode_errors", "color_frames_dmabuf", "color_frames_imported",
          "color_frames_dmabuf_uploaded", "color_frames_hardware", "depth_frames_hardware",
          "material_frames", "material_held", "material_missing", "material_damaged",
          "frames_recorded"):
    eq(k, 0)
eq("zero_copy", False)
# The mock clips have no sound: the default output (alsa, else null) is chosen, nothing played.
want("audio_device", d.get("audio_device") in ("alsa", "null"), "alsa or null")
eq("audio", ""); eq("audio_underruns", 0)
for k in ("audio_delay_ms", "av_offset_ms_p50", "av_offset_ms_p99"):
    eq(k, 0.0)
eq("depth_pairs_published", pre if haptic else 0)
want("frames_late", count("frames_late") <= pre, "<= presented")
want("frames_prepared_ahead", count("frames_prepared_ahead") <= pre, "<= presented")
want("frames_lod_limited", count("frames_lod_limited") <= pre, "<= presented")
count("lod_budget_blocks")
gl = opt["display"] != "mock"  # the mock display draws nothing: no mesh, no level of detail
want("mesh_triangles_p50", (d.get("mesh_triangles_p50", 0) > 0) == gl, "> 0 only when drawn")
want("lod_budget_blocks", (d.get("lod_budget_blocks", 0) > 0) == gl, "> 0 only when drawn")
every = int(opt.get("snapshot_every", 0))
if every:
    pngs = sorted(glob.glob(os.path.join(opt["snapshot_dir"], "*.png")))
    # A PNG every N presented frames from the first (docs/playing.md): frame-000000,
    # frame-0000N, ... (the first frame was left out while the snapshotter was made after it)
    n = math.ceil(pre / every)
    eq("snapshots_written", n)
    want("snapshots_written", len(pngs) == n, "%d PNG files, found %d" % (n, len(pngs)))
    names = ["frame-%06d.png" % (i * every) for i in range(n)]
    want("snapshots_written", [os.path.basename(p) for p in pngs] == names, "files %s" % names)
    for p in pngs:
        head = open(p, "rb").read(24)
        if head[:8] != b"\x89PNG\r\n\x1a\n" or list(struct.unpack(">II", head[16:24])) != d["output_size"]:
            bad.append("%s: not a PNG of output_size %s" % (p, d["output_size"]))
else:
    eq("snapshots_written", 0)
# Real-time figures: type and sane range only.
limit = float(opt.get("duration", frames / fps)) + 1.0
want("playing_s", 0 < d.get("playing_s", 0) <= limit, "in (0, %g]" % limit)
want("presented_fps", abs(d.get("presented_fps", 0) * d.get("playing_s", 0) - pre) < 1e-6 * pre,
     "frames_presented / playing_s")
want("render_ms_p99", 0 <= d.get("render_ms_p50", -1) <= d.get("render_ms_p99", -1), ">= render_ms_p50 >= 0")
want("late_ms_max", d.get("late_ms_max", -1) >= 0, ">= 0")
# tune-in: from the open to the first frame on screen (exact on simulated time in PlaybackSimTest)
want("tune_in_s", 0 < d.get("tune_in_s", 0) <= limit, "in (0, %g]" % limit)
want("rss_mib_start", d.get("rss_mib_start", 0) > 0, "> 0"); want("rss_mib_end", d.get("rss_mib_end", 0) > 0, "> 0")
eq("rss_mib_after_5s", -1.0)
want("locked_mib", d.get("locked_mib", -1) >= 0, ">= 0")
if haptic:
    rate = float(opt.get("rate", 1000))
    eq("haptic_rate_hz", rate)
    run_s, ups, missed = d.get("haptic_run_s", 0), count("haptic_updates"), count("missed_periods")
    want("haptic_run_s", 0 < run_s <= limit, "in (0, %g]" % limit)
    # updates ~ run_s * rate + 1 when no period was missed; the missed ones otherwise.
    want("haptic_updates", 0.5 * run_s * rate <= ups + missed <= run_s * rate + 10,
         "+ missed_periods ~ haptic_run_s x %g" % rate)
    rendered, contact = count("rendered_updates"), count("contact_updates")
    want("rendered_updates", contact <= rendered <= ups, "contact <= rendered <= haptic_updates")
    want("overruns", count("overruns") <= ups, "<= haptic_updates")
    want("safety_releases", count("safety_releases") >= count("watchdog_trips"), ">= watchdog_trips")
    # Under 2 s at <= 1 kHz fills no 8192-sample telemetry ring, however late the drain.
    for k in ("device_losses", "reconnects", "telemetry_dropped"):
        eq(k, 0)
    eq("force_log_lost", False)
    want("remote_connected", d.get("remote_connected", 0) is None or isinstance(d["remote_connected"], bool),
         "null (no remote) or a bool")
    eq("device_connected", True)  # the simulated hand is there from the start to the end
    eq("device_max_force_n", float(opt.get("max_force", 8.5)))
    want("max_force_n", 0 <= d.get("max_force_n", -1) <= d.get("device_max_force_n", 0) + 1e-9, "<= device_max_force_n")
    if "clamped" in opt:  # the hand pushes harder than the device may: the clamp is reached
        near("max_force_n", float(opt["max_force"]), 1e-3)
    want("device_call_max_us", d.get("device_call_max_us", 0) > 0, "> 0")
    for k in ("wake_latency_us", "update_time_us", "period_error_us"):
        s = d.get(k, {})
        v = [s.get(q, -1) for q in ("p50", "p90", "p99", "p999", "max")]
        want(k, 0 <= v[0] <= v[1] <= v[2] <= v[3] <= v[4] and 0 <= s.get("mean", -1) <= v[4], "p50 <= .. <= max")
    want("haptic_thread", str(d.get("haptic_thread")).startswith("dt-haptic: "), "'dt-haptic: ...'")
    pf = d.get("haptic_page_faults", {})
    want("haptic_page_faults", sorted(pf) == ["major", "minor", "warmup"] and all(type(v) is int and v >= 0 for v in pf.values()), "3 counts")
    want("haptic_locked_mib", d.get("haptic_locked_mib", -1) >= 0, ">= 0")
    energy = d.get("energy_into_hand_mj", float("nan"))
    want("energy_peak_mj", d.get("energy_peak_mj", -1) >= max(0.0, energy), ">= max(0, energy_into_hand_mj)")
    if "log" in opt:  # the force log: one row per rendered update (none dropped)
        rows = list(csv.DictReader(open(opt["log"])))
        want("rendered_updates", rendered == len(rows), "%d force log rows" % len(rows))
        want("contact_updates", contact == sum(int(r["contact"]) for r in rows), "the log's contact rows")
        rel = sum(int(r["released"]) for r in rows)
        want("safety_releases", d.get("safety_releases") == rel + d.get("watchdog_trips", 0), "%d released rows + watchdog_trips" % rel)
        fmax = max([math.sqrt(sum(float(r[c]) ** 2 for c in ("fx", "fy", "fz"))) for r in rows] or [0])
        near("max_force_n", fmax, 1e-4)
        # The largest step between consecutive rows (one per command; the first from zero).
        fs = [[float(r[c]) for c in ("fx", "fy", "fz")] for r in rows]
        smax = max([math.dist(a, b) for a, b in zip([[0.0, 0.0, 0.0]] + fs, fs)] or [0])
        near("max_force_step_n", smax, 1e-4)
        near("haptic_run_s", float(rows[-1]["play_t"]) if rows else 0, 1e-5)
        # The passivity observer (haptics/passivity.h) over the log: the work of each row's force
        # over the HIP's move to the next row (the mapping's scale is 1: device and scene moves
        # are the same), mJ.
        e = 0.0
        for a, b in zip(rows, rows[1:]):
            e += sum(float(a[f]) * (float(b[h]) - float(a[h])) for f, h in (("fx", "hip_x"), ("fy", "hip_y"), ("fz", "hip_z")))
        near("energy_into_hand_mj", 1e3 * e, 1e-3 + 1e-3 * abs(1e3 * e))
for b in bad:
    print("FAIL: %s: %s" % (run, b))
if bad:
    sys.exit(1)
print("%s: %d keys checked (%d received, %d presented, %d dropped%s)" % (run, len(d), rec, pre, drop,
      ", %d haptic updates" % d["haptic_updates"] if haptic else ""))
EOF

# play NAME URL OPTIONS...: plays into NAME.json, exit 0 or fail.
play() {
    name=$1 url=$2
    shift 2
    "$exe" play "$url" $mock --stats "$work/$name.json" "$@" >"$work/$name.out" 2>&1 ||
        { cat "$work/$name.out"; fail "$name: play exited $?"; }
}
check() { python3 "$work/check.py" "$@" || { cat "$work/$1.json"; exit 1; }; }

u1="mock://clip?frames=30&fps=30&width=64&height=48"
play clean "$u1" --display mock --haptic sim --haptic-options intent=press,force=3,max_force=1.5 --rate 500 \
    --force-log "$work/force.csv"
check clean "$work/clean.json" "$u1" 30 30 64 48 display=mock haptic=sim rate=500 max_force=1.5 clamped=1 \
    log="$work/force.csv"

u2="mock://clip?frames=25&fps=25&width=80&height=60"
play snaps "$u2" --display headless --haptic none --size 200x100 --snapshot-dir "$work/snaps" --snapshot-every 10
check snaps "$work/snaps.json" "$u2" 25 25 80 60 display=headless haptic=none size=200x100 \
    snapshot_dir="$work/snaps" snapshot_every=10 notes='["no haptic device: playing without haptics"]'

u3="mock://clip?frames=10&fps=20&width=32&height=24"
play loop "$u3" --display mock --haptic sim --loop --duration 1.6
check loop "$work/loop.json" "$u3" 10 20 32 24 display=mock haptic=sim loop=1 duration=1.6

u4="mock://clip?frames=12&fps=24&width=40&height=30&color=0"
play depth "$u4" --display mock --haptic mock
check depth "$work/depth.json" "$u4" 12 24 40 30 display=mock haptic=mock mode=depth-only \
    notes='["no color stream: depth only"]'
echo PASS
