#!/usr/bin/env bash
# The main job: builds everything (installing missing packages first), makes sure LCM multicast can work on this
# machine, then runs `rockwatch demo`: rockwatch-monitor watches the paper's wall live over LCM (UDP multicast that
# stays on this machine, ttl=0) while two suite records are replayed to it in real time, one that collapses the wall
# and one it survives, and its alarm timeline is printed beside the offline simulation of the same samples.
# Arguments go to `rockwatch demo` (e.g. --speed 4; see build/release/host_tools/rockwatch demo --help).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only the two programs the demo runs, with only the packages they need (no ARM toolchain, clang or valgrind).
./scripts/build.sh release demo rockwatch rockwatch-monitor

# Multicast needs a route (added on lo when root and missing; otherwise `rockwatch demo` checks and says what to do).
source scripts/multicast-route.sh

echo
exec build/release/host_tools/rockwatch demo "$@"
