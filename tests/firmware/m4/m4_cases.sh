#!/usr/bin/env bash
# The records of issue 28's bounds on the emulated Cortex-M4, open loop and with the wall observer, at the suite's
# own 200 Hz and resampled to 1 kHz: a collapse (set 1 X 0.40 g), a chattering survivor (set 1 X 0.12 g at r_ana) and
# an observer case whose true wall differs from the model (set 1 X 0.25 g: sensors of an r_ana wall, model r_exp).
# The wall sensors of each record come from a truth run with a modified wall (`rockwatch simulate --sensors-out`:
# a 2 mm transducer offset, a mid-height accelerometer, and r_ana, or a 2 % thinner wall for the r_ana record).
# Runs scripts/m4-replay.sh on each (two at a time) and writes DIR/NAME/m4.json and DIR/NAME/trace.csv per case, then
# prints one line per case: name, rate, observer, median, p99, max, shed, overruns, late samples.
#
#   m4_cases.sh ROCKWATCH IMAGE DIR [NAME_FILTER]
# Exit status: 0 every case ran; 1 a run failed.
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
[[ $# -ge 3 ]] || { echo "usage: $0 ROCKWATCH IMAGE DIR [NAME_FILTER]" >&2; exit 2; }
rockwatch=$1 image=$2 dir=$3 filter=${4:-}
python=/usr/bin/python3
suite=$root/sim/suites/npr9998-2015
mkdir -p "$dir/records"

# Set 1 X resampled to 1 kHz (linear between the 5 ms samples): one 1 ms sub-step per sample.
khz=$dir/records/set01_x_1khz.txt
"$python" "$root/tests/support/resample_1khz.py" "$suite/set01.txt" "$khz"

# name|model options|truth options (each with the record)
cases=(
  "collapse|--scale-pga 0.40|--scale-pga 0.40 --r ana"
  "chatter|--scale-pga 0.12 --r ana|--scale-pga 0.12 --r ana --b 0.098"
  "observer|--scale-pga 0.25 --r exp|--scale-pga 0.25 --r ana"
)
rates=("200hz|--suite $suite --set 1 --component X" "1khz|--record $khz --units mps2")

jobs_file=$dir/jobs.txt
: >"$jobs_file"
for c in "${cases[@]}"; do
  IFS='|' read -r name model truth <<<"$c"
  for r in "${rates[@]}"; do
    IFS='|' read -r rate record <<<"$r"
    case_name=${name}_$rate
    [[ -z $filter || $case_name == *$filter* ]] || continue
    mkdir -p "$dir/$case_name"
    # shellcheck disable=SC2086
    "$rockwatch" simulate $record $truth --sensors-out "$dir/$case_name/sensors.csv" --sensor-bias-m 0.002 \
      --sensor-accel-noise-mps2 0.05 >/dev/null
    echo "$case_name open $record $model" >>"$jobs_file"
    echo "$case_name observer $record $model --wall-sensors $dir/$case_name/sensors.csv" >>"$jobs_file"
  done
done

run_one() {  # CASE MODE OPTIONS...
  local case_name=$1 mode=$2
  shift 2
  local out=$dir/$case_name/$mode
  mkdir -p "$out"
  if ROCKWATCH=$rockwatch "$root/scripts/m4-replay.sh" --m4-image "$image" --m4-trace "$out/trace.csv" \
       --m4-timeout 300 "$@" >"$out/m4.json" 2>"$out/m4.err"; then
    echo ok >"$out/status"
  else
    echo failed >"$out/status"
    cat "$out/m4.err" >&2
  fi
}
export -f run_one
export root rockwatch image dir
xargs -P 2 -L 1 bash -c 'run_one "$@"' _ <"$jobs_file"

status=0
while read -r case_name mode _; do
  out=$dir/$case_name/$mode
  if [[ $(cat "$out/status") != ok ]]; then
    echo "$case_name $mode FAILED"
    status=1
    continue
  fi
  "$python" - "$out/m4.json" "$case_name" "$mode" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
i, w = j["insn_per_sample"], j["carry_over"]
print("%-16s %-8s samples %6d median %7d p99 %7d max %7d (sample %d) shed %d overruns %d late %d (at most %d calls)" % (
    sys.argv[2], sys.argv[3], j["samples"], i["median"], i["p99"], i["max"], i["max_sample"], w["shed_samples"],
    w["overruns"], w["late_samples"], w["max_late_calls"]))
PY
done <"$jobs_file"
exit $status
