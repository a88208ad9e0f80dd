#!/usr/bin/env bash
# Replays a record through the firmware's fixed-point engine (firmware::WallEngine) on an emulated Cortex-M4 and
# prints one JSON object: the machine, the samples, the instructions the engine executed per sample and the alarm
# transitions. The host's `rockwatch simulate --arith fixed --alarms` runs first with the given options and writes
# the engine's configuration and every step's input (--engine-input-out); the replay image
# (firmware/embedded/m4_replay/, built by scripts/embedded-build.sh --m4-replay) then runs on QEMU's mps2-an386 board,
# initialises the engine from that configuration on the target and steps it on exactly those inputs, reading and
# writing files through ARM semihosting. Instructions are counted deterministically: -icount shift=10 makes every
# instruction 1024 ns of virtual time, and the board's 25 MHz timer, read before and after each step, gives the
# instructions in between exactly (firmware/embedded/m4_replay/instruction_clock.hpp; docs/BENCHMARKS.md).
#
#   scripts/m4-replay.sh [--m4-image ELF] [--m4-trace FILE.csv] [--m4-timeout S] [--m4-profile SAMPLE]
#                        SIMULATE_OPTIONS...
#     SIMULATE_OPTIONS  `rockwatch simulate`'s own: --record/--suite ..., --units, --dt, --scale-pga, --vertical,
#                       the wall (--b --h1 --h2 ...), --r, --kappa, --max-step, --t-end, the alarm settings, ...
#                       and --wall-sensors FILE with the --observer-* settings (the observer then runs on the
#                       target too) (--arith fixed and --alarms are added; --arith double and --engine-input-out
#                       are refused)
#     --m4-image ELF    run this image instead of building build/m4-replay/rockwatch_m4_replay.elf (rebuilt when a
#                       source is newer)
#     --m4-trace FILE   also write every sample as CSV: sample,insn_step,insn_engine,level,x_m,xd_mps,pending
#                       (samples still in work after the call),work_units (what the cost model charged the call)
#     --m4-timeout S    give up on QEMU after S seconds (default 600)
#     --m4-profile N    also profile the step of input sample N (a second run: SysTick samples the program counter
#                       every 97.66 instructions) and add "profile": the functions' shares of that step
#   Environment: ROCKWATCH (the rockwatch binary; default build/release/host_tools/rockwatch, else on PATH),
#                QEMU_SYSTEM_ARM (default qemu-system-arm), ARM_GXX (see embedded-build.sh).
# Output keys: machine, samples (input samples including sample 0, which starts the engine), observer (true with
# --wall-sensors: the wall observer ran on the target), insn_per_sample
# {median, p99, max, max_sample} of step() through the monitor's seam (double -> Q7.56, the chain, the published
# sample back in double) over samples 1..n-1, engine_insn_per_sample (the same for process_wall() alone, inputs
# converted beforehand), start_insn, overhead_insn (the measurement window's own cost, subtracted), stack_bytes,
# carry_over {late_samples, max_late_calls, shed_samples, overruns, first_shed_sample, max_pending} (step() works within
# a budget per call and may finish a sample at a later call: docs/FIXED_POINT.md "Bounded work per call"; every
# finished sample is checked against process_wall() on the target, up to the call that first shed: first_shed_sample,
# null when none did; --work-overflow finish never sheds), transitions [{sample, level}] (sample = index of the input sample
# whose step changed the level; its values are the sample's own, whichever call finished it); with
# --m4-profile also profile {sample, insn, interval_insn, addresses, functions [{function, share}]}.
# Exit status: 0 printed; 1 build, emulation or image failure (with a message); 2 invalid options or input (the
# message of simulate); 77 arm-none-eabi-g++ or qemu-system-arm not installed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
python=/usr/bin/python3

help_text() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }
usage() { help_text >&2; exit 2; }

