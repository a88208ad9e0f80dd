#!/usr/bin/env bash
# The rockwatch package for 64-bit ARM (issue 45; docs/packaging.md "64-bit ARM"): scripts/package.sh --arch arm64.
# Cross-builds rockwatch, rockwatch-monitor and their man pages (through qemu-aarch64) in build/arm64, works out the
# Depends with dpkg-shlibdeps against the :arm64 libraries, runs cpack -G DEB and lintian, and prints the .deb's path:
#   build/packages/rockwatch_<version>-1_arm64.deb
# No python3-rockwatch for arm64 (the module would need python3-dev:arm64; pip builds it on the Pi) and no
# rockwatch-mpi (`rockwatch study --mpi` then says it was built without MPI).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh arm64
./scripts/cross-build.sh --no-deps --release rockwatch rockwatch-monitor rockwatch_manpages
build="$PWD/build/arm64"
out="$PWD/build/packages"
mkdir -p "$out"
rm -f "$out"/rockwatch_*_arm64.deb
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Depends: dpkg-shlibdeps reads the :arm64 libraries' shlibs and symbols from dpkg's database (DEB_HOST_ARCH=arm64);
# liblcm1:arm64 is not installed (Multi-Arch: no: it would remove the amd64 one), so its shlibs line comes from the
# downloaded .deb (build/arm64/debs) as debian/shlibs.local, and the library itself from build/arm64/sysroot.
lcm_deb="$(ls "$build"/debs/liblcm1_*_arm64.deb 2>/dev/null | head -n 1)"
[ -n "$lcm_deb" ] || { echo "package-arm64.sh: no liblcm1_*_arm64.deb in build/arm64/debs (scripts/install-deps.sh arm64)" >&2; exit 1; }
mkdir -p "$tmp/shlibs/debian"
printf 'Source: rockwatch\n\nPackage: rockwatch\nArchitecture: arm64\n' >"$tmp/shlibs/debian/control"
dpkg-deb -I "$lcm_deb" shlibs >"$tmp/shlibs/debian/shlibs.local"
depends="$(cd "$tmp/shlibs" && DEB_HOST_ARCH=arm64 dpkg-shlibdeps -O -l"$build/sysroot/usr/lib/aarch64-linux-gnu" \
  "$build/host_tools/rockwatch" "$build/host_tools/rockwatch-monitor" 2>"$tmp/shlibdeps.err")" \
  || { cat "$tmp/shlibdeps.err" >&2; echo "package-arm64.sh: dpkg-shlibdeps failed (above)" >&2; exit 1; }
depends="${depends#shlibs:Depends=}"
[[ "$depends" == *libc6* && "$depends" == *liblcm1* ]] \
  || { echo "package-arm64.sh: dpkg-shlibdeps gave no libc6/liblcm1 dependency: '$depends'" >&2; exit 1; }

cpack --config "$build/CPackConfig.cmake" -G DEB -B "$tmp/cpack" -D CPACK_DEBIAN_PACKAGE_SHLIBDEPS=OFF \
  -D "CPACK_DEBIAN_ROCKWATCH_PACKAGE_DEPENDS=$depends" >"$tmp/cpack.log" 2>&1 \
  || { cat "$tmp/cpack.log" >&2; echo "package-arm64.sh: cpack -G DEB failed (log above)" >&2; exit 1; }
deb="$(ls "$tmp"/cpack/rockwatch_*_arm64.deb 2>/dev/null | head -n 1)"
[ -n "$deb" ] || { ls "$tmp/cpack" >&2; echo "package-arm64.sh: cpack made no rockwatch_*_arm64.deb" >&2; exit 1; }
mv "$deb" "$out/"
deb="$out/$(basename "$deb")"
if command -v lintian >/dev/null; then
  echo "package-arm64.sh: lintian (each finding is explained in docs/packaging.md):"
  lintian --tag-display-limit 0 "$deb" 2>&1 | grep -v 'running with root privileges' | sed 's/^/  /' || true
fi
echo "package-arm64.sh: Depends: $depends"
echo "package.sh: built in build/packages/:"
echo "  build/packages/$(basename "$deb")  ($(du -k "$deb" | cut -f1) KiB)"
