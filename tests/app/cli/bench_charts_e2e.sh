#!/bin/sh
# Every benchmark writes its charts: each `depthtouch bench` runs briefly into a scratch folder and
# every PNG it names must be a PNG of some size (a failed gnuplot script leaves none, or an empty
# one). Whether a chart reads well is checked by eye (docs/benchmarks.md). Exit 77 (skip) without
# gnuplot. Usage: bench_charts_e2e.sh /path/to/depthtouch [shared-data-folder]
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
data="${2:-}"
e2e_start charts-e2e gnuplot

bench() { # name, args...
    name="$1"; shift
    status=0
    "$exe" bench "$name" --out "$work/$name" "$@" >"$work/$name.log" 2>&1 || status=$?
    [ "$status" -eq 0 ] || { tail -n 20 "$work/$name.log"; fail "bench $name exited $status"; }
}
png() { # name, file
    f="$work/$1/$2"
    [ -f "$f" ] || { ls "$work/$1"; fail "bench $1 wrote no $2"; }
    magic=$(od -An -tx1 -N8 "$f" | tr -d ' \n')
    [ "$magic" = "89504e470d0a1a0a" ] || fail "bench $1: $2 is not a PNG"
    size=$(wc -c <"$f")
    [ "$size" -gt 5000 ] || fail "bench $1: $2 is $size bytes (an empty plot?)"
    echo "bench $1: $2 ($size bytes)"
}

bench rt --duration 0.2 --rates 1000 --policies fifo
png rt rt_bench.png
bench media --synthetic --frames 10 --runs 1 --sizes 160x120 --presets ultrafast --depth-crfs 30 \
    --codec-sizes 160x120 96x64 --codec-crfs 18 30 --rate-preset ultrafast
png media media_throughput.png
png media rate_vs_accuracy.png
png media depth_codecs.png
# The depth codec table: each lossy codec at both CRFs at the first size, at the CRF nearest 18
# alone at the second, FFV1 once at each: 7 + 4 rows.
codec_rows() { grep -c -E "^$1 +(h264-8|h264-10|hevc-10) +$2 " "$work/media.log"; }
[ "$(codec_rows 160x120 crf18)" -eq 3 ] && [ "$(codec_rows 160x120 crf30)" -eq 3 ] &&
    [ "$(codec_rows 96x64 crf18)" -eq 3 ] && [ "$(codec_rows 96x64 crf30)" -eq 0 ] &&
    [ "$(grep -c -E '^(160x120|96x64) +ffv1-16 +lossless ' "$work/media.log")" -eq 2 ] ||
    { cat "$work/media.log"; fail "bench media: the depth codec rows are not 7 + 4"; }
bench haptics --quick
png haptics speed_vs_accuracy.png
png haptics psd.png
# Its force-error percentiles, run spread and machine load, checked against one another (no timing
# is asserted): max >= p99 >= p95 >= p50 >= 0 and max >= RMS per row, in the CSV and the JSON
# alike; the load figures present; psd.png's script names the renderer.
python3 - "$work/haptics" "$work/haptics.log" <<'PY' || fail "bench haptics: its figures do not hold together"
import csv, json, sys
d, log = sys.argv[1], open(sys.argv[2]).read()
rows = list(csv.DictReader(open(d + "/haptics_bench.csv")))
doc = json.load(open(d + "/haptics_bench.json"))
assert rows and len(rows) == len(doc["rows"]), "CSV and JSON rows differ"
for r, j in zip(rows, doc["rows"]):
    e = [float(r["force_error_" + k]) for k in ("p50_n", "p95_n", "p99_n", "max_n")]
    rms = float(r["force_rms_error_n"])
    name = "%s %sx%s %s" % (r["method"], r["width"], r["height"], r["motion"])
    assert 0 <= e[0] <= e[1] <= e[2] <= e[3], "%s: error percentiles %s" % (name, e)
    assert e[3] >= rms - 1e-6, "%s: max %g < RMS %g" % (name, e[3], rms)
    for k in ("force_error_p50_n", "force_error_p95_n", "force_error_p99_n", "force_error_max_n"):
        assert abs(j[k] - float(r[k])) <= 1e-6, "%s: %s differs between CSV and JSON" % (name, k)
    lo, hi = float(r["p999_min_over_runs_ns"]), float(r["p999_max_over_runs_ns"])
    assert 0 <= lo <= hi and j["p999_spread_ratio"] >= 1.0, "%s: p99.9 spread %g-%g" % (name, lo, hi)
    am = float(r["amortised_frame_cost_ns"])
    assert abs(am - float(r["frame_cost_ns"]) * 30 / 1000) <= 0.1 + 1e-6 * am, "%s: amortised %g" % (name, am)
m = doc["machine"]
assert m["load_1min_start"] >= 0 and m["load_1min_end"] >= 0 and m["cpus"] >= 1, m
# the steal share of the CPU time during the run (/proc/stat; null where it cannot be read)
assert m["steal_percent"] is None or 0 <= m["steal_percent"] <= 100, m
if m["steal_percent"] is not None:
    assert "% of the CPU time during the run" in log, "no steal printed beside the load"
