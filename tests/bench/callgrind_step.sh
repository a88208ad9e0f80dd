#!/usr/bin/env bash
# Instructions per RockingStepper<double>::step, counted by callgrind (deterministic, unlike timings).
# Runs bench_step_count twice per variant, with N1 and N2 steps, and prints (Ir(N2) - Ir(N1)) / (N2 - N1), so
# process start-up and input generation cancel. Defaults: by N1 = 160000 the response to the looped input has
# settled into an exactly periodic orbit (linear: 80000 steps, from step 72000; full: 32000 steps, from step
# 136000; checked with this build), and N2 - N1 = 160000 is a whole number of orbits of both, so the figure is
# that of steady rocking and does not depend on where the window falls.
#
#   tests/bench/callgrind_step.sh BUILD_DIR [VARIANT...]
#     BUILD_DIR  CMake build directory holding tests/bench/bench_step_count (e.g. build/release)
#     VARIANT    rocking_linear, rocking_full, quiet_linear (default: all three)
#   Environment: N1, N2 (default 160000, 320000); CALLGRIND_OUT_DIR keeps the callgrind.out files there
#   (for callgrind_annotate) instead of a temporary directory.
set -euo pipefail

if [[ $# -lt 1 ]]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
build_dir=$1
shift
variants=("$@")
[[ ${#variants[@]} -gt 0 ]] || variants=(rocking_linear rocking_full quiet_linear)

exe=$build_dir/tests/bench/bench_step_count
[[ -x $exe ]] || { echo "error: $exe not found; build the bench_step_count target first" >&2; exit 1; }
command -v valgrind >/dev/null || { echo "error: valgrind not found" >&2; exit 1; }

n1=${N1:-160000}
n2=${N2:-320000}
(( n2 > n1 )) || { echo "error: N2 ($n2) must be greater than N1 ($n1)" >&2; exit 2; }

if [[ -n ${CALLGRIND_OUT_DIR:-} ]]; then
  out_dir=$CALLGRIND_OUT_DIR
  mkdir -p "$out_dir"
else
  out_dir=$(mktemp -d)
  trap 'rm -rf "$out_dir"' EXIT
fi

# Total Ir of one run; the program's own line goes to stderr so the check that it rocked stays visible.
total_ir() {
  local variant=$1 n=$2 file=$out_dir/callgrind.out.$1.$2
  if ! valgrind --tool=callgrind --callgrind-out-file="$file" "$exe" "$n" "$variant" >&2 2>/dev/null; then
    echo "error: callgrind run of $exe $n $variant failed" >&2
    return 1
  fi
  local ir
  ir=$(awk '/^(summary|totals):/ { print $2; exit }' "$file")
  [[ -n $ir ]] || { echo "error: no instruction total in $file" >&2; return 1; }
  echo "$ir"
}

printf '%-16s %12s %12s %16s %16s %10s\n' variant N1 N2 'Ir(N1)' 'Ir(N2)' Ir/step
for variant in "${variants[@]}"; do
  ir1=$(total_ir "$variant" "$n1")
  ir2=$(total_ir "$variant" "$n2")
  per_step=$(awk -v a="$ir1" -v b="$ir2" -v n1="$n1" -v n2="$n2" 'BEGIN { printf "%.1f", (b - a) / (n2 - n1) }')
  printf '%-16s %12d %12d %16d %16d %10s\n' "$variant" "$n1" "$n2" "$ir1" "$ir2" "$per_step"
done
