#!/bin/sh
# Instructions per modified-renderer update for every setting of `depthtouch bench haptics`
# (720x486, 1920x1080, 3840x2160 x still, 0.1 m/s, 1 m/s), counted by valgrind's callgrind:
# noise-free figures to compare variants of the renderer on a shared machine.
# Usage: haptics_cost.sh [HAPTICS_COST_BINARY] [UPDATES] [OUT_DIR]
# Prints one line per setting: size, speed, Ir/update, and the program's work/accuracy lines.
set -eu
bin=${1:-build/host/bench/haptics/haptics_cost}
updates=${2:-3000}
out=${3:-bench-out/haptics-cost}
mkdir -p "$out"
for size in "720 486" "1920 1080" "3840 2160"; do
    for speed in 0 0.1 1; do
        set -- $size
        tag="${1}x${2}-${speed}"
        valgrind --tool=callgrind --collect-atstart=no --instr-atstart=no \
            --callgrind-out-file="$out/callgrind.$tag" "$bin" "$1" "$2" "$speed" "$updates" \
            >"$out/stdout.$tag" 2>"$out/stderr.$tag"
        ir=$(callgrind_annotate "$out/callgrind.$tag" | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}')
        printf '%-10s %-4s m/s  Ir/update %8.0f\n' "${1}x${2}" "$speed" "$(echo "$ir / $updates" | bc -l)"
        sed 's/^/    /' "$out/stdout.$tag"
    done
done
