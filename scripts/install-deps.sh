#!/usr/bin/env bash
# Installs the Debian packages rockwatch needs. Only missing packages are installed; `apt-get update` runs at most
# once; sudo is used when not root.
#
#   scripts/install-deps.sh demo    what building the programs and running the demo needs (scripts/demo.sh)
#   scripts/install-deps.sh package the demo set plus what scripts/package.sh needs (Debian packages, the wheel)
#   scripts/install-deps.sh arm64   the demo set plus the aarch64 cross build (scripts/cross-build.sh, ctest
#                                   arm64_cross_check, scripts/package.sh --arch arm64): adds dpkg's arm64 architecture
#   scripts/install-deps.sh [all]   that, plus the test-only tools: the Cortex-M4 toolchain and emulator, valgrind, clang and its
#                                   fuzzing runtimes, chromium (scripts/test.sh, scripts/fuzz.sh, scripts/soak.sh), and
#                                   the arm64 set
# Then the npm packages of package-lock.json (`npm ci`: uPlot, compiled into `rockwatch dashboard`, and playwright-core,
# which drives chromium in the dashboard's browser test), when node_modules does not match the lock file. Without the
# npm registry this step warns and the build still succeeds: the dashboard then serves its page without charts and
# the browser test skips, saying why.
set -euo pipefail
set_name="${1:-all}"

# Configuring the release preset needs CppUTest and Google Benchmark (the test and benchmark targets are part of
# the project), so they are in the demo set too; they are small.
DEMO_PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev          # fixed-size matrices (core, firmware)
  libcpputest-dev        # unit tests (found through pkg-config)
  libbenchmark-dev       # Google Benchmark (tests/bench)
  libcli11-dev           # command-line parsing (host_tools)
  nlohmann-json3-dev     # JSON output and reference-value tests
  libfftw3-dev           # FFT for the spectrum-compatible record generator (sim)
  libmseed-dev           # miniSEED record reader (host_tools)
  liblcm-dev liblcm-bin libglib2.0-dev   # LCM transport (firmware); lcm.pc needs glib-2.0
  iproute2               # ip: scripts/multicast-route.sh adds the multicast route on lo when there is none
  python3-matplotlib     # PNG plots (host_tools)
  python3-dev pybind11-dev python3-numpy   # import rockwatch, the Python module (host_tools/python; built when found)
  libboost-dev           # Boost.Beast: HTTP + WebSocket server of `rockwatch dashboard` (header-only)
  openmpi-bin libopenmpi-dev   # rockwatch study --mpi (mpirun, MPI); the tool builds without them, --mpi then refuses
)
# node and npm (the dashboard's uPlot through `npm ci`): Debian's nodejs and npm, unless a node with npm is there already
# (Debian's npm package conflicts with other nodejs builds, e.g. NodeSource's, which bundle npm).
NODE_PACKAGES=(nodejs npm)
# Debian packages and the wheel (scripts/package.sh; ctests package_install and pip_install, issue 45).
PACKAGE_PACKAGES=(
  dpkg-dev               # dpkg-deb, dpkg-shlibdeps (CPack DEB: CPACK_DEBIAN_PACKAGE_SHLIBDEPS)
  help2man               # man pages from --help (packaging/manpage.sh; without it a plain page)
  lintian                # checks the .deb files (scripts/package.sh)
  python3-setuptools python3-wheel python3-venv python3-pip   # pip install . --no-build-isolation, offline
)
# The aarch64 cross build (issue 45; docs/packaging.md "64-bit ARM"): Debian's cross compiler, qemu-aarch64, and the
# arm64 libraries the two programs link, all Multi-Arch: same (they install beside the amd64 ones). Not liblcm:
# liblcm1, liblcm-dev and liblcm-bin are Multi-Arch: no, so installing the :arm64 ones REMOVES the amd64 ones every host
# build needs. They are downloaded instead and unpacked into build/arm64/sysroot (lcm_arm64_sysroot below).
ARM64_PACKAGES=(
  crossbuild-essential-arm64   # aarch64-linux-gnu-gcc/g++ 12, binutils, libc6-dev:arm64 (cmake/toolchains/aarch64-linux-gnu.cmake)
  qemu-user                    # qemu-aarch64: runs the cross-built programs (ctest arm64_cross_check, the man pages)
  libstdc++6:arm64 libgcc-s1:arm64   # the runtimes as dpkg knows them: dpkg-shlibdeps of the arm64 .deb, qemu's loader
  libfftw3-dev:arm64 libmseed-dev:arm64 libglib2.0-dev:arm64   # sim's FFT, the miniSEED reader, lcm.pc's glib-2.0
)
ARM64_LCM_DEBS=(liblcm1:arm64 liblcm-dev:arm64)
TEST_PACKAGES=(
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib libnewlib-arm-none-eabi   # Cortex-M4 build (scripts/embedded-build.sh)
  qemu-system-arm        # the firmware on an emulated Cortex-M4 (scripts/m4-replay.sh, ctest m4_replay)
  binutils               # nm, size (symbol audit: tests/tools/symbol_audit.sh)
  valgrind               # callgrind instruction counts (tests/bench)
  clang libclang-rt-dev  # fuzzing (scripts/fuzz.sh, preset "fuzz"): clang++ and its libFuzzer/ASan/UBSan runtimes
  chromium               # headless browser of the dashboard's browser test (driven by playwright-core from npm)
  python3-pytest         # the Python module's test (tests/python, ctest test_python_module)
  patch                  # the mutants (scripts/mutants.sh, ctest mutants_apply)
)

