#!/usr/bin/env bash
# LCM's UDP multicast needs a route for the group. A machine on a network usually has one (its default route); a
# container or a machine without a network often has none. As root, and only when no route reaches the LCM group,
# this adds the usual one on the loopback interface (rockwatch's traffic never leaves the machine: ttl=0).
# Sourced by scripts/demo.sh and scripts/test.sh (the end-to-end tests run over real multicast on loopback).
if [ "$(id -u)" -eq 0 ] && command -v ip >/dev/null; then
  if ! ip route get 239.255.76.67 >/dev/null 2>&1; then
    echo "multicast: no route for the LCM group: adding 224.0.0.0/4 on lo (ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo)"
    ip link set lo up 2>/dev/null || true
    ip link set lo multicast on 2>/dev/null || true
    ip route add 224.0.0.0/4 dev lo 2>/dev/null || echo "multicast: could not add the route (no NET_ADMIN capability?)" >&2
  fi
fi
