#!/usr/bin/env bash
# ctest m4_replay: the firmware's engine on an emulated Cortex-M4 (scripts/m4-replay.sh) against the host's
# `rockwatch simulate --arith fixed --alarms` on the same input: the same alarm transitions at the same samples, the
# same x and xd at every sample (compare_m4_host.py), on a record that collapses, one that survives and one with a
# vertical component, another wall and sub-stepping. Then the checks' own negative controls (a shifted transition
# and a changed displacement must be reported), and the script's failure paths (bad options: simulate's message and
# exit 2; an image that is not one: exit 1 with a message; a run over its time limit: exit 1, bounded).
#
# Then issue 28's bounds (m4_cases.sh: a collapse, a chattering survivor and an observer case, at 200 Hz and resampled
# to 1 kHz, open loop and with the wall observer): every call within the worst call on paper that
# `rockwatch-monitor --print-config` prints for that rate and observer (core::worst_call_bound), no sample shed with
# the observer, and issue 28's targets: open loop every call <= 25 000 instructions; with the observer at 200 Hz
# every call <= 160 000 (a quarter of the period), at 1 kHz every call <= 32 000 and the median <= 12 000
# (docs/BENCHMARKS.md, "The metered observer").
#
#   m4_replay_check.sh ROCKWATCH_BINARY WORK_DIR ROCKWATCH_MONITOR_BINARY
# Exit status: 0 all identical; 1 a difference or failure; 77 arm-none-eabi-g++ or qemu-system-arm missing (SKIP).
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
here=$root/tests/firmware/m4
[[ $# -eq 3 ]] || { echo "usage: $0 ROCKWATCH_BINARY WORK_DIR ROCKWATCH_MONITOR_BINARY" >&2; exit 2; }
rockwatch=$1
work=$2
monitor=$3
python=/usr/bin/python3

for tool in "${ARM_GXX:-arm-none-eabi-g++}" "${QEMU_SYSTEM_ARM:-qemu-system-arm}"; do
  if ! command -v "$tool" >/dev/null; then
    echo "m4_replay: SKIPPED: $tool not found (scripts/install-deps.sh installs gcc-arm-none-eabi and qemu-system-arm)"
    exit 77
  fi
done
[[ -x $rockwatch ]] || { echo "m4_replay: $rockwatch is not executable" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"

# The image, once, in the build tree (not the source tree's build/m4-replay).
"$root/scripts/embedded-build.sh" --m4-replay "$work/image" >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
image=$work/image/rockwatch_m4_replay.elf
export ROCKWATCH=$rockwatch

suite=$root/sim/suites/npr9998-2015
records=$root/tests/data/records
failed=0
run_case() {
  local name=$1 expect=$2
  shift 2
  local dir=$work/$name
  mkdir -p "$dir"
  echo "== $name ($expect): $*"
  if ! "$root/scripts/m4-replay.sh" --m4-image "$image" --m4-trace "$dir/trace.csv" --m4-timeout 120 "$@" \
        >"$dir/m4.json" 2>"$dir/m4.err"; then
    cat "$dir/m4.err"
    echo "FAILED: m4-replay.sh"
    failed=1
    return
  fi
  "$rockwatch" simulate "$@" --arith fixed --alarms --json --out "$dir/history.csv" >"$dir/host.json"
  if ! "$python" "$here/compare_m4_host.py" "$dir/m4.json" "$dir/trace.csv" "$dir/host.json" "$dir/history.csv" "$expect"; then
    failed=1
  fi
  # The open-loop engine's bounded call (issue: the worst sample; core/work_meter.hpp): at most 25 000 M4
  # instructions and 3 x the median per call, no sample shed, no overrun (the observer's steps are not metered).
  # With --work-overflow finish on a record whose chatter fills the queue: overruns instead of shed samples, and the
  # cost model's units still bound every call's instructions (to within the call's own overhead).
  local policy=bounded
  [[ " $* " == *" --work-overflow finish "* ]] && policy=finish
  [[ " $* " == *" --work-overflow shed "* ]] && policy=shed
  if ! "$python" - "$dir/m4.json" "$dir/trace.csv" "$policy" <<'PY'
import csv, json, sys
j = json.load(open(sys.argv[1]))
if j["observer"]:
    sys.exit(0)
i, w = j["insn_per_sample"], j["carry_over"]
if sys.argv[3] == "finish":
    rows = list(csv.DictReader(open(sys.argv[2])))
    over = max(int(r["insn_step"]) - int(r["work_units"]) for r in rows)
    ok = w["shed_samples"] == 0 and w["overruns"] > 0 and i["max"] > 25000 and over <= 2500
    print("finish at a full queue: max %d M4 instructions a call, %d overruns, %d shed; instructions exceed the units "
          "charged by at most %d" % (i["max"], w["overruns"], w["shed_samples"], over))
    sys.exit(0 if ok else 1)
if sys.argv[3] == "shed":
    # The queue fills and the engine sheds: every call still within 25 000 instructions (the ratio to the median is
    # not checked: this wall rests most of the record, so its median is a resting sample's), and the image compared
    # every sample up to the first shed one.
    ok = i["max"] <= 25000 and w["shed_samples"] > 0 and w["first_shed_sample"] is not None and w["overruns"] == 0
    print("shed at a full queue: max %d M4 instructions a call (%.2f x the median %d), %d shed from sample %s" % (
        i["max"], i["max"] / i["median"], i["median"], w["shed_samples"], w["first_shed_sample"]))
    sys.exit(0 if ok else 1)
ok = i["max"] <= 25000 and i["max"] <= 3 * i["median"] and w["shed_samples"] == 0 and w["overruns"] == 0
print("bounded call: max %d M4 instructions (%.2f x the median %d); carry-over: %d samples late, at most %d calls, "
      "%d shed, %d overruns" % (i["max"], i["max"] / i["median"], i["median"], w["late_samples"], w["max_late_calls"],
                                w["shed_samples"], w["overruns"]))
sys.exit(0 if ok else 1)
PY
  then
    echo "FAILED: the bound on a call ($name)"
    failed=1
  fi
}

run_case set01_x_0.40g collapse --suite "$suite" --set 1 --component X --scale-pga 0.40
run_case set01_x_0.20g survive --suite "$suite" --set 1 --component X --scale-pga 0.20
# A wall settling at r_ana whose chatter fills the engine's queue: with the default policy, which keeps every call
# within the budget, and with the one that keeps every answer.
run_case set01_x_0.12g_ana_shed survive --suite "$suite" --set 1 --component X --scale-pga 0.12 --r ana \
  --work-overflow shed
run_case set01_x_0.12g_ana_finish survive --suite "$suite" --set 1 --component X --scale-pga 0.12 --r ana \
  --work-overflow finish
# El Centro (dt 0.01 s, so two steps per sample), with its vertical, a thicker, shorter wall, r_ana, kappa 1.5.
# The wall observer on the target: wall sensors synthesised from a truth run whose restitution differs from the
# model's (r_ana against the engine's r_exp), with a transducer offset and a mid-height accelerometer.
mkdir -p "$work/observer_truth"
"$rockwatch" simulate --suite "$suite" --set 1 --component X --scale-pga 0.25 --r ana \
  --sensors-out "$work/observer_truth/sensors.csv" --sensor-bias-m 0.002 --sensor-accel-noise-mps2 0.05 >/dev/null
run_case set01_x_0.25g_observer any --suite "$suite" --set 1 --component X --scale-pga 0.25 --r exp \
  --wall-sensors "$work/observer_truth/sensors.csv"
# The trajectory compared above is the fused one only if the observer did fuse: the host's updates must be there.
if [[ -f $work/set01_x_0.25g_observer/m4.json ]] &&
   ! "$python" - "$work/set01_x_0.25g_observer" <<'PY'
import json, sys
d = sys.argv[1]
m4, host = json.load(open(d + "/m4.json")), json.load(open(d + "/host.json"))
o = host["observer"]
ok = m4["observer"] and o["n_updates"] > 100 and o["n_accel_updates"] > 100 and abs(o["bias_estimate_m"] - 0.002) < 5e-4
print("observer on the target: %d displacement and %d acceleration updates, offset %.4f m (0.002 given), r %.4f" % (
    o["n_updates"], o["n_accel_updates"], o["bias_estimate_m"], o["r_estimate"]))
sys.exit(0 if ok else 1)
PY
then
  echo "FAILED: the observer case did not fuse the wall sensors"
  failed=1
fi
# Issue 40's settings reach the image (engine-input keys 37-52; before them it ran their defaults): the look-ahead
# horizon, model doubt at a low level, the model-form σ and the capacity minimums, on the observer case at 0.30 g.
# The case is compared as above, and must tell: the host's trajectory without the settings differs from it.
issue40=(--imminent-horizon 0.17 --observer-doubt-nis 1.5 --observer-model-form-sigma 0.05
         --observer-doubt-model-form-sigma 0.3 --observer-capacity-min-x 0.1 --observer-doubt-capacity-min-x 0.2
         --observer-quiet-motion-noises 30)
run_case set01_x_0.30g_observer_issue40 any --suite "$suite" --set 1 --component X --scale-pga 0.30 --r exp \
  --wall-sensors "$work/observer_truth/sensors.csv" "${issue40[@]}"
d40=$work/set01_x_0.30g_observer_issue40
if [[ -f $d40/history.csv ]]; then
  "$rockwatch" simulate --suite "$suite" --set 1 --component X --scale-pga 0.30 --r exp \
    --wall-sensors "$work/observer_truth/sensors.csv" --arith fixed --alarms --json --out "$d40/history_defaults.csv" \
    >"$d40/host_defaults.json"
  if cmp -s "$d40/history.csv" "$d40/history_defaults.csv"; then
    echo "FAILED: issue 40's settings do not change the host's trajectory on $d40: the case cannot tell"
    failed=1
  else
    echo "issue 40's settings change the trajectory (the image ran them: compared above)"
  fi
fi
run_case elcentro_vertical_wall any --record "$records/RSN6_IMPVALL.I_I-ELC180-hor1.AT2" \
  --vertical "$records/RSN6_IMPVALL.I_I-ELC-UP.AT2" --scale-pga 0.3 --b 0.12 --h1 1.6 --h2 1.5 --r ana --kappa 1.5 \
  --t-end 12

# The profiler (--m4-profile): the collapse case's worst sample, in a second run. The addresses it records must
# number about the step's instructions over the sampling interval (97.66 instructions, plus the handler's own ~13
# per tick), and the shares name functions of the image.
if [[ -f $work/set01_x_0.40g/m4.json ]]; then
  worst=$("$python" -c 'import json,sys; print(json.load(open(sys.argv[1]))["insn_per_sample"]["max_sample"])' \
          "$work/set01_x_0.40g/m4.json")
  if "$root/scripts/m4-replay.sh" --m4-image "$image" --m4-profile "$worst" --m4-timeout 120 --suite "$suite" --set 1 \
       --component X --scale-pga 0.40 >"$work/profile.json" 2>"$work/profile.err" &&
     "$python" - "$work/profile.json" "$worst" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
p = j["profile"]
insn = j["insn_per_sample"]["max"]
ok = (p["sample"] == int(sys.argv[2]) and p["insn"] == insn and insn / 97.66 <= p["addresses"] <= insn / 70.0
      and 0.5 < sum(f["share"] for f in p["functions"]) <= 1.0001
      and not any(f["function"].startswith("0x") for f in p["functions"][:5]))
print("profile of sample %d (%d instructions, %d addresses): %s" % (
    p["sample"], insn, p["addresses"],
    ", ".join("%s %.1f %%" % (f["function"].split("::")[-1], 100 * f["share"]) for f in p["functions"][:4])))
sys.exit(0 if ok else 1)
PY
  then :; else
    cat "$work/profile.err"
    echo "FAILED: the profile of sample $worst"
    failed=1
  fi
fi

# Negative controls: the comparison must see a transition one sample late and a displacement one ulp off.
control=$work/set01_x_0.40g
if [[ -f $control/m4.json ]]; then
  "$python" - "$control" <<'PY'
import json, struct, sys
d = sys.argv[1]
m4 = json.load(open(d + "/m4.json"))
m4["transitions"][-1]["sample"] += 1
json.dump(m4, open(d + "/m4_shifted.json", "w"))
rows = open(d + "/trace.csv").read().splitlines()
f = rows[500].split(",")
x = float(f[4])
f[4] = repr(struct.unpack("<d", struct.pack("<q", struct.unpack("<q", struct.pack("<d", x))[0] + 1))[0])
rows[500] = ",".join(f)
open(d + "/trace_ulp.csv", "w").write("\n".join(rows) + "\n")
PY
  for variant in "m4_shifted.json trace.csv" "m4.json trace_ulp.csv"; do
    read -r j t <<<"$variant"
    if "$python" "$here/compare_m4_host.py" "$control/$j" "$control/$t" "$control/host.json" "$control/history.csv" \
         collapse >"$work/control.out"; then
      echo "FAILED: the comparison accepted a perturbed replay ($j, $t)"
      failed=1
    else
      echo "negative control ($j, $t): $(cat "$work/control.out")"
    fi
  done
fi

# Failure paths of the script.
set +e
"$root/scripts/m4-replay.sh" --m4-image "$image" --suite "$suite" --set 1 --component X --scale-pga -1 \
  >"$work/bad.out" 2>"$work/bad.err"
status=$?
set -e
if [[ $status -ne 2 ]] || ! grep -q "rockwatch simulate: error: --scale-pga" "$work/bad.err" || [[ -s $work/bad.out ]]; then
  echo "FAILED: a bad option gave status $status: $(cat "$work/bad.err")"
  failed=1
else
  echo "bad option: status 2: $(cat "$work/bad.err")"
fi
printf 'not an image\n' >"$work/not_an_image.elf"
set +e
"$root/scripts/m4-replay.sh" --m4-image "$work/not_an_image.elf" --m4-timeout 20 --suite "$suite" --set 1 \
  --component X --scale-pga 0.2 >"$work/bad_image.out" 2>"$work/bad_image.err"
status=$?
set -e
if [[ $status -ne 1 ]] || [[ -s $work/bad_image.out ]] || ! grep -q "^m4-replay: " "$work/bad_image.err"; then
  echo "FAILED: a file that is no image gave status $status: $(cat "$work/bad_image.err")"
  failed=1
else
  echo "not an image: status 1: $(tail -n 1 "$work/bad_image.err")"
fi
# A run that cannot finish in time: 600 s of input (120 001 samples, about 12 s of emulation) with a 1 s limit is stopped, status 1.
set +e
start=$(date +%s)
"$root/scripts/m4-replay.sh" --m4-image "$image" --m4-timeout 1 --suite "$suite" --set 1 --component X \
  --scale-pga 0.2 --t-end 600 >"$work/slow.out" 2>"$work/slow.err"
status=$?
elapsed=$(( $(date +%s) - start ))
set -e
if [[ $status -ne 1 ]] || ! grep -q "did not finish within 1 s" "$work/slow.err" || [[ $elapsed -gt 30 ]]; then
  echo "FAILED: a run over its time limit gave status $status after $elapsed s: $(cat "$work/slow.err")"
  failed=1
else
  echo "time limit: status 1 after $elapsed s: $(tail -n 1 "$work/slow.err")"
fi

# Issue 28's records and bounds.
if ! "$here/m4_cases.sh" "$rockwatch" "$image" "$work/issue28" >"$work/issue28.txt" 2>"$work/issue28.err"; then
  cat "$work/issue28.err" "$work/issue28.txt"
  echo "FAILED: m4_cases.sh"
  failed=1
else
  for rate in 200 1000; do
    for observer in "" --observer; do
      "$monitor" --print-config --rate "$rate" $observer >"$work/issue28/config_${rate}${observer}.json"
    done
  done
  if ! "$python" - "$work/issue28" <<'PY'
import json, os, sys
d = sys.argv[1]
bounds = {}
for rate, tag in ((200, "200hz"), (1000, "1khz")):
    for mode, suffix in (("open", ""), ("observer", "--observer")):
        bounds[(tag, mode)] = json.load(open(os.path.join(d, "config_%d%s.json" % (rate, suffix))))["worst_call"]
ok = True
# Every (case, mode) pair of m4_cases.sh must have run (issue 42: a missing m4.json is a failure, not skipped): its 3
# cases at 2 rates, open loop and with the observer, 12 pairs; and no case the list below does not know.
expected = ["%s_%s" % (n, r) for n in ("collapse", "chatter", "observer") for r in ("200hz", "1khz")]
found = sorted(c for c in os.listdir(d) if os.path.isdir(os.path.join(d, c)) and c != "records")  # records: its inputs
if found != sorted(expected):
    print("FAILED: the cases run %s are not m4_cases.sh's %s" % (found, sorted(expected)))
    ok = False
pairs = 0
for case in sorted(expected):
    for mode in ("open", "observer"):
        path = os.path.join(d, case, mode, "m4.json")
        if not os.path.isfile(path):
            print("%-14s %-8s FAILED: no m4.json (the pair did not run)" % (case, mode))
            ok = False
            continue
        pairs += 1
        tag = case.rsplit("_", 1)[1]
        j = json.load(open(path))
        i, w = j["insn_per_sample"], j["carry_over"]
        bound = bounds[(tag, mode)]["bound_m4_instructions"]
        checks = [("every call within the bound on paper %d" % bound, i["max"] <= bound)]
        if mode == "open":
            checks.append(("every call <= 25 000", i["max"] <= 25000))
        else:
            checks.append(("no sample shed", w["shed_samples"] == 0))
            if tag == "200hz":
                checks.append(("every call <= 160 000", i["max"] <= 160000))
            else:
                checks.append(("every call <= 32 000", i["max"] <= 32000))
                checks.append(("median <= 12 000", i["median"] <= 12000))
        failed = [c for c, good in checks if not good]
        ok = ok and not failed
        print("%-14s %-8s median %7d p99 %7d max %7d, shed %d, late %d: %s" % (
            case, mode, i["median"], i["p99"], i["max"], w["shed_samples"], w["late_samples"],
            "FAILED " + "; ".join(failed) if failed else "ok (" + "; ".join(c for c, _ in checks) + ")"))
print("%d of %d (case, mode) pairs ran and were checked" % (pairs, 2 * len(expected)))
sys.exit(0 if ok and pairs == 2 * len(expected) else 1)
PY
  then
    echo "FAILED: issue 28's bounds"
    failed=1
  fi
fi

[[ $failed -eq 0 ]] && echo "m4_replay: all identical" || echo "m4_replay: FAILED"
exit $failed
