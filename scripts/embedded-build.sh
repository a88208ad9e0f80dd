#!/usr/bin/env bash
# Embedded build proof: compiles core (core/core_compile_check.cpp: every core header, explicit instantiations) and
# every firmware source (firmware/src/*.cpp: the per-sample engine and the monitor loop, with the C++ headers lcm-gen
# writes for firmware/lcmtypes/*.lcm into OUT_DIR and LCM's lcm/lcm_coretypes.h, copied from the include directory
# pkg-config gives for lcm) for a Cortex-M4F with arm-none-eabi-g++, no exceptions, no RTTI, the project's warning
# flags as errors; links a minimal image (firmware/embedded/embedded_main.cpp: a WallEngine for the paper wall over a
# short built-in input, on the sensor path and inside a MonitorLoop fed encoded ground_accel_t messages; newlib-nano,
# nosys stubs, --gc-sections) and prints arm-none-eabi-size for the objects and the image.
#
#   scripts/embedded-build.sh [OUT_DIR]        (default build/embedded)
#   scripts/embedded-build.sh --objects-only [OUT_DIR]   compile only (used by the symbol audit)
#   scripts/embedded-build.sh --m4-replay [OUT_DIR]      the bootable replay image for QEMU's mps2-an386
#       (firmware/embedded/m4_replay/: vector table, start-up, semihosting, WallEngine over an engine-input file;
#       the same compiler flags) as OUT_DIR/rockwatch_m4_replay.elf, and its arm-none-eabi-size; run by
#       scripts/m4-replay.sh. Compiles only wall_engine.cpp of the firmware sources.
#   scripts/embedded-build.sh --m4-monitor [OUT_DIR]     the monitor image on the wire for QEMU's mps2-an386
#       (firmware/embedded/m4_monitor/: MonitorLoop + WallEngine + LcmDatagramReassembler behind a LAN9118 driver and
#       the image's own IPv4/UDP path; the replay image's linker script, semihosting and instruction clock) as
#       OUT_DIR/rockwatch_m4_monitor.elf, and its arm-none-eabi-size; run by scripts/m4-monitor.sh.
# Exit status: 0 built; 1 compile/link failure; 77 arm-none-eabi-g++ not installed (ctest SKIP_RETURN_CODE).
# Environment: ARM_GXX, ARM_SIZE, ARM_NM, LCM_GEN override the tools; ROCKWATCH_M4_OPT the optimisation flag (default
# -O2: the 128-bit fixed-point helpers inline: 1.5 x fewer M4 instructions per sample than -Os, measured on set 1 X;
# docs/BENCHMARKS.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

objects_only=0 m4_replay=0 m4_monitor=0
if [[ ${1:-} == --objects-only ]]; then
  objects_only=1
  shift
elif [[ ${1:-} == --m4-replay ]]; then
  m4_replay=1
  shift
elif [[ ${1:-} == --m4-monitor ]]; then
  m4_monitor=1
  shift
fi
out_dir=${1:-$root/build/embedded}

gxx=${ARM_GXX:-arm-none-eabi-g++}
size_tool=${ARM_SIZE:-arm-none-eabi-size}
nm_tool=${ARM_NM:-arm-none-eabi-nm}
if ! command -v "$gxx" >/dev/null; then
  echo "embedded-build: SKIPPED: $gxx not found (Debian: gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib" \
       "libnewlib-arm-none-eabi; scripts/install-deps.sh installs them)" >&2
  exit 77
fi
command -v pkg-config >/dev/null || { echo "embedded-build: pkg-config not found" >&2; exit 1; }
lcm_gen=${LCM_GEN:-lcm-gen}
command -v "$lcm_gen" >/dev/null || { echo "embedded-build: $lcm_gen not found (Debian: liblcm-bin)" >&2; exit 1; }
lcm_include=$(pkg-config --variable=includedir lcm) || { echo "embedded-build: pkg-config knows no lcm" >&2; exit 1; }
[[ -f $lcm_include/lcm/lcm_coretypes.h ]] || { echo "embedded-build: $lcm_include/lcm/lcm_coretypes.h not found" >&2; exit 1; }

# Eigen as a system include (as CMake does), so -Werror applies to project code only.
eigen_flags=()
for f in $(pkg-config --cflags eigen3); do
  case $f in
    -I*) eigen_flags+=("-isystem" "${f#-I}") ;;
    *) eigen_flags+=("$f") ;;
  esac
done

