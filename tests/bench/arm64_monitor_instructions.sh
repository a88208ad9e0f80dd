#!/usr/bin/env bash
# aarch64 instructions per sample of rockwatch-monitor at 1 kHz, open loop and with --observer (docs/BENCHMARKS.md,
# "What a Raspberry Pi 4/5 costs per wall at 1 kHz"; issue 45): the cross-built monitor (scripts/cross-build.sh)
# runs offline under qemu-aarch64 with tests/bench/qemu_insn_count.c counting every guest instruction; the per-sample
# figure is (count over the whole log - count over its first second) / (samples - first second's samples), so
# start-up, the configuration and the summary cancel. Guest user-space instructions only: the kernel's share
# (reading the log, writing the output log) is not counted. The last column: the x86-64 monitor of X86_BUILD_DIR
# counted the same way by callgrind (when valgrind is installed).
# Input: set 1 X of the shipped suite resampled to 1 kHz (linear), PGA 0.25 g, model r_exp; the wall sensors
# (--observer) of a true wall with r_ana (x_mid, a_mid at 1 kHz, bias 2 mm, accelerometer noise 0.05 m/s^2).
#
#   tests/bench/arm64_monitor_instructions.sh X86_BUILD_DIR [ARM64_BUILD_DIR]   (default build/arm64)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
[ -d "$1" ] || { echo "arm64_monitor_instructions: $1 is not a directory (expected an x86-64 build directory)" >&2; exit 2; }
x86=$(cd "$1" && pwd)/host_tools/rockwatch
arm=$(cd "${2:-$root/build/arm64}" 2>/dev/null && pwd)/host_tools/rockwatch-monitor
[ -x "$x86" ] || { echo "arm64_monitor_instructions: $x86 missing (expected an x86-64 build directory)" >&2; exit 2; }
[ -x "$arm" ] || { echo "arm64_monitor_instructions: $arm missing (scripts/cross-build.sh --release builds it)" >&2; exit 2; }
# CI's port check leaves build/arm64 at -O1 (scripts/cross-build.sh --quick): not the figures of a release.
arm_cache=$(dirname "$(dirname "$arm")")/CMakeCache.txt
if grep -q '^CMAKE_CXX_FLAGS_RELEASE:[A-Z]*=-O1' "$arm_cache" 2>/dev/null; then
  echo "arm64_monitor_instructions: $arm was built at -O1 (CI's quick port check); scripts/cross-build.sh --release rebuilds it at -O3" >&2
  exit 2
fi
command -v qemu-aarch64 >/dev/null || { echo "arm64_monitor_instructions: qemu-aarch64 missing (scripts/install-deps.sh arm64)" >&2; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cc -shared -fPIC -O2 -o "$tmp/libinsn.so" "$root/tests/bench/qemu_insn_count.c"

suite=$root/sim/suites/npr9998-2015
/usr/bin/python3 "$root/tests/support/resample_1khz.py" "$suite/set01.txt" "$tmp/set01_x_1khz.txt"
rec=(--record "$tmp/set01_x_1khz.txt" --units mps2 --scale-pga 0.25)
"$x86" simulate "${rec[@]}" --r ana --sensors-out "$tmp/sensors.csv" --sensor-bias-m 0.002 \
  --sensor-accel-noise-mps2 0.05 >/dev/null
"$x86" replay "${rec[@]}" --rate 1000 --log "$tmp/open.lcmlog" >/dev/null
"$x86" replay "${rec[@]}" --rate 1000 --log "$tmp/observer.lcmlog" --wall-sensors "$tmp/sensors.csv" >/dev/null
# The first second of each log (events stamped within 1 s of the first).
for name in open observer; do
  /usr/bin/python3 - "$tmp/$name.lcmlog" "$tmp/${name}_1s.lcmlog" <<'PY'
import struct, sys
raw, out, pos, t0 = open(sys.argv[1], "rb").read(), bytearray(), 0, None
while pos < len(raw):
    _, _, t = struct.unpack_from(">Iqq", raw, pos)
    clen, dlen = struct.unpack_from(">ii", raw, pos + 20)
    end = pos + 28 + clen + dlen
    t0 = t if t0 is None else t0
    if t - t0 < 1000000:
        out += raw[pos:end]
    pos = end
open(sys.argv[2], "wb").write(out)
PY
done
count() {  # count LOG ARGS...: guest instructions of one offline run; prints "instructions samples"
  local log=$1; shift
  local err
  err=$(cd "$tmp" && qemu-aarch64 -plugin "$tmp/libinsn.so" "$arm" --offline-in "$log" --offline-out out.lcmlog "$@" 2>&1 >/dev/null)
  echo "$(sed -n 's/^insns: //p' <<<"$err") $(sed -n 's/.*samples: \([0-9]*\) received.*/\1/p' <<<"$err")"
}
x86_mon=$(dirname "$x86")/rockwatch-monitor
count_x86() {  # the same with callgrind on the x86-64 monitor (for comparison); "-" without valgrind
  local log=$1; shift
  command -v valgrind >/dev/null || { echo "- -"; return; }
  local err
  err=$(cd "$tmp" && valgrind --tool=callgrind --callgrind-out-file=/dev/null "$x86_mon" --offline-in "$log" \
        --offline-out out.lcmlog "$@" 2>&1 >/dev/null)
  echo "$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' <<<"$err") $(sed -n 's/.*samples: \([0-9]*\) received.*/\1/p' <<<"$err")"
}
printf '%-34s %12s %8s %14s %18s\n' "case (1 kHz, set 1 X 0.25 g)" "instructions" samples "per sample" "x86-64 per sample"
for c in "open loop (fixed point)|open|--rate 1000 --r exp" "open loop (double)|open|--rate 1000 --r exp --arith double" \
         "--observer (fixed point)|observer|--rate 1000 --r exp --observer"; do
  IFS='|' read -r label name args <<<"$c"
  read -r n_full s_full <<<"$(count "$name.lcmlog" $args)"
  read -r n_1s s_1s <<<"$(count "${name}_1s.lcmlog" $args)"
  [ -n "$n_full" ] && [ -n "$s_full" ] && [ -n "$n_1s" ] && [ -n "$s_1s" ] \
    || { echo "arm64_monitor_instructions: no count for $label (qemu plugin or the monitor's summary)" >&2; exit 1; }
  read -r x_full xs_full <<<"$(count_x86 "$name.lcmlog" $args)"
  read -r x_1s xs_1s <<<"$(count_x86 "${name}_1s.lcmlog" $args)"
  x_per=-
  if [ "$x_full" != - ] && [ -n "$x_full" ] && [ -n "$x_1s" ]; then
    x_per=$(printf '%.0f' "$(echo "($x_full - $x_1s) / ($xs_full - $xs_1s)" | bc -l)")
  fi
  printf '%-34s %12d %8d %14.0f %18s\n' "$label" "$n_full" "$s_full" "$(echo "($n_full - $n_1s) / ($s_full - $s_1s)" | bc -l)" "$x_per"
done
