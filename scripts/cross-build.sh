#!/usr/bin/env bash
# Cross-builds the command line and the monitor for 64-bit ARM (aarch64) into build/arm64 (issue 45; docs/packaging.md
# "64-bit ARM"): Debian's cross compiler, the :arm64 libraries, cmake/toolchains/aarch64-linux-gnu.cmake. Only the
# targets named are built (default: rockwatch rockwatch-monitor); no tests, benchmarks, Python module or MPI.
#
#   scripts/cross-build.sh [--no-deps] [--quick | --release] [TARGET...]
# --no-deps skips scripts/install-deps.sh arm64 (the ctest arm64_cross_check: CI's build stage ran it already).
# --quick compiles at -O1 instead of the release's -O3, and the host tools' command-line, output, dashboard and reader
#   code at -O0 (CI's port check, scripts/test.sh: the same sources, warnings and checks, in less compile time:
#   docs/BENCHMARKS.md "The test loop"; the packages keep -O3). The level is
#   kept in build/arm64's cache: a later call without --quick (the ctest) builds at the level the tree has; a tree
#   first configured without --quick is -O3, and --quick on it reconfigures (saying so).
# --release compiles at -O3 whatever the tree had (scripts/package-arm64.sh, the arm64 benchmarks).
# Prints the build's wall time; the programs run under qemu-aarch64 (build/arm64/host_tools/rockwatch{,-monitor}).
set -euo pipefail
cd "$(dirname "$0")/.."
deps=true
quick=false
release=false
targets=()
for a in "$@"; do
  case "$a" in
    --no-deps) deps=false ;;
    --quick) quick=true release=false ;;
    --release) release=true quick=false ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "cross-build.sh: unknown option '$a' (expected --no-deps, --quick, --release or target names)" >&2; exit 2 ;;
    *) targets+=("$a") ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(rockwatch rockwatch-monitor)
if $deps; then ./scripts/install-deps.sh arm64; fi
for tool in aarch64-linux-gnu-g++ aarch64-linux-gnu-pkg-config; do
  command -v "$tool" >/dev/null || { echo "cross-build.sh: $tool not found (scripts/install-deps.sh arm64)" >&2; exit 1; }
done
[ -f build/arm64/sysroot/usr/lib/aarch64-linux-gnu/pkgconfig/lcm.pc ] \
  || { echo "cross-build.sh: build/arm64/sysroot has no arm64 liblcm (scripts/install-deps.sh arm64 unpacks it)" >&2; exit 1; }
dir=build/arm64
start=$(date +%s.%N)
# The optimisation level: -O1 with --quick; else what the tree was configured with; else the release's -O3.
release_flags="-O3 -DNDEBUG"
cached=$(sed -n 's/^CMAKE_CXX_FLAGS_RELEASE:[A-Z]*=//p' "$dir/CMakeCache.txt" 2>/dev/null || true)
# --quick: the host tools' command-line, output and dashboard code at -O0 (ROCKWATCH_HOST_TOOLS_COMPILE_OPTIONS).
host_tools_options=""
if $quick; then release_flags="-O1 -DNDEBUG" host_tools_options="-O0"; elif ! $release && [ -n "$cached" ]; then release_flags=$cached; fi
if [ -f "$dir/build.ninja" ] && [ -n "$cached" ] && [ "$cached" != "$release_flags" ]; then
  echo "cross-build.sh: $dir was configured with '$cached'; reconfiguring with '$release_flags' (a full rebuild)"
  rm -f "$dir/build.ninja"
fi
if [ ! -f "$dir/build.ninja" ]; then
  cmake -G Ninja -S . -B "$dir" -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
    -DROCKWATCH_CROSS_SYSROOT="$PWD/$dir/sysroot" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=$release_flags" \
    "-DROCKWATCH_HOST_TOOLS_COMPILE_OPTIONS=$host_tools_options" \
    -DROCKWATCH_BUILD_TESTS=OFF -DROCKWATCH_BUILD_BENCH=OFF -DROCKWATCH_PYTHON=OFF -DROCKWATCH_MPI=OFF >"$dir/configure.log" 2>&1 \
    || { cat "$dir/configure.log" >&2; echo "cross-build.sh: configuring $dir failed (log above)" >&2; exit 1; }
fi
ninja -C "$dir" "${targets[@]}"
echo "cross-build.sh: ${targets[*]} for aarch64 ($release_flags) in $dir: $(printf '%.0f' "$(echo "$(date +%s.%N) - $start" | bc)") s wall"
