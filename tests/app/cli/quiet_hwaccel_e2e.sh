#!/bin/sh
# End-to-end (issue 61, Smaller): `play --quiet` prints nothing on a desktop that has libvdpau but
# no VDPAU driver. The decoder's hwaccel=auto tried VDPAU there, and libvdpau itself printed
# "Failed to open VDPAU backend libvdpau_nvidia.so: ..." on stderr for each decoder, under --quiet
# too; auto now tries VDPAU only where libvdpau has a driver to load. An X server (Xvfb) and an
# empty driver folder (VDPAU_DRIVER_PATH) make that desktop here. hwaccel=vdpau asked for by name
# still tries it, and fails with its one line: the check that this machine reaches libvdpau at all.
# Exit 77 (skip) without Xvfb, the ffmpeg CLI tools or libvdpau. Usage: quiet_hwaccel_e2e.sh DEPTHTOUCH
set -u
exe="$1"
. "$(dirname "$0")/../../e2e_lib.sh"
e2e_start quiet_hwaccel ffmpeg xvfb-run Xvfb
ldconfig -p 2>/dev/null | grep -q "libvdpau.so.1 " || { echo "no libvdpau: skipped"; exit 77; }

ff -f lavfi -i "testsrc2=s=160x120:r=30:d=1" -pix_fmt yuv420p "$work/c.mkv" || fail "ffmpeg color"
ff -f lavfi -i "testsrc2=s=160x120:r=30:d=1,format=gray" "$work/d.mkv" || fail "ffmpeg depth"
"$exe" encode --color "$work/c.mkv" --depth "$work/d.mkv" --near 1 --far 2 --preset ultrafast \
    -o "$work/a.mkv" >"$work/log" 2>&1 || { cat "$work/log"; fail "encode"; }
mkdir "$work/no-drivers"

# play ARGS...: on an X server with no VDPAU driver installed; stderr in $work/err, exit code in rc.
play() {
    VDPAU_DRIVER_PATH="$work/no-drivers" xvfb-run -a "$exe" play "$work/a.mkv" --no-config \
        --display mock --haptic none --audio-device none --duration 1 "$@" \
        >"$work/out" 2>"$work/err" </dev/null
    rc=$?
}

play --decoder-options hwaccel=vdpau
grep -q "VDPAU" "$work/err" || {
    echo "libvdpau is not reached on this machine (no X server?): skipped"
    cat "$work/err"
    exit 77
}
play --quiet
[ "$rc" -eq 0 ] || fail "play --quiet: exit $rc, '$(cat "$work/err")'"
[ ! -s "$work/err" ] || fail "play --quiet printed on stderr: '$(cat "$work/err")'"
echo "quiet_hwaccel: ok"
