#!/usr/bin/env bash
# Builds and runs every test suite twice: the release build, then the debug build under
# AddressSanitizer + UndefinedBehaviorSanitizer; then the fuzzing smoke run (clang build of the libFuzzer targets,
# the kept regression inputs, about a minute of fuzzing: scripts/fuzz.sh, docs/RELIABILITY.md).
# Prints how long each stage took at the end (docs/BENCHMARKS.md, "The test loop"). Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
stage_times=()
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
  # The end-to-end tests run LCM over real UDP multicast on loopback (they skip, saying why, when it is unavailable);
  # after the build, which installs iproute2.
  source scripts/multicast-route.sh
  stage "$preset: test"
  ctest --preset "$preset" -j "$(nproc)"
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