loaded = max(m["load_1min_start"], m["load_1min_end"]) > m["cpus"] - 1 or (m["steal_percent"] or 0) > 5
assert m["loaded"] == loaded, m
assert "1-minute load" in log, "no load line printed"
assert ("taken on a loaded machine" in log) == loaded, "loaded-machine line does not match the load"
gp = open(d + "/charts.gp").read()
psd = gp[gp.index("psd.png"):]
assert "set title" in psd and "modified renderer" in psd.split("set title", 1)[1].split("\n", 1)[0], "psd.png's title names no renderer"
assert "goal: update p99.9" in gp and "rebuild amortised" in gp, "speed_vs_accuracy.png lacks its goal line or mesh-bvh's rebuild"
PY
bench feel --quick --method finger --data "$work/no-data" --dump 'finger|press'
png feel feel.png
# Its per-update logs name the fingertip's contact state: free 2 mm above all the surface within
# the finger's reach, touching somewhere while pressed under it (the log's own heights).
python3 - "$work/feel" <<'PY' || fail "bench feel --dump: the contact state does not match the heights"
import csv, glob, math, sys
d = sys.argv[1]
files = glob.glob(d + "/feel_dump/*.csv")
assert files, "no feel_dump/*.csv for --dump 'finger|press'"
names = {"free", "behind", "touching", "on-wall", "over-hole"}
for f in files:
    rows = list(csv.DictReader(open(f)))
    assert rows, f
    touched = False
    for r in rows:
        s = r["state"]
        assert s in names, "%s: state %r" % (f, s)
        z, top, reach = float(r["hip_z_mm"]), float(r["surface_z_mm"]), float(r["reach_surface_z_mm"])
        if math.isfinite(top) and math.isfinite(reach) and z > max(top, reach) + 2.0:
            assert s == "free", "%s at %s s: %s 2 mm above all within reach" % (f, r["t_s"], s)
        if r["pressed"] == "1" and math.isfinite(top) and z < top - 0.2:
            touched = touched or s == "touching"
    assert touched, "%s: never touching while pressed under the surface" % f
    # Without --dump-ball-ideal the ideal ball's columns are not computed: nan, not a force.
    for c in ("ball_ideal_fx_n", "ball_ideal_fy_n", "ball_ideal_fz_n"):
        assert all(r[c] == "nan" for r in rows), "%s: %s filled without --dump-ball-ideal" % (f, c)
print("%d dumps checked" % len(files))
PY
# With --dump-ball-ideal they hold the ideal ball's force (ball_ideal.h): none where the HIP is above
# all the surface within the fingertip's reach, some wherever it is under the surface at its own x-y
# (the ball's rest height is never below that surface).
"$exe" bench feel --quick --method finger --data "$work/no-data" --scene synthetic-head \
    --dump 'finger|press' --dump-ball-ideal --out "$work/feel-ball" >"$work/feel-ball.log" 2>&1 ||
    { tail -n 20 "$work/feel-ball.log"; fail "bench feel --dump-ball-ideal failed"; }
python3 - "$work/feel-ball" <<'PY' || fail "bench feel --dump-ball-ideal: the ball's force does not match the heights"
import csv, glob, math, sys
files = glob.glob(sys.argv[1] + "/feel_dump/*.csv")
assert files, "no feel_dump/*.csv with --dump-ball-ideal"
under = 0
for f in files:
    for r in csv.DictReader(open(f)):
        ball = [float(r[c]) for c in ("ball_ideal_fx_n", "ball_ideal_fy_n", "ball_ideal_fz_n")]
        assert all(math.isfinite(v) for v in ball), "%s at %s s: ball force %s" % (f, r["t_s"], ball)
        size = math.sqrt(sum(v * v for v in ball))
        z, top, reach = float(r["hip_z_mm"]), float(r["surface_z_mm"]), float(r["reach_surface_z_mm"])
        if math.isfinite(reach) and z > reach + 0.01:
            assert size == 0.0, "%s at %s s: %.3f N above all within reach" % (f, r["t_s"], size)
        if math.isfinite(top) and z < top - 0.2:
            under += 1
            assert size > 0.0, "%s at %s s: no force %.2f mm under the surface" % (f, r["t_s"], top - z)
assert under > 0, "no update under the surface in the dumped presses"
print("%d dumps, %d updates under the surface checked" % (len(files), under))
PY
# --scene touches only the scenes it names; one that names none is bad input (exit 2, one line).
"$exe" bench feel --quick --method finger --data "$work/no-data" --scene synthetic-head \
    --out "$work/feel-head" >"$work/feel-head.log" 2>&1 ||
    { tail -n 20 "$work/feel-head.log"; fail "bench feel --scene synthetic-head failed"; }
python3 - "$work/feel-head" <<'PY' || fail "bench feel --scene: rows of scenes it did not name"
import csv, sys
scenes = {r["scene"] for r in csv.DictReader(open(sys.argv[1] + "/feel.csv"))} - {"all"}
assert scenes and all("synthetic-head" in s for s in scenes), scenes
PY
status=0
"$exe" bench feel --quick --data "$work/no-data" --scene no-such-scene --out "$work/feel-none" \
    >"$work/feel-none.log" 2>"$work/feel-none.err" || status=$?
