#!/usr/bin/env bash
# Builds and runs every test suite twice: the release build, then the debug build under
# AddressSanitizer + UndefinedBehaviorSanitizer; the aarch64 cross build and its check under qemu (ctest
# arm64_cross_check); then the fuzzing smoke run (clang build of the libFuzzer targets, rockwatch_sim at -O0, the kept
# regression inputs, 36 s of fuzzing: scripts/fuzz.sh --quick, docs/RELIABILITY.md).
#
# A pipeline (issue 42: the fresh-clone CI within 24 min on 2 cores): a test run leaves a core idle about half its time
# (its tests wait on sockets, paced replays and child processes), so the next build runs beside it in the background at
# nice 19: the tests keep the CPU whenever they want it, and the build takes what they leave. Every test's time is
# within a quarter of its timeout with one core busy (docs/BENCHMARKS.md "The test loop"), which is at most what a
# niced build beside it costs. The order:
#   release: build                    (foreground)
#   release: test (all but arm64)     beside  debug: build (background)
#   debug: test                       beside  arm64: build (background, nice 10), fuzz: build (background, nice 19)
#   release: test arm64_cross_check   beside  fuzz: build (if not done)
#   quiet tests                       alone: both presets' entries labelled quiet_machine but m4_monitor_wire
#   quiet: board on the wire          m4_monitor_wire (the emulated board must keep real time; beside a build it fell
#                                     behind and lost datagrams) beside  fuzz: smoke (background, nice 19, one fuzzer
#                                     at a time, then nproc once the board is done)
# (Both presets' tests run with "all but the quiet ones" first, the quiet ones at the end.) The entries labelled
# release_only (tests/CMakeLists.txt: an image built by arm-none-eabi-g++, a Python engine, a check of the docs) are
# registered disabled under the sanitizers: the summary line names them apart from the skipped ones.
# A background build's output goes to build/ci-<name>.log (printed when it fails).
# Prints how long each stage took and the CPU its processes used at the end (docs/BENCHMARKS.md, "The test loop").
# Exits non-zero on any failure.
# Ends, pass or fail, with a line of the suites run and skipped per preset (scripts/ctest-summary.py). Under CI=true
# a test that would skip for a missing tool or service fails instead (tests/support/no_skip_in_ci.sh, ci_skip.hpp),
# and any skip left fails the run: CI expects 0 skipped.
#
#   scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
stage_times=()
suites_line=()
timeout_lines=()
declare -A bg_pid=()
print_suites() {
  echo "== suites run and skipped: ${suites_line[*]:-no ctest run finished}"
}
finish() {
  local pid
  for pid in "${bg_pid[@]}"; do kill -- "-$pid" 2>/dev/null || kill "$pid" 2>/dev/null || true; done
  print_suites
}
trap finish EXIT
# CPU seconds (user + system) of this shell's finished child processes so far: cutime + cstime of /proc/PID/stat.
ticks=$(getconf CLK_TCK)
child_cpu() {
  local f
  read -r -a f </proc/$$/stat
  echo $(((f[15] + f[16]) / ticks))
}
# The CPU ticks of this (sub)shell's finished children: cutime + cstime of /proc/BASHPID/stat.
own_child_ticks() {
  local f
  read -r -a f </proc/$BASHPID/stat
  echo $((f[15] + f[16]))
}
# with_cpu COMMAND...: runs COMMAND in a subshell and adds its CPU (all its processes) to the stage's; returns its
# status.
with_cpu() {
  local rc=0 file=build/.stage-cpu.$$
  mkdir -p build
  (
    status=0
    "$@" || status=$?
    own_child_ticks >"$file"
    exit "$status"
  ) || rc=$?
  stage_cpu_ticks=$((stage_cpu_ticks + $(cat "$file" 2>/dev/null || echo 0)))
  rm -f "$file"
  return "$rc"
}
stage() {  # stage NAME: starts NAME's clock; stage_done records it
  echo "== $1 ($(date +%T))"
  stage_start=$SECONDS
  stage_name=$1
  stage_cpu_ticks=0
}
stage_done() {
  stage_times+=("$(printf '%-26s %4d s wall, from %4d s %5d s CPU' "$stage_name" $((SECONDS - stage_start)) \
    "$stage_start" $((stage_cpu_ticks / ticks)))")
}
log_of() { echo "build/ci-$(tr -cs 'a-z0-9' '-' <<<"$1" | sed 's/-$//').log"; }
# bg_start NAME NICE COMMAND...: runs COMMAND in the background at NICE (its own process group, so a failure elsewhere
# stops all of it); its output in build/ci-NAME.log, its status and times in that file's .status.
bg_start() {
  local name=$1 niceness=$2
  shift 2
  local log
  log=$(log_of "$name")
  mkdir -p build
  rm -f "$log.status"
  echo "== $name ($(date +%T), in the background at nice $niceness: $log)"
  set -m
  (
    start=$SECONDS
    status=0
    nice -n "$niceness" "$@" >"$log" 2>&1 </dev/null || status=$?
    own_child_ticks >"$log.cpu"  # not in $(…): that is another subshell, without these children
    echo "$status $start $SECONDS $(($(cat "$log.cpu") / ticks))" >"$log.status"
  ) &
  bg_pid[$name]=$!
  set +m
}
# bg_wait NAME: waits for NAME; on failure prints the end of its log and exits.
bg_wait() {
  local name=$1 log status start end cpu
  log=$(log_of "$name")
  wait "${bg_pid[$name]}" || true
  unset "bg_pid[$name]"
  read -r status start end cpu <"$log.status" || { status=1 start=0 end=0 cpu=0; }
  stage_times+=("$(printf '%-26s %4d s wall, from %4d s %5d s CPU (background)' "$name" $((end - start)) "$start" "$cpu")")
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "FAILED: $name (exit status $status; the whole output: $log)" >&2
    exit "$status"
  fi
  echo "== $name done ($(date +%T), $((end - start)) s)"
}
# run_ctest PRESET JUNIT [CTEST ARGUMENTS...]: one ctest call; its JUnit file kept for the preset's summary line.
run_ctest() {
  local preset=$1 junit="$PWD/build/$1/$2"
  shift 2
  rm -f "$junit"
  ctest_status=0
  with_cpu ctest --preset "$preset" -j "$(nproc)" --output-junit "$junit" "$@" || ctest_status=$?
}
# summarise PRESET JUNIT...: the preset's line of suites run and skipped; fails on a failure, or a skip under CI=true.
summarise() {
  local preset=$1 summary
  shift
  local files=()
  for f in "$@"; do files+=("$PWD/build/$preset/$f"); done
  summary=$(/usr/bin/python3 scripts/ctest-summary.py "$preset" "${files[@]}")
  suites_line+=("$summary;")
  echo "$summary"
  # The entries closest to their timeouts (each must stay within a quarter of it): informational.
  timeout_lines+=("$(/usr/bin/python3 scripts/ctest-timeouts.py "$preset" "build/$preset" "${files[@]}")")
  [ "$ctest_status" -eq 0 ] || exit "$ctest_status"
  if [ "${CI:-}" = true ] && ! grep -q ", 0 skipped" <<<"$summary"; then
    echo "FAILED: tests skipped under CI=true: $summary" >&2
    exit 1
  fi
}

