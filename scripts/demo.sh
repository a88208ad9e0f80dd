#!/usr/bin/env bash
# The main job: builds everything (installing missing packages first), makes sure LCM multicast can work on this
# machine, then runs `rockwatch demo`: rockwatch-monitor watches the paper's wall live over LCM (UDP multicast that
# stays on this machine, ttl=0) while two suite records are replayed to it in real time, one that collapses the wall
# and one it survives, and its alarm timeline is printed beside the offline simulation of the same samples.
# Arguments go to `rockwatch demo` (e.g. --speed 4; see build/release/host_tools/rockwatch demo --help).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release

# Multicast needs a route. A machine on a network usually has one (its default route); a container or a machine
# without a network often has none. As root, and only when no route reaches the LCM group, this adds the usual one
# on the loopback interface (the demo's traffic never leaves the machine: ttl=0). Otherwise `rockwatch demo` checks
# multicast itself and says what to do.
if [ "$(id -u)" -eq 0 ] && command -v ip >/dev/null; then
  if ! ip route get 239.255.76.67 >/dev/null 2>&1; then
    echo "demo: no route for multicast: adding 224.0.0.0/4 on lo (ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo)"
    ip link set lo up 2>/dev/null || true
    ip link set lo multicast on 2>/dev/null || true
    ip route add 224.0.0.0/4 dev lo 2>/dev/null || echo "demo: could not add the route (no NET_ADMIN capability?)" >&2
  fi
fi

echo
exec build/release/host_tools/rockwatch demo "$@"
