#!/usr/bin/env bash
# ctest pip_install: `pip install .` offline into a fresh virtual environment (Debian's setuptools and wheel through
# --system-site-packages, --no-build-isolation), building the module's target in this build tree
# (ROCKWATCH_CMAKE_BUILD_DIR), then `python -m rockwatch --version` and an import from the venv's site-packages.
#   packaging/test_pip_install.sh BUILD_DIR SOURCE_DIR VERSION
set -euo pipefail
build="$1" src="$2" version="$3"
fail() { echo "pip_install: FAIL: $*" >&2; exit 1; }
/usr/bin/python3 -c 'import venv, ensurepip, setuptools, wheel' 2>/dev/null \
  || fail "Debian's python3-venv, python3-setuptools and python3-wheel are needed (scripts/install-deps.sh)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$tmp/venv"
ROCKWATCH_CMAKE_BUILD_DIR="$build" PIP_DISABLE_PIP_VERSION_CHECK=1 \
  "$tmp/venv/bin/pip" install --no-index --no-build-isolation --no-deps "$src" >"$tmp/pip.log" 2>&1 \
  || { tail -n 30 "$tmp/pip.log"; fail "pip install --no-index --no-build-isolation $src"; }
cd "$tmp"
out="$("$tmp/venv/bin/python" -m rockwatch --version)"
[ "$out" = "rockwatch $version" ] || fail "python -m rockwatch --version: '$out'"
"$tmp/venv/bin/python" -c '
import rockwatch, sys
assert "/venv/" in rockwatch.__file__, rockwatch.__file__
assert hasattr(rockwatch, "simulate") and hasattr(rockwatch, "read_record"), dir(rockwatch)
print("pip_install: import rockwatch from", rockwatch.__file__)' || fail "import rockwatch from the venv"
echo "pip_install: OK"