[ "$status" -eq 2 ] && [ "$(grep -c 'depthtouch bench feel: --scene' "$work/feel-none.err")" -eq 1 ] ||
    { cat "$work/feel-none.err"; fail "bench feel --scene no-such-scene: exit $status"; }
# --setting measures only the settings it names, --quick or not; a name that is none is bad input.
"$exe" bench feel --quick --method finger,modified --setting finger-ramp,modified-release \
    --data "$work/no-data" --scene synthetic-head --out "$work/feel-setting" \
    >"$work/feel-setting.log" 2>&1 ||
    { tail -n 20 "$work/feel-setting.log"; fail "bench feel --setting failed"; }
python3 - "$work/feel-setting" <<'PY' || fail "bench feel --setting: rows of settings it did not name"
import csv, sys
settings = {r["setting"] for r in csv.DictReader(open(sys.argv[1] + "/feel.csv"))}
assert settings == {"finger-ramp", "modified-release"}, settings
PY
status=0
"$exe" bench feel --quick --data "$work/no-data" --setting fingr --out "$work/feel-fingr" \
    >"$work/feel-fingr.log" 2>"$work/feel-fingr.err" || status=$?
[ "$status" -eq 2 ] && [ "$(wc -l <"$work/feel-fingr.err")" -eq 1 ] &&
    grep -q "depthtouch bench feel: --setting: no setting 'fingr'.*finger-ramp" "$work/feel-fingr.err" ||
    { cat "$work/feel-fingr.err"; fail "bench feel --setting fingr: exit $status"; }
bench stability --quick
png stability stability.png
png stability stability_energy.png
# Its limits table is the one its CSV gives: per series, the first k that is not stable.
python3 - "$work/stability" <<'PY' || fail "bench stability: limits differ from its runs"
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/stability.csv")))
assert rows and {"wall", "finger", "modified"} <= {r["method"] for r in rows}, "methods"
first = {}
for r in rows:
    key = (r["method"], r["surface"], r["servo_rate_hz"], r["hand_damping_n_s_per_m"])
    if r["outcome"] not in ("settled", "decaying"):
        first.setdefault(key, float(r["stiffness_n_per_m"]))
for l in csv.DictReader(open(d + "/stability_limits.csv")):
    key = (l["method"], l["surface"], l["servo_rate_hz"], l["hand_damping_n_s_per_m"])
    assert abs(first.get(key, 0.0) - float(l["first_unstable_n_per_m"])) < 1e-3, key
PY
bench av --duration 2 --frames 30 --size 96x64
png av av.png
# The offsets it prints are the ones its A/V logs hold: the p99 of |offset_ms| in av-null.csv.
python3 - "$work/av" <<'PY' || fail "bench av: printed figures differ from its logs"
import csv, math, re, sys
d = sys.argv[1]
printed = {}
for line in open(d + "/../av.log"):
    m = re.match(r"(null|wav)\s+(\d+)\s+(\S+)\s+(\S+)", line)
    if m:
        printed[m.group(1)] = (int(m.group(2)), float(m.group(4)))
for out in ("null", "wav"):
    off = sorted(abs(float(r["offset_ms"])) for r in csv.DictReader(open("%s/av-%s.csv" % (d, out))))
    frames, p99 = printed[out]
    # platform::percentile: the nearest rank
    want = off[max(0, math.ceil(0.99 * len(off)) - 1)]
    if frames != len(off) or abs(p99 - want) > 0.051:
        sys.exit("%s: printed %d frames, p99 %.1f; the log has %d, p99 %.2f" % (out, frames, p99, len(off), want))
PY
skipped=""
if ! "$exe" bench render --help >/dev/null 2>&1; then
    skipped="bench render not in this build (no EGL)"
elif [ -n "$data" ] && [ -f "$data/rgbd-7scenes-redkitchen/frame-000000.depth.png" ]; then
    bench render --frames 5 --data "$data"
    png render fps_vs_error.png
    png render stages.png
    png render cpu_vs_depth_size.png
    # --no-stages draws no stage chart and removes the one of the run before from --out, so no old
    # chart is taken for this run's; gnuplot's warnings stay out of the printed tables.
    bench render --frames 5 --data "$data" --no-stages --only step8,quadtree-0.50
    [ -f "$work/render/stages.png" ] && fail "bench render --no-stages left a stages.png"
    grep -E "^Warning: |, line [0-9]+: " "$work/render.log" &&
        fail "bench render: gnuplot's warnings in the output"
    png render fps_vs_error.png
    png render cpu_vs_depth_size.png
else
    [ "${DT_REQUIRE_SHARED_DATA:-0}" != 0 ] && fail "bench render: no shared RGB-D data at '$data'"
    skipped="bench render skipped: no shared RGB-D data at '$data'"
fi
# A partial run says what it left out on its PASS line.
if [ -n "$skipped" ]; then echo "PASS except: $skipped"; else echo PASS; fi
