#!/usr/bin/env bash
# The firmware on the wire (issue 43): the monitor image (firmware/embedded/m4_monitor/: firmware::MonitorLoop with
# the fixed-point WallEngine, and the wall observer with --observer, behind a LAN9118 driver and the image's own
# IPv4/UDP path) booted on QEMU's mps2-an386 board with its LAN9118 on a network this script owns: QEMU's socket
# network (each Ethernet frame one UDP datagram on 127.0.0.1) bridged by scripts/m4-monitor-run.py to the LCM URL's
# multicast group. Prints `lcm-url: URL` when the image listens; `rockwatch replay --lcm-url URL` drives it,
# `rockwatch dashboard --lcm-url URL` shows it (it publishes what rockwatch-monitor publishes: wall_state_t,
# alarm_event_t, monitor_status_t once per second, wall_estimate_t with the observer). On SIGINT/SIGTERM (or after
# --m4-duration) it stops QEMU and prints one JSON object.
#
#   scripts/m4-monitor.sh [--lcm-url URL] [--m4-image ELF] [--m4-duration S] [--m4-work DIR] MONITOR_OPTIONS...
#     MONITOR_OPTIONS  rockwatch-monitor's own (checked by `rockwatch-monitor --print-config`, whose settings the image
#                      runs): --config, --wall-file, the wall (--b --h1 ...), --r, --kappa, the alarm options, --rate,
#                      --max-step, --observer, --work-budget, --work-overflow, --clock-tolerance. Not for the image:
#                      --arith double, --model full, walls, --forecast, --accept-from, --log, --offline-in/out.
#                      Every wall, alarm and observer key of the settings reaches the image (firmware::EngineInputKey;
#                      the config file's observer keys, alarm.imminent_horizon_s); one the runner cannot pass fails
#                      (exit 2, naming it) rather than the image running its default (ctest m4_monitor_config).
#     --lcm-url URL    udpm://GROUP:PORT?ttl=0 (default: the default group on a free port, printed)
#     --m4-image ELF   run this image instead of build/m4-monitor/rockwatch_m4_monitor.elf (rebuilt when a source
#                      is newer)
#     --m4-duration S  stop by itself after S seconds (default: only on SIGINT/SIGTERM)
#     --m4-work DIR    keep the run's files there (configuration, the image's output, QEMU's log); default a
#                      temporary directory, removed
#     --m4-hostile-frames  (tests) once the image listens, send it 12 malformed frames below UDP, each one of the
#                      receive path's reject classes (not IPv4, IPv4 malformed, fragments, not UDP, not for the
#                      group and port, UDP malformed); bridge.hostile_frames says how many of each were sent
# Output keys: machine, observer, frames_received (Ethernet frames the NIC delivered), datagrams_received (UDP
# datagrams for the group and port), samples_received, samples_processed, gaps, duplicates, out_of_order,
# transitions [{input_seq, level}], insn_per_sample {median, p99, max} (per ground message: from the NIC's RX FIFO to
# on_message()'s return, every output frame sent), receive_insn_per_sample (the receive part alone: driver, IPv4/UDP,
# LCM reassembly), insn_per_sensor_datagram, insn_per_other_datagram, engine_insn_per_sample (the part in the
# engine's calls), image_overhead_insn_per_sample and image_overhead_insn_per_sensor_datagram (the rest: the image's
# own part of the call), declared_call_overhead_insn (what the image declares to the engine, taken off the observer's
# budget: kImageCallOverheadUnits), overhead_insn, counters (the image's: NIC, IPv4/UDP, LCM layer, MonitorCounters),
# bridge.
# Environment: ROCKWATCH_MONITOR (default build/release/host_tools/rockwatch-monitor, else on PATH),
#              QEMU_SYSTEM_ARM (default qemu-system-arm), ARM_GXX (see embedded-build.sh).
# Exit status: 0 printed; 1 build, emulation or image failure (with a message); 2 invalid options (rockwatch-monitor's
# message); 77 arm-none-eabi-g++ or qemu-system-arm not installed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
python=/usr/bin/python3

help_text() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }
usage() { help_text >&2; exit 2; }

