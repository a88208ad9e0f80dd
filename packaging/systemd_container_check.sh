#!/usr/bin/env bash
# The rockwatch package under a running systemd (issue 45: "apt install ./rockwatch_*.deb on a clean Debian 12 gives a
# rockwatch-monitor service that starts, and apt remove leaves nothing running"). A Debian 12 root made by debootstrap
# (minbase + systemd, cached in ROOT) boots systemd as PID 1 in its own PID, mount and network namespaces (unshare, a
# chroot); the package's dependencies are installed first (apt, network), then, inside the booted system, without
# network: apt install, the unit's state, apt remove, install again, reinstall (postinst's restart path), purge.
# Not a ctest: it needs root, unshare and debootstrap's download (about 200 MB) the first time. docs/packaging.md.
#
#   packaging/systemd_container_check.sh DEB [ROOT]     (ROOT default /var/tmp/rockwatch-deb12-root)
# Exit 0 when every step gave the expected state; 1 otherwise (each step's state is printed).
set -euo pipefail
if [ $# -lt 1 ] || [ $# -gt 2 ] || [ ! -f "$1" ]; then
  echo "usage: systemd_container_check.sh DEB [ROOT] (DEB: a rockwatch_*_amd64.deb, e.g. from scripts/package.sh)" >&2
  exit 2
fi
deb="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
root="${2:-/var/tmp/rockwatch-deb12-root}"
[ "$(id -u)" -eq 0 ] || { echo "systemd_container_check: needs root (debootstrap, unshare, chroot)" >&2; exit 2; }
[ "$(dpkg-deb -f "$deb" Architecture)" = "$(dpkg --print-architecture)" ] \
  || { echo "systemd_container_check: $deb is for $(dpkg-deb -f "$deb" Architecture), this host runs $(dpkg --print-architecture)" >&2; exit 2; }
command -v debootstrap >/dev/null || apt-get install -y -q --no-install-recommends debootstrap
if [ ! -x "$root/lib/systemd/systemd" ]; then
  debootstrap --variant=minbase --include=systemd,systemd-sysv,dbus,init-system-helpers,iproute2 bookworm "$root" \
    http://deb.debian.org/debian
fi
# The package's dependencies, from the mirror (the booted system has no network).
cp /etc/resolv.conf "$root/etc/resolv.conf"
deps="$(dpkg-deb -f "$deb" Depends | sed -e 's/([^)]*)//g' -e 's/,/ /g')"
mount -t proc proc "$root/proc"
(chroot "$root" apt-get update -q && chroot "$root" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
  --no-install-recommends $deps) >/dev/null || { umount "$root/proc"; echo "systemd_container_check: installing $deps failed" >&2; exit 1; }
umount "$root/proc"
cp "$deb" "$root/var/tmp/rockwatch.deb"

# Boot: systemd as PID 1 of new PID/mount/UTS/IPC/network namespaces, in the chroot.
boot="$(mktemp)"
cat >"$boot" <<BOOT
#!/bin/bash
mount --make-rprivate /
mount --bind "$root" "$root"
mount -t proc proc "$root/proc"
mount --rbind /sys "$root/sys"
mount --rbind /dev "$root/dev"
mount -t tmpfs tmpfs "$root/run"
mount -t tmpfs tmpfs "$root/tmp"
cd "$root"
exec chroot . /usr/bin/env container=other /lib/systemd/systemd --system
BOOT
chmod +x "$boot"
unshare --pid --fork --mount --uts --ipc --net "$boot" >/dev/null 2>&1 &
unshare_pid=$!
pid1=""
for _ in $(seq 50); do
  pid1="$(pgrep -P "$unshare_pid" -x systemd || true)"
  [ -n "$pid1" ] && break
  sleep 0.2
done
[ -n "$pid1" ] || { rm -f "$boot"; echo "systemd_container_check: systemd did not start" >&2; exit 1; }
trap 'kill -9 "$pid1" 2>/dev/null || true; rm -f "$boot"' EXIT
inside() { nsenter -t "$pid1" -m -u -i -n -p -r -w /bin/bash -c "cd /var/tmp && $*"; }
for _ in $(seq 60); do
  state="$(inside systemctl is-system-running 2>/dev/null || true)"
  case "$state" in running|degraded) break ;; esac
  sleep 0.5
done
echo "systemd_container_check: booted ($state): $(inside systemctl --version | head -n 1)"
inside 'ip link set lo up && ip route add 224.0.0.0/4 dev lo'   # the monitor's multicast group on loopback
apt="env DEBIAN_FRONTEND=noninteractive apt-get -y -q"
status=0
expect() {  # expect WHAT EXPECTED ACTUAL
  if [ "$2" = "$3" ]; then echo "  ok   $1: $3"; else echo "  FAIL $1: '$3' (expected '$2')"; status=1; fi
}
running() { inside 'n=0; for p in /proc/[0-9]*; do case "$(cat $p/comm 2>/dev/null)" in rockwatch*) n=$((n+1));; esac; done; echo $n'; }
active() { inside "systemctl is-active rockwatch-monitor" || true; }

inside "$apt install ./rockwatch.deb" >/dev/null 2>&1; sleep 3
expect "apt install: the unit" "active enabled" "$(active) $(inside systemctl is-enabled rockwatch-monitor || true)"
expect "apt install: rockwatch processes" 1 "$(running)"
pid="$(inside systemctl show -p MainPID --value rockwatch-monitor)"
sleep 5
expect "5 s later (WatchdogSec=2s): same process, no restart" "$pid 0" \
  "$(inside systemctl show -p MainPID --value rockwatch-monitor) $(inside systemctl show -p NRestarts --value rockwatch-monitor)"
inside "journalctl -u rockwatch-monitor --no-pager -o cat | grep -m1 listening" | sed 's/^/  journal: /'
inside "$apt remove rockwatch" >/dev/null 2>&1
expect "apt remove: the unit" "inactive" "$(active)"
expect "apt remove: rockwatch processes" 0 "$(running)"
inside "$apt install ./rockwatch.deb" >/dev/null 2>&1; sleep 2
expect "install again: the unit" "active" "$(active)"
pid="$(inside systemctl show -p MainPID --value rockwatch-monitor)"
inside "$apt install --reinstall ./rockwatch.deb" >/dev/null 2>&1; sleep 2
new="$(inside systemctl show -p MainPID --value rockwatch-monitor)"
expect "reinstall (postinst restart): active, a new process" "active yes" "$(active) $([ "$new" != "$pid" ] && echo yes || echo no)"
inside "$apt purge rockwatch" >/dev/null 2>&1
expect "apt purge: the unit" "inactive" "$(active)"
expect "apt purge: rockwatch processes, /etc/rockwatch, enablement links" "0 no no" \
  "$(running) $(inside '[ -e /etc/rockwatch ] && echo yes || echo no') $(inside 'ls /etc/systemd/system/*/rockwatch-monitor.service /etc/systemd/system/rockwatch-monitor.service >/dev/null 2>&1 && echo yes || echo no')"
[ $status -eq 0 ] && echo "systemd_container_check: OK" || echo "systemd_container_check: FAILED"
exit $status
