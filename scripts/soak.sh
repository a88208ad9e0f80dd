#!/usr/bin/env bash
# Opt-in long soak of rockwatch-monitor (docs/RELIABILITY.md "Soak"): builds the release preset and feeds the
# monitor at 1 kHz over LCM on loopback for SECONDS (default 3600), with injected input faults, then checks that every
# sample is accounted for, that the counters that must stay zero did, that VmRSS stayed flat after the warm-up and
# that the monitor made no heap call per sample (LD_PRELOAD counting shim). CI runs the 30 s version
# (ctest -R monitor_soak_short).
#
#   scripts/soak.sh [SECONDS] [soak_monitor options...]     e.g. scripts/soak.sh 600 --rate 500
#
# The JSON result goes to build/release/soak/result.json, the monitor's stdout/stderr and the heap report to
# build/release/soak/. Exit status: 0 pass, 1 a check failed, 77 skipped (no multicast route on loopback:
# scripts/multicast-route.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-3600}"
shift || true
./scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target soak_monitor
out=build/release/soak
mkdir -p "$out"
# RSS every minute, a warm-up of 10 s; the rest of the options as given.
exec build/release/tests/soak/soak_monitor --duration "$seconds" --warmup 10 --rss-every 60 \
  --keep "$out" --json "$out/result.json" "$@" >/dev/null