image="" duration=0 work_keep="" lcm_url=""
mon_args=()
hostile_frames=()
while [[ $# -gt 0 ]]; do
  case $1 in
    --m4-image) [[ $# -ge 2 ]] || usage; image=$2; shift 2 ;;
    --m4-duration)
      [[ $# -ge 2 && $2 =~ ^[1-9][0-9]*$ ]] || { echo "m4-monitor: --m4-duration needs whole seconds > 0" >&2; exit 2; }
      duration=$2; shift 2 ;;
    --m4-work) [[ $# -ge 2 && -n $2 ]] || { echo "m4-monitor: --m4-work needs a directory" >&2; exit 2; }
      work_keep=$2; shift 2 ;;
    --lcm-url) [[ $# -ge 2 && -n $2 ]] || { echo "m4-monitor: --lcm-url needs a URL, e.g. udpm://239.255.76.67:7667?ttl=0" >&2; exit 2; }
      lcm_url=$2; shift 2 ;;
    --lcm-url=*) lcm_url=${1#--lcm-url=}; shift ;;
    --m4-hostile-frames) hostile_frames=(--hostile-frames); shift ;;
    -h|--help) help_text; exit 0 ;;
    --log|--log=*|--offline-in|--offline-in=*|--offline-out|--offline-out=*|--forecast|--forecast=*|--accept-from|--accept-from=*|--receive-path|--receive-path=*|--print-config|--version)
      echo "m4-monitor: ${1%%=*} is not available for the image" >&2; exit 2 ;;
    *) mon_args+=("$1"); shift ;;
  esac
done

qemu=${QEMU_SYSTEM_ARM:-qemu-system-arm}
if ! command -v "$qemu" >/dev/null; then
  echo "m4-monitor: SKIPPED: $qemu not found (Debian: qemu-system-arm; scripts/install-deps.sh installs it)" >&2
  exit 77
fi
monitor=${ROCKWATCH_MONITOR:-$root/build/release/host_tools/rockwatch-monitor}
if [[ ! -x $monitor ]]; then
  monitor=$(command -v rockwatch-monitor || true)
  [[ -n $monitor ]] || { echo "m4-monitor: no rockwatch-monitor binary: build it (cmake --build build/release --target rockwatch-monitor) or set ROCKWATCH_MONITOR" >&2; exit 1; }
fi
if [[ -z $lcm_url ]]; then
  port=$("$python" -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("", 0)); print(s.getsockname()[1])')
  lcm_url="udpm://239.255.76.67:$port?ttl=0"
fi

if [[ -n $work_keep ]]; then
  mkdir -p "$work_keep"
  work=$(cd "$work_keep" && pwd)
else
  work=$(mktemp -d "${TMPDIR:-/tmp}/m4-monitor.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi

# 1. The settings, as rockwatch-monitor runs them (its own messages and status for bad options).
set +e
"$monitor" "${mon_args[@]}" --lcm-url "$lcm_url" --print-config >"$work/print-config.json" 2>"$work/print-config.err"
status=$?
set -e
if [[ $status -ne 0 ]]; then
  cat "$work/print-config.err" >&2
  exit "$status"
fi

# 2. The image: built unless given, and rebuilt when a source it depends on is newer (m4-monitor-image.sh; its exit
# status passed on: 77 when arm-none-eabi-g++ is missing, saying so).
if [[ -z $image ]]; then
  image=$root/build/m4-monitor/rockwatch_m4_monitor.elf
  "$root/scripts/m4-monitor-image.sh" "$root/build/m4-monitor" >&2 || exit $?
fi
[[ -f $image ]] || { echo "m4-monitor: image $image not found" >&2; exit 1; }
if [[ $(head -c 4 "$image" | od -An -tx1 | tr -d ' \n') != 7f454c46 ]]; then
  echo "m4-monitor: $image is not an ELF image (build it with scripts/embedded-build.sh --m4-monitor)" >&2
  exit 1
fi
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")

# 3. QEMU, the bridge, the JSON (SIGINT/SIGTERM reach the runner, which stops QEMU and prints).
trap '' INT TERM  # the runner handles them; this shell only waits for it
"$python" "$root/scripts/m4-monitor-run.py" --image "$image" --qemu "$qemu" --print-config "$work/print-config.json" \
  --lcm-url "$lcm_url" --work "$work" --timeout "$duration" "${hostile_frames[@]}" &
runner=$!
trap 'kill -INT $runner 2>/dev/null || true' INT TERM
status=0
while true; do
  set +e
  wait "$runner"
  status=$?
  set -e
  # wait returns early (> 128) when a trapped signal arrives; the runner is still finishing.
  if kill -0 "$runner" 2>/dev/null; then continue; fi
  break
done
exit "$status"
