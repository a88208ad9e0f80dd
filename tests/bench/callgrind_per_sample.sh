#!/usr/bin/env bash
# Per-sample instruction counts of the fixed-point engine and, for comparison, the double engine, counted exactly
# by callgrind (bench_sample_instructions: one dump per measured call; see that file). Input: set 1, component X of
# the shipped suite at PGA 0.2 g (4000 samples at 200 Hz, rocking with impacts). Prints, per pass, the distribution
# of instructions per sample: min, median, p99, max (and the sample where it occurs) and max/median. The constant
# cost of the measurement window (an empty call, row `overhead`) is subtracted from the other rows.
#
#   tests/bench/callgrind_per_sample.sh BUILD_DIR [--check MAX_MEDIAN_RATIO MAX_INSTR] [--record SET_FILE] [--observer]
#     BUILD_DIR  CMake build directory holding tests/bench/bench_sample_instructions (e.g. build/release)
#     --check    exit 1 if, for fixed_step or fixed_process, max > MAX_MEDIAN_RATIO × median or max > MAX_INSTR
#     --observer the engines through the monitor's seam with the wall observer off and on instead
#                (bench_observer_instructions: fixed_off, fixed_observer, double_off, double_observer)
#   Environment: CALLGRIND_OUT_DIR keeps callgrind.out there (one part per sample) instead of a temporary directory.
# Exit status: 0 report printed (and checks passed); 1 check failed or run failed; 2 usage; 77 valgrind missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)

usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[[ $# -ge 1 ]] || usage
build_dir=$1
shift
check_ratio="" check_max="" record=$root/sim/suites/npr9998-2015/set01.txt observer=0
while [[ $# -gt 0 ]]; do
  case $1 in
    --check) [[ $# -ge 3 ]] || usage; check_ratio=$2; check_max=$3; shift 3 ;;
    --record) [[ $# -ge 2 ]] || usage; record=$2; shift 2 ;;
    --observer) observer=1; shift ;;
    *) usage ;;
  esac
done

if ! command -v valgrind >/dev/null; then
  echo "callgrind_per_sample: SKIPPED: valgrind not found (Debian: valgrind; scripts/install-deps.sh installs it)" >&2
  exit 77
fi
driver=bench_sample_instructions
passes="fixed_step fixed_process double_step double_process overhead"
if [[ $observer -eq 1 ]]; then
  driver=bench_observer_instructions
  passes="fixed_off fixed_observer double_off double_observer overhead"
fi
exe=$build_dir/tests/bench/$driver
[[ -x $exe ]] || { echo "error: $exe not found; build the $driver target first" >&2; exit 1; }

if [[ -n ${CALLGRIND_OUT_DIR:-} ]]; then
  out_dir=$CALLGRIND_OUT_DIR
  mkdir -p "$out_dir"
else
  out_dir=$(mktemp -d)
  trap 'rm -rf "$out_dir"' EXIT
fi
out=$out_dir/callgrind.out.per_sample

echo "record: ${record#"$root"/} (X, scaled to PGA 0.2 g), paper wall, linear model, r_exp, kappa 2, dt 5 ms"
if ! valgrind --tool=callgrind --collect-atstart=no --combine-dumps=yes --dump-line=no --dump-instr=no \
      --callgrind-out-file="$out" "$exe" "$record" 2>"$out_dir/stderr.log"; then
  cat "$out_dir/stderr.log" >&2
  echo "error: callgrind run of $exe failed" >&2
  exit 1
fi
grep -v '^==' "$out_dir/stderr.log" || true
echo

# One "summary:" per dump part, labelled by the preceding "desc: Trigger: Client Request: PASS".
awk '
  /^desc: Trigger: Client Request: / { label = $NF; next }
  /^desc: Trigger: / { label = ""; next }
  /^summary: / { if (label != "") { idx[label]++; print label, idx[label], $2 } }
' "$out" >"$out_dir/samples.txt"

# Statistics per pass (POSIX awk + sort): nearest-rank percentiles of the counts minus the overhead row's median.
values() { awk -v l="$1" -v o="$2" '$1 == l { print $3 - o }' "$out_dir/samples.txt"; }
n_overhead=$(values overhead 0 | wc -l)
[[ $n_overhead -gt 0 ]] || { echo "error: no overhead pass in the callgrind output" >&2; exit 1; }
overhead=$(values overhead 0 | sort -n | awk -v n="$n_overhead" 'NR == int((n + 1) / 2) { print }')

printf '%-15s %7s %7s %7s %7s %7s %7s %11s\n' pass samples min median p99 max max_at max/median
failed=0
for pass in $passes; do
  ovh=$overhead
  [[ $pass == overhead ]] && ovh=0
  n=$(values "$pass" "$ovh" | wc -l)
  [[ $n -gt 0 ]] || { echo "error: pass $pass missing from the callgrind output" >&2; exit 1; }
  # max_at: index of the (first) largest sample, 1-based, from the unsorted series.
  read -r max_at < <(values "$pass" "$ovh" | awk 'NR == 1 || $1 > m { m = $1; at = NR } END { print at }')
  read -r mn med p99 mx < <(values "$pass" "$ovh" | sort -n | awk -v n="$n" '
    { v[NR] = $1 }
    END { print v[1], v[int((n + 1) / 2)], v[int(0.99 * n + 0.999999)], v[n] }')
  ratio=$(awk -v a="$mx" -v b="$med" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }')
  printf '%-15s %7d %7d %7d %7d %7d %7d %11s\n' "$pass" "$n" "$mn" "$med" "$p99" "$mx" "$max_at" "$ratio"
  if [[ -n $check_ratio && $pass == fixed_* ]]; then
    if awk -v m="$mx" -v r="$check_ratio" -v d="$med" 'BEGIN { exit !(m > r * d) }'; then
      echo "CHECK FAILED: $pass max $mx > $check_ratio x median $med" >&2
      failed=1
    fi
    if (( mx > check_max )); then
      echo "CHECK FAILED: $pass max $mx > $check_max instructions" >&2
      failed=1
    fi
  fi
done
echo "(instructions per sample, x86-64 host build; the window's overhead of $overhead subtracted except in its own row;"
echo " percentiles nearest-rank; max_at = 1-based sample index)"
if [[ -n $check_ratio ]]; then
  if [[ $failed -eq 0 ]]; then
    echo "check (fixed_step, fixed_process): max <= $check_ratio x median and max <= $check_max: ok"
  else
    echo "check (fixed_step, fixed_process): max <= $check_ratio x median and max <= $check_max: FAILED"
  fi
fi
exit $failed
