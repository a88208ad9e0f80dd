#!/usr/bin/env bash
# Builds and runs every test suite twice: the release build, then the debug build under
# AddressSanitizer + UndefinedBehaviorSanitizer; then the fuzzing smoke run (clang build of the libFuzzer targets,
# the kept regression inputs, about a minute of fuzzing: scripts/fuzz.sh, docs/RELIABILITY.md).
# Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
for preset in release debug; do
  echo "== $preset: build"
  ./scripts/build.sh "$preset"
  # The end-to-end tests run LCM over real UDP multicast on loopback (they skip, saying why, when it is unavailable);
  # after the build, which installs iproute2.
  source scripts/multicast-route.sh
  echo "== $preset: test"
  ctest --preset "$preset" -j "$(nproc)"
done
echo "== fuzz: smoke"
./scripts/fuzz.sh smoke
