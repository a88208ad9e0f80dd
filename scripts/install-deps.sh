#!/usr/bin/env bash
# Installs the Debian packages rockwatch needs. Only missing packages are installed; `apt-get update` runs at most
# once; sudo is used when not root.
#
#   scripts/install-deps.sh demo    what building the programs and running the demo needs (scripts/demo.sh)
#   scripts/install-deps.sh package the demo set plus what scripts/package.sh needs (Debian packages, the wheel)
#   scripts/install-deps.sh [all]   that, plus the test-only tools: the Cortex-M4 toolchain and emulator, valgrind, clang and its
#                                   fuzzing runtimes, chromium (scripts/test.sh, scripts/fuzz.sh, scripts/soak.sh)
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
TEST_PACKAGES=(
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib libnewlib-arm-none-eabi   # Cortex-M4 build (scripts/embedded-build.sh)
  qemu-system-arm        # the firmware on an emulated Cortex-M4 (scripts/m4-replay.sh, ctest m4_replay)
  binutils               # nm, size (symbol audit: tests/tools/symbol_audit.sh)
  valgrind               # callgrind instruction counts (tests/bench)
  clang libclang-rt-dev  # fuzzing (scripts/fuzz.sh, preset "fuzz"): clang++ and its libFuzzer/ASan/UBSan runtimes
  chromium               # headless browser of the dashboard's browser test (driven by playwright-core from npm)
  python3-pytest         # the Python module's test (tests/python, ctest test_python_module)
)

case "$set_name" in
  demo) PACKAGES=("${DEMO_PACKAGES[@]}") ;;
  package) PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGE_PACKAGES[@]}") ;;
  all) PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGE_PACKAGES[@]}" "${TEST_PACKAGES[@]}") ;;
  *) echo "install-deps: unknown package set '$set_name' (expected 'demo', 'package' or 'all')" >&2; exit 2 ;;
esac

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

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages of the '$set_name' set present"
  npm_install
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
npm_install
