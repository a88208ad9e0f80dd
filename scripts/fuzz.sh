#!/usr/bin/env bash
# Builds the libFuzzer targets (CMake preset "fuzz": clang, ASan + UBSan) and runs them (docs/RELIABILITY.md).
#
#   scripts/fuzz.sh smoke                          every kept regression input, then every fuzzer for its share of
#                                                  36 s from the committed seeds, nproc fuzzers at a time (CI:
#                                                  scripts/test.sh)
#   scripts/fuzz.sh long [SECONDS] [TARGET...]     opt-in long run, SECONDS per target (600); the corpus grows across
#                                                  runs in build/fuzz/corpus-work/TARGET
#   scripts/fuzz.sh regress                        only the kept regression inputs
#   scripts/fuzz.sh list                           the targets
#   --quick (after the mode)                       the preset "fuzz-quick" in build/fuzz-quick: rockwatch_sim (not a
#                                                  parser) at -O0, the rest at -O1 (CI's smoke: docs/BENCHMARKS.md
#                                                  "The test loop"); long runs want the default preset
#   --jobs-file=FILE (after the mode)              smoke: how many fuzzers at a time, read from FILE before each
#                                                  start (nproc when it is absent or not a number): CI runs the smoke
#                                                  one at a time beside the emulated board's test, then nproc
#
# Exit status non-zero on any crash, uncaught exception, sanitizer report, leak, timeout (hang) or out-of-memory.
# Per target: executions, seconds, executions/s, corpus files/bytes at the end, coverage; logs and crashing inputs in
# build/fuzz/logs and build/fuzz/artifacts. A crashing input is kept as tests/fuzz/regressions/TARGET/NAME once fixed.
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-smoke}"
preset=fuzz
args=()
jobs_file=""
for a in "$@"; do
  case "$a" in
    --quick) preset=fuzz-quick ;;
    --jobs-file=*) jobs_file=${a#--jobs-file=} ;;
    *) args+=("$a") ;;
  esac
done
set -- "${args[@]}"
build=build/$preset
bin=$build/tests/fuzz
corpus=tests/fuzz/corpus
regressions=tests/fuzz/regressions
dicts=tests/fuzz/dict

# target  max_len  smoke_seconds  seed corpora (besides corpus/<target without fuzz_>)
targets=(
  "fuzz_record_at2        4096  2"
  "fuzz_record_plain      4096  2"
  "fuzz_record_esm        8192  2"
  "fuzz_record_itaca      4096  2"
  "fuzz_record_miniseed   4096  3"
  "fuzz_record_suite      4096  2"
  "fuzz_read_record       8192  3"
  "fuzz_suite_manifest    8192  2"
  "fuzz_wall_sensor_csv   4096  2"
  "fuzz_monitor_config    4096  3"
  "fuzz_monitor_args      1024  2"
  "fuzz_monitor_loop     32768 5"
  "fuzz_monitor_datagrams 16384 4"
  "fuzz_dashboard         8192  2"
)

field() { echo "$1" | awk -v n="$2" '{print $n}'; }
target_names() { for t in "${targets[@]}"; do field "$t" 1; done; }

usage() {
  sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
}

build_fuzzers() {
  ./scripts/install-deps.sh
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$(nproc)"
}

