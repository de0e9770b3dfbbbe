#!/usr/bin/env bash
# Install every Debian package that DepthTouch's build, tests, benchmarks and demo need.
#
# Usage: toolchain/install-deps.sh [--cross aarch64|armhf]... [--dry-run]
#
# Idempotent: packages that are already installed are skipped, and nothing is done when all are present.
# Runs apt-get directly as root, or through sudo as a normal user.
# --cross ARCH also installs the cross compiler, qemu-user and the ARCH (:arm64 / :armhf) -dev packages
# that the cross build links against (Debian multiarch).
set -euo pipefail

# Host packages, grouped by what needs them. Later features add their packages here.
HOST_PACKAGES=(
    # build
    build-essential cmake ninja-build pkgconf git
    # compile cache: shared between build trees (the mutation check's scratch copy)
    ccache
    # the generated mutants of the mutation check (tests/mutation/generate.py: Python 3.11's tomllib)
    python3
    # .ci/format-check: clang-format-diff on the lines changed since .ci/format-base
    clang-format-14
    # packaging: the man page from --help; dpkg-shlibdeps (dpkg-dev) for the package's Depends;
    # the package test's checks: lintian, and systemd-analyze (systemd) scoring the unit's sandbox
    help2man dpkg-dev lintian systemd
    # the documentation's examples: socat talks to the control socket (docs/devices.md)
    socat
    # the completion test runs the generated zsh function (bash is there already)
    zsh
    # the HLS test serves a playlist over HTTP with busybox's httpd
    busybox
    # tests and benchmarks
    googletest libgtest-dev libgmock-dev libbenchmark-dev gnuplot-nox
    # libraries used by the app layer
    libglm-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
    # depth enhancement: Delaunay triangulation
    libcgal-dev
    libtomlplusplus-dev
    # drivers: FFmpeg (decode, encode, image I/O) and its command-line tools for tests; TagLib for
    # the ID3 tags of MPEG-TS timed metadata
    libavcodec-dev libavformat-dev libavutil-dev libswscale-dev libswresample-dev ffmpeg libtag1-dev
    # drivers: EGL + GLES on Mesa (llvmpipe when there is no GPU), GBM/KMS, X11
    libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev libx11-dev
    # tests of the X11 display: a private virtual X server
    xvfb
    # drivers: USB haptic device, remote-control input, sound output
    libusb-1.0-0-dev libevdev-dev libasound2-dev
    # fuzz preset: clang with libFuzzer and the sanitizer runtimes
    clang-14 libclang-rt-14-dev
    # the GStreamer plugin (gst/, built when these are found) and its tests: gst-inspect-1.0 and
    # gst-launch-1.0, the Matroska demuxer (plugins-good) and the H.264 decoder (libav)
    libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev gstreamer1.0-tools
    gstreamer1.0-plugins-good gstreamer1.0-libav
)

# -dev packages the cross build links against, per Debian architecture.
CROSS_DEV_PACKAGES=(
    libgtest-dev libgmock-dev
    libavcodec-dev libavformat-dev libavutil-dev libswscale-dev libswresample-dev libtag1-dev
    libegl-dev libgles-dev libgbm-dev libdrm-dev
    libusb-1.0-0-dev libevdev-dev libasound2-dev
    libcgal-dev
    libtomlplusplus-dev
)

cross_arches=()
dry_run=0
while [ $# -gt 0 ]; do
    case "$1" in
        --cross)
            [ $# -ge 2 ] || { echo "install-deps: --cross needs an architecture (aarch64 or armhf)" >&2; exit 2; }
            cross_arches+=("$2"); shift 2 ;;
        --cross=*) cross_arches+=("${1#--cross=}"); shift ;;
        --dry-run) dry_run=1; shift ;;
        -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "install-deps: unknown option '$1' (see --help)" >&2; exit 2 ;;
    esac
done

if [ "$(id -u)" -eq 0 ]; then
    SUDO=()
elif command -v sudo >/dev/null 2>&1; then
    SUDO=(sudo)
else
    echo "install-deps: not root and sudo is not installed: run this script as root" >&2
    exit 1
fi

wanted=("${HOST_PACKAGES[@]}")
foreign=()
for arch in "${cross_arches[@]}"; do
    case "$arch" in
        aarch64|arm64) deb=arm64; triple=aarch64-linux-gnu ;;
        armhf|arm) deb=armhf; triple=arm-linux-gnueabihf ;;
        *) echo "install-deps: unknown cross architecture '$arch' (aarch64 or armhf)" >&2; exit 2 ;;
    esac
    foreign+=("$deb")
    wanted+=("g++-$triple" qemu-user)
    for p in "${CROSS_DEV_PACKAGES[@]}"; do wanted+=("$p:$deb"); done
done

# Installed means dpkg lists the package as "install ok installed" for the wanted architecture (the
# host's, or the one after ':'), or as an Architecture: all package. With a foreign architecture
# enabled, dpkg-query prints one line per installed architecture, hence the per-line match.
native=$(dpkg --print-architecture)
is_installed() {
    local name=${1%%:*} arch=$native
    [ "$name" = "$1" ] || arch=${1#*:}
    dpkg-query -W -f='${Status}|${Architecture}\n' "$name" 2>/dev/null |
        grep -qE "^install ok installed\|($arch|all)\$"
}
missing=()
for p in "${wanted[@]}"; do
    is_installed "$p" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#wanted[@]} packages are installed"
    exit 0
fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
[ "$dry_run" -eq 0 ] || exit 0

need_update=0
for deb in "${foreign[@]}"; do
    if ! dpkg --print-foreign-architectures | grep -qx "$deb"; then
        "${SUDO[@]}" dpkg --add-architecture "$deb"
        need_update=1
    fi
done
# Refresh the package lists when they are missing or older than a day, or after adding an architecture.
if [ $need_update -eq 1 ] || [ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mtime -1 2>/dev/null | head -1)" ]; then
    "${SUDO[@]}" apt-get update -q
fi
DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "install-deps: done"
