#!/usr/bin/env bash
# Builds and runs every test suite twice: the release build, then the debug build under
# AddressSanitizer + UndefinedBehaviorSanitizer; then the fuzzing smoke run (clang build of the libFuzzer targets,
# the kept regression inputs, about a minute of fuzzing: scripts/fuzz.sh, docs/RELIABILITY.md).
# Prints how long each stage took at the end (docs/BENCHMARKS.md, "The test loop"). Exits non-zero on any failure.
# Ends, pass or fail, with a line of the suites run and skipped per preset (scripts/ctest-summary.py). Under CI=true
# a test that would skip for a missing tool or service fails instead (tests/support/no_skip_in_ci.sh, ci_skip.hpp),
# and any skip left fails the run: CI expects 0 skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
stage_times=()
suites_line=()
print_suites() {
  echo "== suites run and skipped: ${suites_line[*]:-no ctest run finished}"
}
trap print_suites EXIT
# CPU seconds (user + system) of this shell's finished child processes so far: cutime + cstime of /proc/PID/stat.
ticks=$(getconf CLK_TCK)
child_cpu() {
  local f
  read -r -a f </proc/$$/stat
  echo $(((f[15] + f[16]) / ticks))
}
stage() {  # stage NAME: starts NAME's clocks; stage_done records them
  echo "== $1 ($(date +%T))"
  stage_start=$SECONDS
  stage_cpu=$(child_cpu)
  stage_name=$1
}
stage_done() {
  stage_times+=("$(printf '%-14s %4d s wall %5d s CPU' "$stage_name" $((SECONDS - stage_start)) \
    $(($(child_cpu) - stage_cpu)))")
}
for preset in release debug; do
  stage "$preset: build"
  ./scripts/build.sh "$preset"
  stage_done
  if [ "$preset" = release ]; then
    # The aarch64 cross build of the two programs (build/arm64), which ctest arm64_cross_check runs under qemu.
    stage "arm64: build"
    ./scripts/cross-build.sh --no-deps
    stage_done
  fi
  # The end-to-end tests run LCM over real UDP multicast on loopback (they skip, saying why, when it is unavailable,
  # and fail under CI=true); after the build, which installs iproute2.
  source scripts/multicast-route.sh
  stage "$preset: test"
  junit="$PWD/build/$preset/ctest-junit.xml"
  rm -f "$junit"
  ctest_status=0
  ctest --preset "$preset" -j "$(nproc)" --output-junit "$junit" || ctest_status=$?
  summary=$(/usr/bin/python3 scripts/ctest-summary.py "$preset" "$junit")
  suites_line+=("$summary;")
  echo "$summary"
  [ "$ctest_status" -eq 0 ] || exit "$ctest_status"
  if [ "${CI:-}" = true ] && ! grep -q ", 0 skipped" <<<"$summary"; then
    echo "FAILED: tests skipped under CI=true: $summary" >&2
    exit 1
  fi
  stage_done
done
stage "fuzz: build"
./scripts/build.sh fuzz
stage_done
stage "fuzz: smoke"
./scripts/fuzz.sh smoke  # (its build step finds everything up to date)
stage_done
echo "== stage times"
printf '%s\n' "${stage_times[@]}"
printf '%-14s %4d s wall %5d s CPU\n' total "$SECONDS" "$(child_cpu)"
