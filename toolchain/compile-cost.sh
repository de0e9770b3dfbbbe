#!/usr/bin/env bash
# What the build costs, per translation unit: configures BUILD with the host preset, compiling every
# unit through /usr/bin/time and ccache with an empty cache of its own (BUILD/ccache, so nothing comes
# from the developer's cache), builds the TARGETs (all when none is named), and prints the build's
# wall time, the CPU seconds (user + system, the compiler's own, so a busy machine inflates them
# less than the wall time) per folder and the costliest units. docs/building.md, "Build time", has
# the figures it printed and what they led to.
#
# Usage: toolchain/compile-cost.sh BUILD [TARGET...]    e.g. toolchain/compile-cost.sh /tmp/cost depthtouch
# Exit: 0, or the build's status; 2 for bad usage or without /usr/bin/time (Debian package `time`).
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: toolchain/compile-cost.sh BUILD [TARGET...]" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "compile-cost: needs /usr/bin/time (apt-get install time)" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(mkdir -p "$1" && cd "$1" && pwd)
shift
log=$build/compile-cost.log
rm -rf "$build/ccache" "$log"
launcher="/usr/bin/time;-f;%U %S %e %C;-a;-o;$log;env;CCACHE_DIR=$build/ccache;CCACHE_BASEDIR=$root;ccache"
command -v ccache > /dev/null || launcher="/usr/bin/time;-f;%U %S %e %C;-a;-o;$log"
cmake --preset host -S "$root" -B "$build" -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" \
    -DCMAKE_C_COMPILER_LAUNCHER="$launcher" > "$build/compile-cost-configure.log"
targets=()
for t in "$@"; do targets+=(--target "$t"); done
start=$SECONDS
status=0
cmake --build "$build" "${targets[@]}" > "$build/compile-cost-build.log" 2>&1 || status=$?
wall=$((SECONDS - start))
[ "$status" -eq 0 ] || { tail -20 "$build/compile-cost-build.log"; exit "$status"; }

# One line per compile: "user system wall command...", the source after -c.
units=$(awk -v root="$root/" '
    $1 ~ /^[0-9.]+$/ {
        src = ""
        for (i = 4; i < NF; i++) if ($i == "-c") src = $(i + 1)
        if (src == "") next
        sub(root, "", src)
        printf "%.2f %s\n", $1 + $2, src
    }' "$log" | sort -rn)
awk -v wall="$wall" '{ t += $1 } END {
    printf "%d units, %.0f CPU-s (%.1f CPU-min); build wall time %d s\n", NR, t, t / 60, wall }' <<< "$units"
echo "CPU-s   share  folder"
awk '{ t += $1; n = split($2, p, "/"); f = p[1] "/" p[2]; if (p[1] == "tests" && n > 3) f = f "/" p[3]
       c[f] += $1 }
     END { for (f in c) printf "%7.1f %5.1f%%  %s\n", c[f], 100 * c[f] / t, f }' <<< "$units" | sort -rn
echo "CPU-s  unit"
head -n "${DT_COST_TOP:-25}" <<< "$units" | awk '{ printf "%6.1f  %s\n", $1, $2 }'
