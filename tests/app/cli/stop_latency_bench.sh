#!/usr/bin/env bash
# How fast `depthtouch play` stops while its live stream is silent: quit and stop on the control
# socket, SIGTERM, and --duration, each tried N times (default 20) on a FIFO whose sender wrote a
# one-second clip and then went quiet with the FIFO still open (a network stream whose sender
# stalled). Prints the median, p99 and worst of each and writes stop_latency.csv and
# stop_latency.png (gnuplot) into OUT_DIR. A figure, not a test: nothing here asserts a time.
#
# Usage: [DT_STOP_SENDER=trickle] [DT_STOP_ACTIONS='quit stop sigterm duration']
#        [DT_STOP_HTTP_ACTIONS='http-quit http-sigterm http-seek']
#        tests/app/cli/stop_latency_bench.sh DEPTHTOUCH [OUT_DIR] [N]
# Needs: ffmpeg (the clip), socat (the control socket), gnuplot (the chart; skipped without it).
# Measured: quit and SIGTERM from the request to the process's exit; stop from the request to its
# answer; --duration 3 from the control socket's appearance (the control loop starts just after)
# to the exit, less 3 s, with --idle, so that the player is waiting for the next sender by then.
# Source: the goal of docs/benchmarks.md (stop, quit, SIGTERM and --duration within 100 ms at p99 over 20 tries).
set -euo pipefail

exe=${1:?usage: stop_latency_bench.sh DEPTHTOUCH [OUT_DIR] [N]}
out=${2:-stop-latency}
tries=${3:-20}
[ -x "$exe" ] || { echo "stop_latency_bench.sh: $exe is not an executable (build/host/app/cli/depthtouch?)" >&2; exit 2; }
mkdir -p "$out"
work=$(mktemp -d)
sender=
player=
cleanup() {
    [ -n "$player" ] && kill -KILL "$player" 2>/dev/null || true
    [ -n "$sender" ] && kill -KILL "$sender" 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT

ffmpeg -loglevel error -f lavfi -i testsrc=size=160x120:rate=30:duration=1 -c:v libx264 \
    -preset ultrafast -pix_fmt yuv420p -f mpegts "$work/live.ts"

now_ms() { date +%s%3N; }
ask() { # ask SOCKET JSON: prints the answer line
    { printf "%s\n" "$2" | socat -t 5 - "UNIX-CONNECT:$1" 2>/dev/null | head -n 1; } || true
}
wait_state() { # wait_state SOCKET STATE: up to 10 s
    local end=$(($(now_ms) + 10000))
    while [ "$(now_ms)" -lt "$end" ]; do
        [ "$(ask "$1" '{"command":["get","state"]}')" = "{\"data\":\"$2\",\"error\":\"success\"}" ] &&
            return 0
        sleep 0.05
    done
    return 1
}
# DT_STOP_SENDER=trickle: the FIFO's sender writes the clip 2 kB at a time, a piece every 0.2 s
# (a link that trickles), instead of all at once and then nothing.
split -b 2048 -d -a 4 "$work/live.ts" "$work/piece."
start_silent_sender() { # a writer that sends the clip and keeps the FIFO open, silent
    rm -f "$work/live.fifo"
    mkfifo "$work/live.fifo"
    if [ "${DT_STOP_SENDER:-silent}" = trickle ]; then
        (exec 3>"$work/live.fifo"; for p in "$work"/piece.*; do cat "$p" >&3; sleep 0.2; done
         exec sleep 600) &
    else
        (exec 3>"$work/live.fifo"; cat "$work/live.ts" >&3; exec sleep 600) &
    fi
    sender=$!
}
stop_sender() { kill -KILL "$sender" 2>/dev/null || true; wait "$sender" 2>/dev/null || true; sender=; }

echo "action,try,ms" >"$out/stop_latency.csv"
record() { echo "$1,$2,$3" >>"$out/stop_latency.csv"; }

actions=${DT_STOP_ACTIONS:-quit stop sigterm duration}
for action in $actions; do
    for i in $(seq 1 "$tries"); do
        start_silent_sender
        sock="$work/ctl.sock"
        rm -f "$sock"
        if [ "$action" = duration ]; then
            # --idle: the silence does not end it first (it waits for the next sender instead)
            "$exe" play "$work/live.fifo" --display mock --haptic none --quiet --control "$sock" \
                --idle --duration 3 >/dev/null 2>&1 &
        else
            "$exe" play "$work/live.fifo" --display mock --haptic none --quiet --control "$sock" \
                --idle >/dev/null 2>&1 &
        fi
        player=$!
        # --duration counts from the control loop's start, just after the socket is made
        for _ in $(seq 1 500); do [ -S "$sock" ] && break; sleep 0.01; done
        t_start=$(now_ms)
        if ! wait_state "$sock" playing; then
            echo "stop_latency: try $i of $action never played" >&2
            kill -KILL "$player" 2>/dev/null || true
            player=
            stop_sender
            continue
        fi
        t_playing=$(now_ms)
        case "$action" in
        quit)
            sleep 1.5
            t0=$(now_ms)
            ask "$sock" '{"command":["quit"]}' >/dev/null
            wait "$player" || true
            record quit "$i" $(($(now_ms) - t0))
            ;;
        stop)
            sleep 1.5
            t0=$(now_ms)
            ask "$sock" '{"command":["stop"]}' >/dev/null
            record stop "$i" $(($(now_ms) - t0))
            ask "$sock" '{"command":["quit"]}' >/dev/null
            wait "$player" || true
            ;;
        sigterm)
            sleep 1.5
            t0=$(now_ms)
            kill -TERM "$player"
            wait "$player" || true
            record sigterm "$i" $(($(now_ms) - t0))
            ;;
        duration)
            # By 3 s the stream has been silent for about 2 s and the player waits for the next
            # sender in a blocked open: --duration must end that wait.
            wait "$player" || true
            late=$(($(now_ms) - t_start - 3000))
            record duration "$i" $((late < 0 ? 0 : late))
            ;;
        esac
        player=
        stop_sender
        : "$t_playing"
    done