# The dictionary of a target (read_record: all the record formats'), or nothing.
dict_option() {
  local name=${1#fuzz_}
  if [ "$name" = read_record ]; then
    cat "$dicts"/record_*.dict >"$build/read_record.dict"
    echo "-dict=$build/read_record.dict"
  elif [ -f "$dicts/$name.dict" ]; then
    echo "-dict=$dicts/$name.dict"
  fi
}

seed_dirs() {
  local name=${1#fuzz_}
  local dirs=("$corpus/$name")
  if [ "$name" = read_record ]; then dirs+=("$corpus"/record_*); fi
  echo "${dirs[@]}"
}

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
common=(-timeout=10 -rss_limit_mb=2048 -print_final_stats=1)

results=()
failed=()

# run_fuzzer TARGET MAX_LEN SECONDS WORK_DIR: fuzzes for SECONDS from WORK_DIR (new inputs go there) and the seeds.
run_fuzzer() {
  local target=$1 max_len=$2 seconds=$3 work=$4
  local log=$build/logs/$target.log artifacts=$build/artifacts/$target/
  mkdir -p "$work" "$artifacts" "$build/logs"
  local dict
  dict=$(dict_option "$target")
  local start end status=0
  start=$(date +%s.%N)
  # shellcheck disable=SC2046
  "$bin/$target" "${common[@]}" -max_len="$max_len" -max_total_time="$seconds" -artifact_prefix="$artifacts" \
    ${dict:+"$dict"} "$work" $(seed_dirs "$target") >"$log" 2>&1 || status=$?
  end=$(date +%s.%N)
  local execs rate done_line corp cov
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  done_line=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -1 || true)
  corp=$(echo "$done_line" | sed -n 's/.*corp: \([0-9]*\/[0-9]*[a-zA-Z]*\).*/\1/p')
  cov=$(echo "$done_line" | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
  local verdict=ok
  if [ "$status" -ne 0 ]; then
    verdict="FAILED (exit $status)"
    echo "== $target: FAILED, exit $status; the end of $log:" >&2
    tail -n 60 "$log" >&2
  fi
  local elapsed
  elapsed=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
  printf '%-22s %7s %10s %8s %14s %6s  %s\n' "$target" "$elapsed" "${execs:-?}" \
    "${rate:-?}" "${corp:-?}" "${cov:-?}" "$verdict" >"$build/logs/$target.result"
}

# How many fuzzers at a time: --jobs-file's number when there is one, else nproc.
max_jobs() {
  local n=""
  [ -z "$jobs_file" ] || n=$(cat "$jobs_file" 2>/dev/null || true)
  if [[ "$n" =~ ^[1-9][0-9]*$ ]]; then echo "$n"; else nproc; fi
}

# run_fuzzers WORK_ROOT: every target for its smoke seconds, longest first, max_jobs at a time (each fuzzer is one
# process on one core: run one after another they left a core idle, issue 42), new inputs in WORK_ROOT/TARGET; then the
# results in the targets' order.
run_fuzzers() {
  local work_root=$1 t running=0
  for t in "${targets[@]}"; do
    rm -f "$build/logs/$(field "$t" 1).result"
  done
  # Longest first, so that the last ones to start are short and the cores finish together; the results are
  # printed in the table's order.
  local by_length=()
  mapfile -t by_length < <(printf '%s\n' "${targets[@]}" | sort -k3,3nr -s)
  for t in "${by_length[@]}"; do
    while [ "$running" -ge "$(max_jobs)" ]; do
      wait -n || true
      running=$((running - 1))
    done
    run_fuzzer "$(field "$t" 1)" "$(field "$t" 2)" "$(field "$t" 3)" "$work_root/$(field "$t" 1)" &
    running=$((running + 1))
  done
  wait || true
  for t in "${targets[@]}"; do collect_result "$(field "$t" 1)"; done
}
# collect_result TARGET: run_fuzzer's line of TARGET into the results (and the failures).
collect_result() {
  local line
  line=$(cat "$build/logs/$1.result" 2>/dev/null || echo "$1: no result (the run did not finish) FAILED")
  results+=("$line")
  [[ "$line" != *FAILED* ]] || failed+=("$1")
}

# Every kept input of every target, each run once (regression tests of fixed defects).
run_regressions() {
  local total=0
  for target in $(target_names); do
    local dir=$regressions/${target#fuzz_}
    [ -d "$dir" ] || continue
    local files=()
    while IFS= read -r -d '' f; do files+=("$f"); done < <(find "$dir" -type f ! -name '*.md' -print0 | sort -z)
    [ ${#files[@]} -gt 0 ] || continue
    total=$((total + ${#files[@]}))
    local log=$build/logs/$target.regressions.log status=0
    mkdir -p "$build/logs"
    "$bin/$target" -timeout=10 -rss_limit_mb=2048 "${files[@]}" >"$log" 2>&1 || status=$?
    if [ "$status" -ne 0 ]; then
      failed+=("$target regressions")
      echo "== $target: a kept regression input fails (exit $status); the end of $log:" >&2
      tail -n 60 "$log" >&2
    else
      echo "regressions $target: ${#files[@]} inputs ok"
    fi
  done
  echo "regressions: $total kept inputs run"
}

print_results() {
  printf '%-22s %7s %10s %8s %14s %6s  %s\n' target seconds execs exec/s "corpus(n/size)" cov result
  for r in "${results[@]}"; do echo "$r"; done
}

finish() {
  if [ ${#failed[@]} -gt 0 ]; then
    echo "fuzz: FAILED: ${failed[*]} (crashing inputs in $build/artifacts/)" >&2
    exit 1
  fi
  echo "fuzz: no defect found"
}

case "$mode" in
  smoke)
    build_fuzzers
    run_regressions
    rm -rf "$build/corpus-smoke"
    start=$(date +%s)
    run_fuzzers "$build/corpus-smoke"
    print_results
    echo "smoke run: $(($(date +%s) - start)) s of fuzzing"
    finish
    ;;
  long)
    seconds="${2:-600}"
    [[ "$seconds" =~ ^[0-9]+$ ]] || usage
    shift $(($# >= 2 ? 2 : 1))
    wanted=("$@")
    for w in "${wanted[@]}"; do
      target_names | grep -x "$w" >/dev/null || { echo "fuzz: no target $w (scripts/fuzz.sh list)" >&2; exit 2; }
    done
    build_fuzzers
    for t in "${targets[@]}"; do
      name=$(field "$t" 1)
      if [ ${#wanted[@]} -gt 0 ] && ! printf '%s\n' "${wanted[@]}" | grep -x "$name" >/dev/null; then continue; fi
      rm -f "$build/logs/$name.result"
      run_fuzzer "$name" "$(field "$t" 2)" "$seconds" "$build/corpus-work/$name"
      collect_result "$name"
    done
    print_results
    finish
    ;;
  regress)
    build_fuzzers
    run_regressions
    finish
    ;;
  list)
    target_names
    ;;
  *)
    usage
    ;;
esac
