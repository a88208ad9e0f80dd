#!/usr/bin/env bash
# The monitor's own receive path against liblcm's, side by side in one session, runs alternated (docs/BENCHMARKS.md,
# "The monitor's own receive path against liblcm's"): one line per run, "CASE PATH RESULT".
#
#   tests/bench/monitor_latency_side_by_side.sh BUILD_DIR [CASE ...] [--runs N] [--port P]
#
# Cases (default: all but the busy-poll one):
#   ordinary      1 kHz, batch 1, 10 s; every process ordinary (SCHED_OTHER)
#   rt            1 kHz, batch 1, 10 s; the monitor alone under --realtime 50 (the benchmark stays ordinary)
#   rt-pinned     as rt, the monitor pinned to CPU 1 (--cpu 1) and the benchmark's threads to CPU 0
#   busy-poll     as rt-pinned, with --busy-poll-us 50 on the monitor's socket
#   all-rt-pinned as rt-pinned, and the benchmark (publisher and subscriber) under `chrt -f 40` as well
#   batch50       10 kHz, batch 50, 5 s; ordinary
#   batch50-rt    10 kHz, batch 50, 5 s; as rt-pinned
# Each case runs N times (default 2) on each path, own then liblcm, alternated. Needs an idle machine (nothing else
# timed or built meanwhile) and a build with -DROCKWATCH_BUILD_BENCH=ON.
set -euo pipefail

build=${1:?usage: $0 BUILD_DIR [CASE ...] [--runs N] [--port P]}
shift
runs=2
port=7693
cases=()
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --port) port=$2; shift 2 ;;
    *) cases+=("$1"); shift ;;
  esac
done
[ ${#cases[@]} -gt 0 ] || cases=(ordinary rt rt-pinned batch50 batch50-rt)

bench=$build/tests/bench/bench_monitor_latency
monitor=$build/host_tools/rockwatch-monitor
monitor_liblcm=$build/tests/bench/rockwatch-monitor-liblcm  # the same loop with liblcm's receive thread as its input
url="udpm://239.255.76.67:$port?ttl=0"

one() {  # CASE PATH
  local rate=1000 seconds=10 batch=1 margs="" bargs=() prefix=()
  case $1 in
    ordinary) ;;
    rt) margs="--realtime 50" ;;
    rt-pinned) margs="--realtime 50 --cpu 1"; bargs=(--cpu 0) ;;
    busy-poll) margs="--realtime 50 --cpu 1 --busy-poll-us 50"; bargs=(--cpu 0) ;;
    all-rt-pinned) margs="--realtime 50 --cpu 1"; bargs=(--cpu 0); prefix=(chrt -f 40) ;;
    batch50) rate=10000; seconds=5; batch=50 ;;
    batch50-rt) rate=10000; seconds=5; batch=50; margs="--realtime 50 --cpu 1"; bargs=(--cpu 0) ;;
    *) echo "unknown case $1" >&2; exit 2 ;;
  esac
  if [ "$2" = liblcm ] && [ "$1" = busy-poll ]; then return; fi  # liblcm owns its socket
  local out exe=$monitor
  if [ "$2" = liblcm ]; then exe=$monitor_liblcm; fi
  out=$("${prefix[@]}" "$bench" "$exe" --rate $rate --seconds $seconds --batch $batch --lcm-url "$url" --receive-path "$2" \
        ${margs:+--monitor-args "$margs"} "${bargs[@]}" 2>/dev/null || true)
  echo "$1 $2 $(echo "$out" | head -1)"
  echo "$out" | sed -n 's/^  monitor timing: /    timing: /p'
}

for c in "${cases[@]}"; do
  for ((r = 1; r <= runs; ++r)); do
    for p in own liblcm; do one "$c" "$p"; done
  done
done