done

# A stalled HTTP server: it announces a 10 s clip, sends its first 200 kB and then nothing (a
# server or a link that hangs mid-file). quit, SIGTERM and a seek to 0 while the read is blocked.
ffmpeg -loglevel error -f lavfi -i testsrc=size=160x120:rate=30:duration=10 -c:v libx264 \
    -preset ultrafast -pix_fmt yuv420p -f mpegts "$work/long.ts"
size=$(stat -c %s "$work/long.ts")
printf 'HTTP/1.0 200 OK\r\nContent-Type: video/mp2t\r\nContent-Length: %s\r\n\r\n' "$size" \
    >"$work/head.txt"
head -c 200000 "$work/long.ts" >"$work/part.ts"
port=$((20000 + $$ % 20000))
socat "TCP-LISTEN:$port,reuseaddr,fork" \
    SYSTEM:"cat '$work/head.txt' '$work/part.ts'; exec sleep 600" 2>/dev/null &
server=$!
sleep 0.3
for action in ${DT_STOP_HTTP_ACTIONS-http-quit http-sigterm http-seek}; do
    for i in $(seq 1 "$tries"); do
        sock="$work/ctl.sock"
        rm -f "$sock"
        "$exe" play "http://127.0.0.1:$port/clip.ts" --display mock --haptic none --quiet \
            --control "$sock" --idle >/dev/null 2>&1 &
        player=$!
        for _ in $(seq 1 500); do [ -S "$sock" ] && break; sleep 0.01; done
        if ! wait_state "$sock" playing; then
            echo "stop_latency: try $i of $action never played" >&2
            kill -KILL "$player" 2>/dev/null || true
            player=
            continue
        fi
        sleep 1.5
        t0=$(now_ms)
        case "$action" in
        http-quit)
            ask "$sock" '{"command":["quit"]}' >/dev/null
            wait "$player" || true
            record http-quit "$i" $(($(now_ms) - t0))
            ;;
        http-sigterm)
            kill -TERM "$player"
            wait "$player" || true
            record http-sigterm "$i" $(($(now_ms) - t0))
            ;;
        http-seek)
            ask "$sock" '{"command":["seek",0,"absolute"]}' >/dev/null
            record http-seek "$i" $(($(now_ms) - t0))
            ask "$sock" '{"command":["quit"]}' >/dev/null
            wait "$player" || true
            ;;
        esac
        player=
    done
done
kill -KILL "$server" 2>/dev/null || true
wait "$server" 2>/dev/null || true
actions="$actions ${DT_STOP_HTTP_ACTIONS-http-quit http-sigterm http-seek}"

echo "stop latency with a silent live stream and a stalled HTTP server, $tries tries each (ms):"
printf '%-9s %8s %8s %8s\n' action median p99 worst
for action in $actions; do
    grep "^$action," "$out/stop_latency.csv" | cut -d, -f3 | sort -n | awk -v a="$action" '
        { v[NR] = $1 }
        END {
            if (NR == 0) { printf "%-9s %8s\n", a, "none"; exit }
            p99 = v[int(0.99 * (NR - 1)) + 1 + (0.99 * (NR - 1) > int(0.99 * (NR - 1)))]
            printf "%-9s %8d %8d %8d\n", a, v[int((NR + 1) / 2)], p99, v[NR]
        }'
done | tee "$out/stop_latency.txt"

if command -v gnuplot >/dev/null; then
    gnuplot <<EOF
set terminal pngcairo size 900,540
set output '$out/stop_latency.png'
set datafile separator ','
set title 'play: time to stop or seek with a silent live stream and a stalled HTTP server ($tries tries each)'
set ylabel 'ms (log scale; 0 is drawn at 1)'
set xlabel 'try'
set key below horizontal
set logscale y
set yrange [1:400]
set xrange [0:$tries + 1]
set grid ytics
plot '$out/stop_latency.csv' using (strcol(1) eq 'quit' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 1 lc rgb '#9400d3' title 'quit (socket → exit)', \
     '' using (strcol(1) eq 'stop' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 2 lc rgb '#009e73' title 'stop (socket → answer)', \
     '' using (strcol(1) eq 'sigterm' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 3 lc rgb '#56b4e9' title 'SIGTERM → exit', \
     '' using (strcol(1) eq 'duration' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 4 lc rgb '#e69f00' title '--duration 3: exit after 3 s', \
     '' using (strcol(1) eq 'http-quit' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 6 dt 3 lc rgb '#d55e00' title 'stalled HTTP: quit', \
     '' using (strcol(1) eq 'http-sigterm' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 8 dt 3 lc rgb '#0072b2' title 'stalled HTTP: SIGTERM', \
     '' using (strcol(1) eq 'http-seek' ? \$2 : 1/0):(\$3 > 0 ? \$3 : 1) with linespoints pt 12 dt 3 lc rgb '#555555' title 'stalled HTTP: seek 0 → answer', \
     100 with lines dashtype 2 lw 2 lc rgb 'black' title 'goal: 100 ms'
EOF
fi
