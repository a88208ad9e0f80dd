#!/usr/bin/env bash
# ctest package_install: the Debian packages of this build tree (cpack -G DEB into a temporary directory), unpacked
# into a throwaway root with dpkg -x, and the installed programs run from there: rockwatch --version, simulate on a
# record of the shipped suite, rockwatch-monitor --print-config with the packaged /etc/rockwatch/monitor.json,
# python3 -m rockwatch --version from the root's dist-packages. Checks the dependencies dpkg-shlibdeps wrote.
#   packaging/test_package_install.sh BUILD_DIR SOURCE_DIR VERSION
set -euo pipefail
build="$1" src="$2" version="$3"
fail() { echo "package_install: FAIL: $*" >&2; exit 1; }
for tool in cpack dpkg-deb dpkg-shlibdeps; do
  command -v "$tool" >/dev/null || fail "$tool not found (dpkg-dev, cmake: scripts/install-deps.sh)"
done
[ -f "$build/CPackConfig.cmake" ] || fail "$build/CPackConfig.cmake missing: configure the build tree first"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
t0=$(date +%s.%N)
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$tmp/out" >"$tmp/cpack.log" 2>&1 || { cat "$tmp/cpack.log"; fail "cpack -G DEB"; }
t1=$(date +%s.%N)
deb="$(ls "$tmp/out"/rockwatch_"$version"-*.deb 2>/dev/null | head -n 1)"
[ -n "$deb" ] || { ls "$tmp/out"; fail "no rockwatch_${version}-*.deb from cpack"; }
pydeb="$(ls "$tmp/out"/python3-rockwatch_"$version"-*.deb 2>/dev/null | head -n 1)"
root="$tmp/root"
dpkg -x "$deb" "$root"
[ -z "$pydeb" ] || dpkg -x "$pydeb" "$root"
echo "package_install: cpack $(printf '%.1f' "$(echo "$t1 - $t0" | bc)") s; $(basename "$deb") $(stat -c %s "$deb") bytes${pydeb:+, $(basename "$pydeb") $(stat -c %s "$pydeb") bytes}"

# Dependencies from dpkg-shlibdeps: the C library, the C++ runtime and the LCM library at least.
depends="$(dpkg-deb -f "$deb" Depends)"
echo "package_install: rockwatch Depends: $depends"
for lib in libc6 libstdc++6 liblcm; do
  [[ "$depends" == *"$lib"* ]] || fail "rockwatch's Depends lacks $lib (CPACK_DEBIAN_PACKAGE_SHLIBDEPS): $depends"
done
for f in postinst prerm postrm conffiles; do
  dpkg-deb -I "$deb" "$f" >/dev/null 2>&1 || fail "rockwatch has no $f"
done
grep -qx /etc/rockwatch/monitor.json <(dpkg-deb -I "$deb" conffiles) || fail "/etc/rockwatch/monitor.json is not a conffile"

# The files a lab gets.
for f in usr/bin/rockwatch usr/bin/rockwatch-monitor lib/systemd/system/rockwatch-monitor.service \
         etc/rockwatch/monitor.json usr/share/man/man1/rockwatch.1.gz usr/share/man/man1/rockwatch-monitor.1.gz \
         usr/share/rockwatch/suites/npr9998-2015/manifest.json; do
  [ -e "$root/$f" ] || fail "/$f is not in the package"
done
grep -q '^ExecStart=/usr/bin/rockwatch-monitor ' "$root/lib/systemd/system/rockwatch-monitor.service" \
  || fail "the packaged unit does not start /usr/bin/rockwatch-monitor"
zcat "$root/usr/share/man/man1/rockwatch.1.gz" | grep -q '^\.SH' || fail "rockwatch.1.gz is not a man page"

# The installed programs, run from the throwaway root.
out="$("$root/usr/bin/rockwatch" --version)"
[ "$out" = "rockwatch $version" ] || fail "installed rockwatch --version: '$out'"
"$root/usr/bin/rockwatch" simulate --suite "$root/usr/share/rockwatch/suites/npr9998-2015" --set 1 --component X \
  --wall paper --json >"$tmp/simulate.json" || fail "installed rockwatch simulate on the shipped suite"
grep -q '"max_abs_x' "$tmp/simulate.json" || { head -c 400 "$tmp/simulate.json"; fail "simulate --json has no max_abs_x"; }
"$root/usr/bin/rockwatch-monitor" --print-config --config "$root/etc/rockwatch/monitor.json" >"$tmp/config.json" \
  || fail "installed rockwatch-monitor --print-config --config /etc/rockwatch/monitor.json"
grep -q '"config_digest"' "$tmp/config.json" || fail "--print-config printed no config_digest"
out="$("$root/usr/bin/rockwatch-monitor" --version)"
[ "$out" = "rockwatch-monitor $version" ] || fail "installed rockwatch-monitor --version: '$out'"

if [ -n "$pydeb" ]; then
  pydepends="$(dpkg-deb -f "$pydeb" Depends)"
  echo "package_install: python3-rockwatch Depends: $pydepends"
  [[ "$pydepends" == *python3-numpy* && "$pydepends" == *libc6* ]] || fail "python3-rockwatch's Depends: $pydepends"
  out="$(cd "$tmp" && PYTHONPATH="$root/usr/lib/python3/dist-packages" /usr/bin/python3 -m rockwatch --version)"
  [ "$out" = "rockwatch $version" ] || fail "python3 -m rockwatch --version from the package: '$out'"
  (cd "$tmp" && PYTHONPATH="$root/usr/lib/python3/dist-packages" /usr/bin/python3 -c '
import rockwatch, sys
assert rockwatch.__file__.startswith(sys.argv[1]), rockwatch.__file__
print("package_install: import rockwatch from", rockwatch.__file__)' "$root") || fail "import rockwatch from the package"
else
  echo "package_install: no python3-rockwatch (the module is not built in this tree)"
fi
echo "package_install: OK"
