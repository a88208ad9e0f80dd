#!/usr/bin/env bash
# The monitor image for QEMU's mps2-an386 (scripts/embedded-build.sh --m4-monitor) as OUT_DIR/rockwatch_m4_monitor.elf:
# built when missing, rebuilt when a source it depends on is newer, else left as it is (a no-op in milliseconds).
# Used by scripts/m4-monitor.sh (build/m4-monitor) and by ctest m4_monitor_image, which builds the wire test's image
# in the release test stage so that the quiet stage (scripts/test.sh) spends its time on the wire, not compiling.
#
#   scripts/m4-monitor-image.sh OUT_DIR
# Exit status: 0 current or built; 1 build failure (its log printed); 77 arm-none-eabi-g++ not found (ctest SKIP).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[[ $# -eq 1 && -n $1 ]] || { echo "usage: $0 OUT_DIR" >&2; exit 2; }
out=$1
image=$out/rockwatch_m4_monitor.elf
if ! command -v "${ARM_GXX:-arm-none-eabi-g++}" >/dev/null; then
  echo "m4-monitor-image: SKIPPED: ${ARM_GXX:-arm-none-eabi-g++} not found (scripts/install-deps.sh installs gcc-arm-none-eabi)" >&2
  exit 77
fi
if [[ -f $image ]] && [[ -z $(find "$root/core/include" "$root/firmware/include" "$root/firmware/src" \
                               "$root/firmware/lcmtypes" "$root/firmware/embedded/m4_monitor" \
                               "$root/firmware/embedded/m4_replay" "$root/scripts/embedded-build.sh" \
                               "$root/CMakeLists.txt" -newer "$image" -print -quit) ]]; then
  echo "m4-monitor-image: $image is current"
  exit 0
fi
echo "m4-monitor-image: building $image (scripts/embedded-build.sh --m4-monitor)"
mkdir -p "$out"
staging=$(mktemp -d "$out/.build.XXXXXX")
trap 'rm -rf "$staging"' EXIT
if ! "$root/scripts/embedded-build.sh" --m4-monitor "$staging" >"$staging/build.log" 2>&1; then
  cat "$staging/build.log" >&2
  echo "m4-monitor-image: building the monitor image failed" >&2
  exit 1
fi
mv -f "$staging/rockwatch_m4_monitor.elf" "$image"  # in one step: a reader never sees half an image