image="" trace="" timeout_s=600 profile_sample=""
sim_args=()
arith_given=0
while [[ $# -gt 0 ]]; do
  case $1 in
    --m4-image) [[ $# -ge 2 ]] || usage; image=$2; shift 2 ;;
    --m4-trace) [[ $# -ge 2 ]] || usage; trace=$2; shift 2 ;;
    --m4-profile)
      [[ $# -ge 2 && $2 =~ ^[1-9][0-9]{0,9}$ ]] || { echo "m4-replay: --m4-profile needs an input sample index >= 1" >&2; exit 2; }
      profile_sample=$2; shift 2 ;;
    --m4-timeout)
      [[ $# -ge 2 && $2 =~ ^[1-9][0-9]*$ ]] || { echo "m4-replay: --m4-timeout needs whole seconds > 0" >&2; exit 2; }
      timeout_s=$2; shift 2 ;;
    -h|--help) help_text; exit 0 ;;
    --arith|--arith=*)
      value=${1#--arith}; value=${value#=}
      if [[ -z $value ]]; then [[ $# -ge 2 ]] || usage; value=$2; shift; fi
      if [[ $value != fixed ]]; then
        echo "m4-replay: the Cortex-M4 runs the fixed-point engine: --arith must be fixed (got '$value')" >&2
        exit 2
      fi
      arith_given=1; shift ;;
    --engine-input-out|--engine-input-out=*)
      echo "m4-replay: ${1%%=*} is not available here (the script writes the engine input itself)" >&2
      exit 2 ;;
    *) sim_args+=("$1"); shift ;;
  esac
done
[[ ${#sim_args[@]} -gt 0 ]] || usage

qemu=${QEMU_SYSTEM_ARM:-qemu-system-arm}
if ! command -v "$qemu" >/dev/null; then
  echo "m4-replay: SKIPPED: $qemu not found (Debian: qemu-system-arm; scripts/install-deps.sh installs it)" >&2
  exit 77
fi
rockwatch=${ROCKWATCH:-$root/build/release/host_tools/rockwatch}
if [[ ! -x $rockwatch ]]; then
  rockwatch=$(command -v rockwatch || true)
  [[ -n $rockwatch ]] || { echo "m4-replay: no rockwatch binary: build it (cmake --build build/release --target rockwatch) or set ROCKWATCH" >&2; exit 1; }
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/m4-replay.XXXXXX")
trap 'rm -rf "$work"' EXIT

# 1. The host's analysis and the engine input (simulate's own messages and status for bad options or input).
extra=(--alarms)
[[ $arith_given -eq 1 ]] || extra+=(--arith fixed)
set +e
"$rockwatch" simulate "${sim_args[@]}" "${extra[@]}" --engine-input-out "$work/input.bin" >/dev/null 2>"$work/simulate.err"
status=$?
set -e
cat "$work/simulate.err" >&2  # its notes (e.g. on the record), or its error
[[ $status -eq 0 ]] || exit "$status"

# 2. The image: built unless given, and rebuilt when a source it depends on is newer.
if [[ -z $image ]]; then
  if ! command -v "${ARM_GXX:-arm-none-eabi-g++}" >/dev/null; then
    echo "m4-replay: SKIPPED: ${ARM_GXX:-arm-none-eabi-g++} not found (scripts/install-deps.sh installs gcc-arm-none-eabi)" >&2
    exit 77
  fi
  build_dir=$root/build/m4-replay
  image=$build_dir/rockwatch_m4_replay.elf
  if [[ ! -f $image ]] || [[ -n $(find "$root/core/include" "$root/firmware/include" "$root/firmware/src" \
                                      "$root/firmware/embedded/m4_replay" "$root/scripts/embedded-build.sh" \
                                      "$root/CMakeLists.txt" -newer "$image" -print -quit) ]]; then
    echo "m4-replay: building the replay image (scripts/embedded-build.sh --m4-replay)" >&2
    # Built in a directory of its own and moved into place, so that concurrent runs never see half an image.
    if ! "$root/scripts/embedded-build.sh" --m4-replay "$work/image" >"$work/build.log" 2>&1; then
      cat "$work/build.log" >&2
      echo "m4-replay: building the replay image failed" >&2
      exit 1
    fi
    mkdir -p "$build_dir"
    cp "$work/image/rockwatch_m4_replay.elf" "$image.tmp.$$"
    mv -f "$image.tmp.$$" "$image"
  fi
fi
[[ -f $image ]] || { echo "m4-replay: image $image not found" >&2; exit 1; }
if [[ $(head -c 4 "$image" | od -An -tx1 | tr -d ' \n') != 7f454c46 ]]; then
  echo "m4-replay: $image is not an ELF image (build it with scripts/embedded-build.sh --m4-replay)" >&2
  exit 1
fi
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")

# 3. The emulation, bounded in time. The image reads input.bin and writes output.txt in QEMU's working directory.
shift_icount=10
run_qemu() {  # OUTPUT_NAME [profile SAMPLE]
  (cd "$work" && timeout --kill-after=10 "$timeout_s" "$qemu" -M mps2-an386 -cpu cortex-m4 -nographic -monitor none \
     -serial none -semihosting-config enable=on,target=native -icount shift=$shift_icount \
     -kernel "$image" -append "input.bin $*") >"$work/qemu.log" 2>&1
}
set +e
run_qemu output.txt
status=$?
if [[ $status -eq 0 && -n $profile_sample ]]; then
  run_qemu profile.txt profile "$profile_sample"
  status=$?
fi
set -e
if [[ $status -ne 0 ]]; then
  cat "$work/qemu.log" >&2
  case $status in
    124|137) echo "m4-replay: QEMU did not finish within $timeout_s s (--m4-timeout)" >&2 ;;
    3) echo "m4-replay: the image did not get its command line" >&2 ;;
    4|5) echo "m4-replay: the image could not read the engine input (status $status)" >&2 ;;
    6) echo "m4-replay: the engine refused the configuration on the target" >&2 ;;
    7) echo "m4-replay: the image could not write its output" >&2 ;;
    8|9|10) echo "m4-replay: the image failed (status $status: 8 engines disagree, 9 fault, 10 assertion)" >&2 ;;
    *) echo "m4-replay: QEMU exited with status $status" >&2 ;;
  esac
  exit 1
fi

qemu_version=$("$qemu" --version | sed -n '1s/^QEMU emulator version \([0-9][0-9.]*\).*/\1/p')
symbols=""
if [[ -n $profile_sample ]]; then
  symbols=$work/symbols.txt
  "${ARM_NM:-arm-none-eabi-nm}" -C -S --defined-only "$image" >"$symbols" 2>/dev/null || : >"$symbols"
fi
# 4. Ticks to instructions, statistics and the JSON.
observer=0
for a in "${sim_args[@]}"; do [[ $a == --wall-sensors || $a == --wall-sensors=* ]] && observer=1; done
"$python" - "$work/output.txt" "$shift_icount" "${qemu_version:-?}" "$trace" "$profile_sample" "$symbols" "$observer" <<'EOF'
import json, math, struct, sys

path, shift, qemu_version, trace = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
profile_sample, symbols = sys.argv[5], sys.argv[6]
observer = sys.argv[7] == "1"
LEVELS = ["QUIET", "ROCKING", "WARNING", "IMMINENT", "COLLAPSED"]
NS_PER_TICK = 40.0                      # the board's 25 MHz timer clock
ticks_per_insn = (1 << shift) / NS_PER_TICK

def fail(message):
    sys.stderr.write("m4-replay: " + message + "\n")
    sys.exit(1)

def insns(ticks):
    # Exact when the counts are whole: each read is off by less than one tick, i.e. 1/25.6 instruction.
    v = ticks / ticks_per_insn
    n = round(v)
    if abs(v - n) > 0.25:
        fail("the timer ticks (%d) are not a whole number of instructions (%.3f): is the timer clock 25 MHz?" % (ticks, v))
    return n

def from_bits(text):
    return struct.unpack("<d", int(text, 16).to_bytes(8, "little"))[0]

lines = open(path).read().splitlines()
if not lines or lines[0] != "rockwatch-m4-replay 1":
    fail("the image's output has no header")
overhead = start = end = work = None
steps = []
for number, line in enumerate(lines[1:], start=2):
    f = line.split()
    if f[0] == "overhead" and len(f) == 3:
        lo, hi = insns(int(f[1])), insns(int(f[2]))
        if lo != hi:
            fail("the measurement overhead varies (%d to %d instructions): the count is not deterministic" % (lo, hi))
        overhead = lo
    elif f[0] == "start" and len(f) == 3:
        start = (insns(int(f[1])), int(f[2]))
    elif f[0] == "s" and len(f) == 8:
        steps.append((insns(int(f[1])), insns(int(f[2])), int(f[3]), from_bits(f[4]), from_bits(f[5]), int(f[6]),
                      int(f[7])))
    elif f[0] == "work" and len(f) == 6:
        work = {"late_samples": int(f[1]), "max_late_calls": int(f[2]), "shed_samples": int(f[3]), "overruns": int(f[4]),
                "first_shed_sample": int(f[5]) or None}
    elif f[0] == "end" and len(f) == 3:
        end = (int(f[1]), int(f[2]))
    else:
        fail("output line %d not understood: %r" % (number, line))
if overhead is None or start is None or end is None or work is None:
    fail("the image's output is incomplete")
if end[0] != len(steps) + 1:
    fail("the image reports %d samples but wrote %d" % (end[0], len(steps) + 1))

def stats(values):
    if not values:
        return {"median": 0, "p99": 0, "max": 0, "max_sample": 0}
    s = sorted(values)
    n = len(s)
    rank = lambda p: s[max(0, math.ceil(p * n) - 1)]
    top = max(values)
    return {"median": s[(n + 1) // 2 - 1], "p99": rank(0.99), "max": top, "max_sample": values.index(top) + 1}

step_insn = [st[0] - overhead for st in steps]
engine_insn = [st[1] - overhead for st in steps]
transitions = []
level = start[1]
for i, st in enumerate(steps, start=1):
    if st[2] != level:
        transitions.append({"sample": i, "level": LEVELS[st[2]]})
        level = st[2]

if trace:
    with open(trace, "w") as t:
        t.write("sample,insn_step,insn_engine,level,x_m,xd_mps,pending,work_units\n")
        t.write("0,%d,,%s,0,0,0,0\n" % (start[0] - overhead, LEVELS[start[1]]))
        for i, st in enumerate(steps, start=1):
            t.write("%d,%d,%d,%s,%r,%r,%d,%d\n" % (i, step_insn[i - 1], engine_insn[i - 1], LEVELS[st[2]], st[3],
                                                 st[4], st[5], st[6]))

result = {
    "machine": "mps2-an386 (Cortex-M4F, qemu-system-arm %s, -icount shift=%d)" % (qemu_version, shift),
    "samples": len(steps) + 1,
    "observer": observer,
    "insn_per_sample": stats(step_insn),
    "engine_insn_per_sample": stats(engine_insn),
    "start_insn": start[0] - overhead,
    "overhead_insn": overhead,
    "stack_bytes": end[1],
    "carry_over": dict(work, max_pending=max([st[5] for st in steps] or [0])),
    "transitions": transitions,
}

if profile_sample:
    k = int(profile_sample)
    if k >= len(steps) + 1:
        fail("--m4-profile %d: the replay has samples 0 to %d" % (k, len(steps)))
    interval = None
    addresses = []
    for line in open(path.replace("output.txt", "profile.txt")).read().splitlines():
        f = line.split()
        if f[0] == "profile":
            interval, dropped = int(f[1]), int(f[3])
            if dropped:
                fail("the profiler dropped %d addresses" % dropped)
        elif f[0] == "p":
            addresses.append(int(f[1], 16) & ~1)
    if interval is None:
        fail("the profiling run wrote no profile")
    functions = []  # (start, end, name): functions of the image, from nm
    for line in open(symbols):
        f = line.split(None, 3)
        if len(f) == 4 and f[2] in "TtWw":
            start_addr, size = int(f[0], 16), int(f[1], 16)
            name = f[3].strip()
            functions.append((start_addr, start_addr + size, name.split("(")[0] if "(" in name else name))
    functions.sort()
    counts = {}
    for a in addresses:
        name = "0x%x" % a
        for lo, hi, n in functions:
            if lo <= a < hi:
                name = n
                break
        counts[name] = counts.get(name, 0) + 1
    total = max(1, len(addresses))
    result["profile"] = {
        "sample": k,
        "insn": step_insn[k - 1],
        "interval_insn": round(interval / ticks_per_insn, 2),
        "addresses": len(addresses),
        "functions": [{"function": n, "share": round(c / total, 4)}
                      for n, c in sorted(counts.items(), key=lambda kv: -kv[1])[:15]],
    }

print(json.dumps(result, indent=2))
EOF
