#!/usr/bin/env bash
# The project's own supervisor for rockwatch-monitor, for machines without systemd (containers, lab PCs run by
# hand): starts the monitor with the given arguments and restarts it at once whenever it exits or is killed,
# until the supervisor itself gets SIGINT or SIGTERM (then the monitor is stopped cleanly, with its summary).
#
#   scripts/monitor-supervisor.sh [--monitor PATH] [--pid-file FILE] [--] MONITOR_ARGS...
#
# --monitor: the executable (default: build/release/host_tools/rockwatch-monitor beside this script's tree).
# --pid-file: the current monitor's pid is written there at each start (tests and operators read it).
# A monitor that exits within 1 s of its start 5 times in a row (a bad configuration, exit status 2) makes the
# supervisor stop with that status instead of spinning. Each restart is reported on stderr with the exit cause.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
monitor="$root/build/release/host_tools/rockwatch-monitor"
pid_file=""
while [ $# -gt 0 ]; do
  case "$1" in
    --monitor) monitor=$2; shift 2 ;;
    --pid-file) pid_file=$2; shift 2 ;;
    --) shift; break ;;
    *) break ;;
  esac
done
[ -x "$monitor" ] || { echo "monitor-supervisor: $monitor is not an executable (build it: scripts/build.sh)" >&2; exit 2; }

child=0
stopping=0
stop() {
  stopping=1
  [ "$child" -ne 0 ] && kill -TERM "$child" 2>/dev/null
}
trap stop INT TERM

fast_failures=0
restarts=0
while :; do
  started=$(date +%s%N)
  "$monitor" "$@" &
  child=$!
  [ -n "$pid_file" ] && echo "$child" > "$pid_file"
  wait "$child"
  status=$?
  # wait returns early (status > 128) when our own trap ran: wait again for the monitor's real exit.
  while kill -0 "$child" 2>/dev/null; do wait "$child"; status=$?; done
  if [ "$stopping" -eq 1 ]; then
    echo "monitor-supervisor: stopped after $restarts restart(s)" >&2
    exit 0
  fi
  elapsed_ms=$(( ($(date +%s%N) - started) / 1000000 ))
  if [ "$status" -gt 128 ]; then cause="signal $((status - 128))"; else cause="exit status $status"; fi
  if [ "$elapsed_ms" -lt 1000 ]; then fast_failures=$((fast_failures + 1)); else fast_failures=0; fi
  if [ "$fast_failures" -ge 5 ]; then
    echo "monitor-supervisor: the monitor failed 5 times within 1 s of starting ($cause); giving up" >&2
    exit "$([ "$status" -gt 0 ] && [ "$status" -le 128 ] && echo "$status" || echo 1)"
  fi
  restarts=$((restarts + 1))
  echo "monitor-supervisor: rockwatch-monitor ended ($cause) after ${elapsed_ms} ms; restart $restarts" >&2
done