case "$set_name" in
  demo) PACKAGES=("${DEMO_PACKAGES[@]}") ;;
  package) PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGE_PACKAGES[@]}") ;;
  arm64) PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGE_PACKAGES[@]}" "${ARM64_PACKAGES[@]}") ;;
  all) PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGE_PACKAGES[@]}" "${TEST_PACKAGES[@]}" "${ARM64_PACKAGES[@]}") ;;
  *) echo "install-deps: unknown package set '$set_name' (expected 'demo', 'package', 'arm64' or 'all')" >&2; exit 2 ;;
esac
with_arm64=false
case "$set_name" in arm64|all) with_arm64=true ;; esac

if ! command -v npm >/dev/null 2>&1; then PACKAGES+=("${NODE_PACKAGES[@]}"); fi

# npm ci when node_modules is missing or older than the lock file (npm writes node_modules/.package-lock.json).
npm_install() {
  cd "$(dirname "$0")/.."
  if [ -f node_modules/.package-lock.json ] && [ node_modules/.package-lock.json -nt package-lock.json ]; then
    echo "install-deps: node_modules matches package-lock.json"
    return 0
  fi
  if ! command -v npm >/dev/null 2>&1; then
    echo "install-deps: warning: npm not found: the dashboard will have no charts, its browser test will skip" >&2
    return 0
  fi
  echo "install-deps: npm ci (uplot, playwright-core: package-lock.json)"
  if ! npm ci --ignore-scripts --no-audit --no-fund; then
    echo "install-deps: warning: npm ci failed (no registry?): the dashboard will have no charts, its browser test" \
         "will skip" >&2
  fi
}

# liblcm for arm64 (not co-installable, above): the two .deb files downloaded into build/arm64/debs and unpacked into
# build/arm64/sysroot, lcm.pc's prefix pointed there; the toolchain file finds it through ROCKWATCH_CROSS_SYSROOT.
lcm_arm64_sysroot() {
  cd "$(dirname "$0")/.."
  local sysroot=build/arm64/sysroot debs=build/arm64/debs pc
  pc="$sysroot/usr/lib/aarch64-linux-gnu/pkgconfig/lcm.pc"
  if [ -f "$pc" ] && [ -e "$sysroot/usr/lib/aarch64-linux-gnu/liblcm.so.1" ]; then
    echo "install-deps: liblcm (arm64) present in $sysroot"
    return 0
  fi
  rm -rf "$debs" "$sysroot"
  mkdir -p "$debs" "$sysroot"
  chmod 777 "$debs"   # apt-get download runs as _apt when it can
  (cd "$debs" && apt-get download "${ARM64_LCM_DEBS[@]}") \
    || { echo "install-deps: apt-get download ${ARM64_LCM_DEBS[*]} failed (dpkg --add-architecture arm64, apt-get update?)" >&2; exit 1; }
  for d in "$debs"/*.deb; do dpkg-deb -x "$d" "$sysroot"; done
  sed -i "s|^prefix=.*|prefix=$PWD/$sysroot/usr|" "$pc"
  echo "install-deps: liblcm (arm64) unpacked into $sysroot (not installed: Multi-Arch: no)"
}

need_update=false
if $with_arm64 && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  echo "install-deps: dpkg --add-architecture arm64"
  if [ "$(id -u)" -ne 0 ]; then sudo dpkg --add-architecture arm64; else dpkg --add-architecture arm64; fi
  need_update=true
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ] && ! $need_update; then
  echo "install-deps: all ${#PACKAGES[@]} packages of the '$set_name' set present"
  if $with_arm64; then (lcm_arm64_sysroot); fi
  npm_install
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
if $with_arm64; then (lcm_arm64_sysroot); fi
npm_install
