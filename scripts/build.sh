#!/usr/bin/env bash
# Configures and builds one CMake preset (default: release) after making sure the packages are there.
#
#   scripts/build.sh [PRESET [PACKAGE_SET [TARGET...]]]
# PACKAGE_SET is scripts/install-deps.sh's set (default: all); TARGETs limit the build (default: everything).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
package_set="${2:-all}"
shift $(( $# < 2 ? $# : 2 ))
./scripts/install-deps.sh "$package_set"
cmake --preset "$preset" >/dev/null
target_args=()
for t in "$@"; do target_args+=(--target "$t"); done
cmake --build --preset "$preset" -j "$(nproc)" "${target_args[@]}"
