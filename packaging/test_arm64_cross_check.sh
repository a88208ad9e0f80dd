#!/usr/bin/env bash
# ctest arm64_cross_check (issue 45; docs/packaging.md "64-bit ARM"): the aarch64 cross build of rockwatch and
# rockwatch-monitor (build/arm64: scripts/cross-build.sh, a no-op when CI's build stage made it current) run under
# qemu-aarch64 against this tree's x86-64 programs on the same inputs:
#   simulate --json: the double engine and the fixed-point one with the alarm, the full model, the wall observer
#   rockwatch-monitor --offline-in: the golden log (fixed point; and --arith double --model full) and an observer log
# Verdicts, alarm transitions, counts and strings identical; every other number (max |x| among them) within 1e-12
# relative (packaging/arm64_compare.py). Without the cross toolchain or qemu-aarch64: skipped (exit 77) saying
# what is missing, failed under CI=true (tests/support/missing_under_ci.sh).
#   packaging/test_arm64_cross_check.sh X86_BUILD_DIR SOURCE_DIR
set -euo pipefail
if [ $# -ne 2 ]; then echo "usage: test_arm64_cross_check.sh X86_BUILD_DIR SOURCE_DIR" >&2; exit 2; fi
build="$(cd "$1" && pwd)" src="$(cd "$2" && pwd)"
fail() { echo "arm64_cross_check: FAIL: $*" >&2; exit 1; }
missing=()
for tool in aarch64-linux-gnu-g++ aarch64-linux-gnu-pkg-config qemu-aarch64 ninja cmake; do
  command -v "$tool" >/dev/null || missing+=("$tool")
done
[ -e /lib/ld-linux-aarch64.so.1 ] || missing+=("libc6:arm64")
[ -f "$src/build/arm64/sysroot/usr/lib/aarch64-linux-gnu/pkgconfig/lcm.pc" ] || missing+=("liblcm for arm64 in build/arm64/sysroot")
if [ ${#missing[@]} -gt 0 ]; then
  exec "$src/tests/support/missing_under_ci.sh" \
    "arm64_cross_check: ${missing[*]} missing (scripts/install-deps.sh arm64 installs them)"
fi
x86_rw="$build/host_tools/rockwatch" x86_mon="$build/host_tools/rockwatch-monitor"
[ -x "$x86_rw" ] && [ -x "$x86_mon" ] || fail "$x86_rw or $x86_mon missing: build this tree first"

t0=$(date +%s.%N)
"$src/scripts/cross-build.sh" --no-deps >/tmp/arm64_cross_build.$$.log 2>&1 \
  || { cat /tmp/arm64_cross_build.$$.log; rm -f /tmp/arm64_cross_build.$$.log; fail "scripts/cross-build.sh"; }
tail -n 1 /tmp/arm64_cross_build.$$.log; rm -f /tmp/arm64_cross_build.$$.log
arm_rw="$src/build/arm64/host_tools/rockwatch" arm_mon="$src/build/arm64/host_tools/rockwatch-monitor"
readelf -h "$arm_rw" | grep -q 'Machine: *AArch64' || fail "$arm_rw is not an aarch64 program (readelf -h)"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/x86" "$tmp/arm"
suite="$src/sim/suites/npr9998-2015"
compare="/usr/bin/python3 $src/packaging/arm64_compare.py"
qemu_s=0
# run NAME rockwatch|monitor ARGS...: the x86-64 program and the aarch64 one (under qemu) in their own directories, same arguments.
run() {
  local name="$1" prog="$2"; shift 2
  local x86="$x86_rw" arm="$arm_rw"
  if [ "$prog" = monitor ]; then x86="$x86_mon" arm="$arm_mon"; fi
  (cd "$tmp/x86" && "$x86" "$@" >"$name.out" 2>"$name.err") || { cat "$tmp/x86/$name.err"; fail "x86-64 $name"; }
  local a b
  a=$(date +%s.%N)
  (cd "$tmp/arm" && qemu-aarch64 "$arm" "$@" >"$name.out" 2>"$name.err") || { cat "$tmp/arm/$name.err"; fail "aarch64 $name (qemu)"; }
  b=$(date +%s.%N)
  qemu_s=$(echo "$qemu_s + $b - $a" | bc)
  $compare --label "$name" "$tmp/x86/$name.out" "$tmp/arm/$name.out" || fail "$name: the aarch64 output differs"
}

# The wall sensors of a true wall (r_ana, biased transducer) for the observer cases, made once by the x86-64 build.
rec3=(--suite "$suite" --set 3 --component X --scale-pga 0.25)
"$x86_rw" simulate "${rec3[@]}" --r ana --sensors-out "$tmp/sensors.csv" --sensor-bias-m 0.002 --sensor-seed 7 >/dev/null
cp "$tmp/sensors.csv" "$tmp/x86/" && cp "$tmp/sensors.csv" "$tmp/arm/"
rec1=(--suite "$suite" --set 1 --component X --scale-pga 0.40)
run simulate_double rockwatch simulate "${rec1[@]}" --alarms --json
run simulate_fixed rockwatch simulate "${rec1[@]}" --arith fixed --alarms --json
run simulate_full rockwatch simulate --suite "$suite" --set 2 --component Y --scale-pga 0.30 --model full --alarms --json
run simulate_observer rockwatch simulate "${rec3[@]}" --r exp --arith fixed --alarms --wall-sensors sensors.csv --json

# The monitor offline: the golden log, and a log with the same true wall's sensors (rockwatch replay --log).
golden="$src/tests/data/monitor/set01_X_0.40g_200Hz.lcmlog"
"$x86_rw" replay "${rec3[@]}" --log "$tmp/obs_in.lcmlog" --wall-sensors "$tmp/sensors.csv" --json >/dev/null
run monitor_fixed monitor --offline-in "$golden" --offline-out out_fixed.lcmlog
run monitor_double monitor --offline-in "$golden" --offline-out out_double.lcmlog --arith double --model full
run monitor_observer monitor --offline-in "$tmp/obs_in.lcmlog" --offline-out out_observer.lcmlog --observer --r exp
for m in fixed double observer; do
  $compare --lcm-logs --label "monitor_$m log" "$tmp/x86/out_$m.lcmlog" "$tmp/arm/out_$m.lcmlog" \
    || fail "monitor_$m: the aarch64 monitor's output log differs"
done
echo "arm64_cross_check: 7 cases equal (1e-12 relative); qemu-aarch64 runs $(printf '%.1f' "$qemu_s") s; total $(printf '%.0f' "$(echo "$(date +%s.%N) - $t0" | bc)") s"
echo "arm64_cross_check: OK"
