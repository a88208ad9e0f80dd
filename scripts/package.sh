#!/usr/bin/env bash
# Builds rockwatch's packages into build/packages/ and prints their paths (issue 45; docs/packaging.md):
#   rockwatch_<version>-1_<arch>.deb          the CLI, rockwatch-monitor and its systemd unit, /etc/rockwatch, man pages
#   python3-rockwatch_<version>-1_<arch>.deb  the Python module for Debian's python3
#   rockwatch-<version>-cp3XX-...whl          the same module for pip (pip install build/packages/rockwatch-*.whl)
#
#   scripts/package.sh [--arch amd64|arm64]
# --arch arm64: the rockwatch package for 64-bit ARM from the cross build (scripts/package-arm64.sh; no Python module).
# Uses the release preset's tree (build/release: configured when it is not), builds only the packaged targets, runs
# cpack -G DEB and lintian, then `pip wheel` with Debian's setuptools (offline, --no-build-isolation).
set -euo pipefail
cd "$(dirname "$0")/.."
arch="$(dpkg --print-architecture)"
while [ $# -gt 0 ]; do
  case "$1" in
    --arch) arch="${2:-}"; shift 2 || { echo "package.sh: --arch needs amd64 or arm64" >&2; exit 2; } ;;
    --arch=*) arch="${1#--arch=}"; shift ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "package.sh: unknown argument '$1' (usage: scripts/package.sh [--arch amd64|arm64])" >&2; exit 2 ;;
  esac
done
host_arch="$(dpkg --print-architecture)"
case "$arch" in
  "$host_arch") ;;
  arm64) exec ./scripts/package-arm64.sh ;;
  *) echo "package.sh: --arch $arch: expected amd64 or arm64 (this host is $host_arch)" >&2; exit 2 ;;
esac

./scripts/install-deps.sh package
build=build/release
if [ ! -f "$build/build.ninja" ]; then
  cmake --preset release >/dev/null
else
  cmake "$build" >/dev/null   # picks up new install() rules; keeps the tree's options
fi
grep -q '^ROCKWATCH_PYTHON_MODULE:INTERNAL=ON' "$build/CMakeCache.txt" \
  || { echo "package.sh: the Python module is not built in $build (python3-dev, pybind11-dev missing?)" >&2; exit 1; }
ninja -C "$build" rockwatch rockwatch-monitor rockwatch_python rockwatch_manpages
out="$PWD/build/packages"
mkdir -p "$out"
rm -f "$out"/rockwatch_*.deb "$out"/python3-rockwatch_*.deb "$out"/rockwatch-*.whl
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$out" >"$out/cpack.log" 2>&1 \
  || { cat "$out/cpack.log" >&2; echo "package.sh: cpack -G DEB failed (log above)" >&2; exit 1; }
rm -rf "$out/_CPack_Packages"
if command -v lintian >/dev/null; then
  echo "package.sh: lintian (each finding is explained in docs/packaging.md):"
  lintian --tag-display-limit 0 "$out"/*.deb 2>&1 | grep -v 'running with root privileges' | sed 's/^/  /' || true
fi
ROCKWATCH_CMAKE_BUILD_DIR="$PWD/$build" PIP_DISABLE_PIP_VERSION_CHECK=1 \
  /usr/bin/python3 -m pip wheel --no-index --no-build-isolation --no-deps -w "$out" . >"$out/wheel.log" 2>&1 \
  || { tail -n 30 "$out/wheel.log" >&2; echo "package.sh: pip wheel failed (log above)" >&2; exit 1; }
echo "package.sh: built in build/packages/:"
for f in "$out"/rockwatch_*.deb "$out"/python3-rockwatch_*.deb "$out"/rockwatch-*.whl; do
  echo "  build/packages/$(basename "$f")  ($(du -k "$f" | cut -f1) KiB)"
done