# The project's warning flags, read from rockwatch_warnings in the top-level CMakeLists.txt (one source of truth).
mapfile -t warnings < <(sed -n '/target_compile_options(rockwatch_warnings INTERFACE/,/)/p' "$root/CMakeLists.txt" |
  sed -e 's/target_compile_options(rockwatch_warnings INTERFACE//' -e 's/)//' | tr -s ' \t' '\n' | sed '/^$/d')
if [[ ${#warnings[@]} -eq 0 ]]; then
  echo "embedded-build: could not read the warning flags of rockwatch_warnings from CMakeLists.txt" >&2
  exit 1
fi
for w in "${warnings[@]}"; do
  [[ $w == -W* ]] || { echo "embedded-build: unexpected token '$w' in rockwatch_warnings" >&2; exit 1; }
done

# The project version, as CMake passes it to the monitor loop (monitor_status_t carries it).
version=$(sed -n 's/^project(rockwatch VERSION \([0-9]*\.[0-9]*\.[0-9]*\).*/\1/p' "$root/CMakeLists.txt")
[[ $version =~ ^[0-9]+\.[0-9]+\.[0-9]+$ ]] || { echo "embedded-build: no project VERSION in CMakeLists.txt" >&2; exit 1; }
IFS=. read -r version_major version_minor version_patch <<<"$version"

mkdir -p "$out_dir"
# The LCM message headers (lcm-gen, as firmware/CMakeLists.txt does) and lcm_coretypes.h alone: the host's include
# directory itself must not be searched (its C library headers are not newlib's).
rm -rf "$out_dir/lcmtypes" "$out_dir/lcm-include"
mkdir -p "$out_dir/lcmtypes" "$out_dir/lcm-include/lcm"
"$lcm_gen" -x --cpp-hpath "$out_dir/lcmtypes" "$root"/firmware/lcmtypes/*.lcm >/dev/null
cp "$lcm_include/lcm/lcm_coretypes.h" "$out_dir/lcm-include/lcm/"

target_flags=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
# -ffp-contract=off: no fused multiply-add (VFMA.F32) where the source has a product and a sum, so the observer's
# single-precision covariance is the host's bit for bit (CMakeLists.txt passes the same flag).
cxx_flags=(-std=c++17 "${target_flags[@]}" -fno-exceptions -fno-rtti ${ROCKWATCH_M4_OPT:--O2} -ffp-contract=off -ffunction-sections -fdata-sections
           "${warnings[@]}" "${eigen_flags[@]}" -I"$root/core/include" -I"$root/firmware/include"
           -isystem "$out_dir/lcmtypes" -isystem "$out_dir/lcm-include"
           -DROCKWATCH_VERSION_MAJOR="$version_major" -DROCKWATCH_VERSION_MINOR="$version_minor"
           -DROCKWATCH_VERSION_PATCH="$version_patch")

echo "embedded-build: $("$gxx" --version | head -n 1)"
echo "embedded-build: flags: ${cxx_flags[*]}"
compile() {
  local src=$1 obj=$2
  local extra=()
  # lcm_coretypes.h reads and writes doubles through int64_t pointers: as in CMake (firmware/CMakeLists.txt), every
  # translation unit that includes the generated headers is compiled with -fno-strict-aliasing.
  if grep -qE '#include "rockwatch/(firmware/monitor_loop|[a-z_]+_t)\.hpp"' "$src"; then
    extra=(-fno-strict-aliasing)
  fi
  echo "embedded-build: compile ${src#"$root"/} ${extra[*]}"
  "$gxx" "${cxx_flags[@]}" "${extra[@]}" -c "$src" -o "$obj"
}
if [[ $m4_replay -eq 1 ]]; then
  # The replay image: its own start-up and linker script instead of newlib's crt0 (-nostartfiles); newlib-nano for
  # memcpy/strlen and libm's sqrt, no nosys stubs (nothing may need them: no heap, no stdio, no syscalls).
  replay_dir=$root/firmware/embedded/m4_replay
  obj_dir=$out_dir/m4_replay
  rm -rf "$obj_dir"
  mkdir -p "$obj_dir"
  objects=()
  for src in "$root/firmware/src/wall_engine.cpp" "$replay_dir"/*.cpp; do
    obj=$obj_dir/$(basename "${src%.cpp}").o
    compile "$src" "$obj"
    objects+=("$obj")
  done
  echo "embedded-build: assemble ${replay_dir#"$root"/}/startup.S"
  "$gxx" "${target_flags[@]}" -c "$replay_dir/startup.S" -o "$obj_dir/startup.o"
  objects+=("$obj_dir/startup.o")
  image=$out_dir/rockwatch_m4_replay.elf
  echo "embedded-build: link ${image#"$root"/}"
  "$gxx" "${target_flags[@]}" -Os --specs=nano.specs -nostartfiles -T "$replay_dir/mps2_an386.ld" -Wl,--gc-sections \
    -Wl,-Map="$out_dir/rockwatch_m4_replay.map" "${objects[@]}" -o "$image"
  echo
  echo "== arm-none-eabi-size (image; .text = code + constants + vector table, flash; .data + .bss + the 16 KiB stack, RAM)"
  "$size_tool" -A "$image" | awk '$1 ~ /^\.(text|ARM\.exidx|data|bss|stack)$/'
  "$size_tool" "$image" | sed "s|$out_dir/||"
  exit 0
fi

if [[ $m4_monitor -eq 1 ]]; then
  # The monitor image: the replay image's start-up conventions (its own startup.S with the Ethernet and SysTick wake
  # vectors), linker script, semihosting and instruction clock (included from m4_replay/).
  monitor_dir=$root/firmware/embedded/m4_monitor
  replay_dir=$root/firmware/embedded/m4_replay
  obj_dir=$out_dir/m4_monitor
  rm -rf "$obj_dir"
  mkdir -p "$obj_dir"
  cxx_flags+=(-I"$replay_dir")
  objects=()
  for src in "$root/firmware/src/wall_engine.cpp" "$root/firmware/src/monitor_loop.cpp" \
             "$root/firmware/src/lcm_datagram.cpp" "$monitor_dir"/*.cpp; do
    obj=$obj_dir/$(basename "${src%.cpp}").o
    compile "$src" "$obj"
    objects+=("$obj")
  done
  echo "embedded-build: assemble ${monitor_dir#"$root"/}/startup.S"
  "$gxx" "${target_flags[@]}" -c "$monitor_dir/startup.S" -o "$obj_dir/startup.o"
  objects+=("$obj_dir/startup.o")
  image=$out_dir/rockwatch_m4_monitor.elf
  echo "embedded-build: link ${image#"$root"/}"
  "$gxx" "${target_flags[@]}" -Os --specs=nano.specs -nostartfiles -T "$replay_dir/mps2_an386.ld" -Wl,--gc-sections \
    -Wl,-Map="$out_dir/rockwatch_m4_monitor.map" "${objects[@]}" -o "$image"
  echo
  echo "== arm-none-eabi-size (image; .text = code + constants + vector table, flash; .data + .bss + the 16 KiB stack, RAM)"
  "$size_tool" -A "$image" | awk '$1 ~ /^\.(text|ARM\.exidx|data|bss|stack)$/'
  "$size_tool" "$image" | sed "s|$out_dir/||"
  exit 0
fi

rm -f "$out_dir"/*.o
objects=()
for src in "$root/core/core_compile_check.cpp" "$root"/firmware/src/*.cpp "$root/firmware/embedded/embedded_main.cpp"; do
  obj=$out_dir/$(basename "${src%.cpp}").o
  compile "$src" "$obj"
  objects+=("$obj")
done
if [[ $objects_only -eq 1 ]]; then
  exit 0
fi

image=$out_dir/rockwatch_embedded.elf
echo "embedded-build: link ${image#"$root"/}"
"$gxx" "${target_flags[@]}" -Os --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections \
  -Wl,-Map="$out_dir/rockwatch_embedded.map" "${objects[@]:1}" -o "$image"

echo
echo "== arm-none-eabi-size (objects: all sections before --gc-sections; image: what is linked)"
"$size_tool" "${objects[@]}" "$image" | sed "s|$out_dir/||"

# What the image holds besides the engine: the heap and stdio must not be in it (the audit checks the objects).
echo
echo "== image: allocation / stdio symbols linked in (expected: none)"
linked=$("$nm_tool" "$image" | awk '$2 ~ /^[TtWw]$/ { print $3 }' |
  grep -E '^(_?(malloc|free|calloc|realloc)(_r)?|_sbrk(_r)?|(f|s)?i?printf|_v?f?i?printf_r|puts|_?fwrite(_r)?)$' || true)
if [[ -n $linked ]]; then
  echo "$linked"
else
  echo "(none)"
fi
echo "== image: largest functions"
"$nm_tool" --size-sort -C -r "$image" | awk '$2 ~ /^[Tt]$/ && n++ < 12'