stage "release: build"
with_cpu ./scripts/build.sh release
stage_done
# The end-to-end tests run LCM over real UDP multicast on loopback (they skip, saying why, when it is unavailable,
# and fail under CI=true); after the build, which installs iproute2.
source scripts/multicast-route.sh

bg_start "debug: build" 19 ./scripts/build.sh debug
stage "release: test"
run_ctest release ctest-junit.xml -E '^arm64_cross_check$' -LE quiet_machine
release_status=$ctest_status
stage_done
[ "$release_status" -eq 0 ] || { summarise release ctest-junit.xml; }
bg_wait "debug: build"

# The aarch64 cross build of the two programs (build/arm64, at -O1: cross-build.sh --quick), which ctest arm64_cross_check runs under qemu; the
# libFuzzer targets. Both beside the debug tests, the cross build first (nice 10 before 19).
bg_start "arm64: build" 10 ./scripts/cross-build.sh --no-deps --quick
bg_start "fuzz: build" 19 ./scripts/build.sh fuzz-quick
stage "debug: test"
run_ctest debug ctest-junit.xml -LE quiet_machine
debug_status=$ctest_status
stage_done
[ "$debug_status" -eq 0 ] || { summarise debug ctest-junit.xml; }

bg_wait "arm64: build"
stage "release: arm64 check"
run_ctest release ctest-junit-arm64.xml -R '^arm64_cross_check$'
arm64_status=$ctest_status
stage_done

bg_wait "fuzz: build"
# Nothing beside these: the entries labelled quiet_machine but the emulated board's, of both presets, one at a time
# (the dashboard's browser tests: chromium's page must keep up with 30 updates a second).
stage "quiet tests"
run_ctest release ctest-junit-quiet.xml -L quiet_machine -E '^m4_monitor_wire$'
release_quiet_status=$ctest_status
run_ctest debug ctest-junit-quiet.xml -L quiet_machine
debug_quiet_status=$ctest_status
stage_done

# The emulated board on the wire (m4_monitor_wire: QEMU, the host monitor, the replay and a listener, about 0.6 of a
# core) beside the fuzz smoke at one fuzzer at a time, nice 19: one core stays the board's (beside a two-job build it
# fell behind real time and lost datagrams; beside one fuzzer every state is equal and no datagram lost, with more
# samples finished a call late: docs/BENCHMARKS.md "The test loop"). When the board is done, the smoke goes on nproc
# at a time (scripts/fuzz.sh --jobs-file).
smoke_jobs=$PWD/build/ci-fuzz-smoke-jobs
echo 1 >"$smoke_jobs"
bg_start "fuzz: smoke" 19 ./scripts/fuzz.sh smoke --quick "--jobs-file=$smoke_jobs"
stage "quiet: board on the wire"
run_ctest release ctest-junit-wire.xml -R '^m4_monitor_wire$'
release_wire_status=$ctest_status
nproc >"$smoke_jobs"
stage_done
max() { echo $(($1 > $2 ? ($1 > $3 ? $1 : $3) : ($2 > $3 ? $2 : $3))); }
ctest_status=$(max "$release_status" "$arm64_status" "$(max "$release_quiet_status" "$release_wire_status" 0)")
summarise release ctest-junit.xml ctest-junit-arm64.xml ctest-junit-quiet.xml ctest-junit-wire.xml
ctest_status=$(max "$debug_status" "$debug_quiet_status" 0)
summarise debug ctest-junit.xml ctest-junit-quiet.xml
bg_wait "fuzz: smoke"
grep -E '^(target |fuzz_|smoke run|regressions|fuzz: )' "$(log_of "fuzz: smoke")" || true
echo "== entries against their timeouts"
printf '%s\n' "${timeout_lines[@]}"
echo "== stage times"
printf '%s\n' "${stage_times[@]}"
printf '%-26s %4d s wall %5d s CPU\n' total "$SECONDS" "$(child_cpu)"
