#!/usr/bin/env python3
"""Load test of one rockwatch-monitor (issue 41, item 5): many walls at 1 kHz and many dashboard viewers.

    scripts/load-test.py [--walls 64] [--rate 1000] [--viewers 50] [--pga 0.3] [--seconds 20]
                         [--build build/release] [--monitor PATH] [--rockwatch PATH] [--lcm-url URL]
                         [--monitor-args '--realtime 50'] [--keep DIR] [--json FILE] [--no-wait-idle]

What runs (real parts only, on this machine, UDP multicast on loopback, a random group and port of 239.255.76.151+):
  - rockwatch-monitor with a `walls` array of --walls walls (w00, w01, ...; the paper wall) on one shared ground
    channel, --rate Hz, and --log on a tmpfs (/dev/shm) — the log is the measuring instrument (below);
  - rockwatch dashboard on the same group, and --viewers WebSocket clients (this script, one thread with a selector:
    the RFC 6455 handshake on /ws, then every frame read and counted) for the whole run;
  - rockwatch replay of suite npr9998-2015 set 1 X scaled to --pga g at --rate Hz, cut after --seconds s (SIGINT):
    at 0.3 g every wall rocks (up to WARNING), none collapses, so every wall's engine works all along.

Figures (printed, and as JSON with --json):
  - sample latency, from the monitor's own --log: each wall_state_t event's log time (CLOCK_REALTIME when the
    monitor published it) minus (a) the sample's utime, the time the replay scheduled it (start + i/rate: so this
    includes the sender's lateness, the kernel and the monitor's queue) — "sample to state"; and (b) the time the
    monitor received that sample (its input event's log time) — "receive to publish", the monitor's own work for
    all the walls in front of this one. p50, p99, p99.9 and max over every wall's states;
  - CPU: the monitor's and the dashboard's utime + stime (/proc/PID/stat) over the replay, as % of one core and per
    wall (and µs per wall-sample);
  - samples dropped by the monitor: per wall, samples sent by the replay − samples_received, and the gaps,
    state_resets, duplicates, out_of_order counters (all must be 0); besides, the kernel's drop count at the
    monitor's UDP sockets (/proc/PID/net/udp), which would explain a loss;
  - viewers: connected at the end, frames and bytes received, the slowest viewer's frames; the dashboard's own
    summary line (updates sent, dropped for slow pages); this script's CPU (the viewers' threads) is reported too,
    since it competes with the monitor for the same cores.

Exit status 0 when no sample was dropped and every viewer stayed connected, 1 otherwise, 2 on bad options or when a
program does not start. Measure on an idle machine: the script waits (up to 10 min) while a compiler runs
(`pgrep ninja`, `pgrep cc1plus`) unless --no-wait-idle.
"""
import argparse
import base64
import json
import os
import random
import selectors
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def udp_drops(pid):
    """Datagrams the kernel dropped at pid's UDP sockets (their receive buffers full)."""
    inodes = set()
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            link = os.readlink(f"/proc/{pid}/fd/{fd}")
        except OSError:
            continue
        m = re.match(r"socket:\[(\d+)\]", link)
        if m:
            inodes.add(m.group(1))
    drops = 0
    with open(f"/proc/{pid}/net/udp") as f:
        next(f)
        for line in f:
            cols = line.split()
            if cols[9] in inodes:
                drops += int(cols[-1])
    return drops


def builds_running():
    for name in ("ninja", "cc1plus"):
        if subprocess.run(["pgrep", "-x", name], stdout=subprocess.DEVNULL).returncode == 0:
            return True
    return False


class Viewer:
    """One dashboard page: the RFC 6455 handshake on /ws (blocking), then its frames, read by Viewers' loop."""

    def __init__(self, port):
        self.frames = self.bytes = 0
        self.connected = False
        self.error = ""
        self.buf = bytearray()
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n")
                          .encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError("closed during the handshake")
            head += chunk
        head, rest = head.split(b"\r\n\r\n", 1)
        if not head.startswith(b"HTTP/1.1 101"):
            raise ConnectionError(head.split(b"\r\n")[0].decode(errors="replace"))
        self.buf += rest
        self.connected = True
        self.sock.setblocking(False)

    def feed(self, chunk):
        """Counts the whole frames in the buffer (server frames: unmasked; 7-, 16- or 64-bit length)."""
        b = self.buf
        b += chunk
        at = 0
        while len(b) - at >= 2:
            n = b[at + 1] & 0x7F
            h = 2
            if n == 126:
                if len(b) - at < 4:
                    break
                n, h = struct.unpack_from(">H", b, at + 2)[0], 4
            elif n == 127:
                if len(b) - at < 10:
                    break
                n, h = struct.unpack_from(">Q", b, at + 2)[0], 10
            if len(b) - at < h + n:
                break
            opcode = b[at] & 0x0F
            if opcode == 0x8:
                raise ConnectionError("closed by the dashboard")
            if opcode == 0x9:  # ping: a masked pong with the same payload
                payload = bytes(b[at + h:at + h + n])
                self.sock.sendall(bytes([0x8A, 0x80 | len(payload)]) + b"\0\0\0\0" + payload)
            else:
                self.frames += 1
                self.bytes += n
            at += h + n
        del b[:at]


class Viewers(threading.Thread):
    """Every viewer's socket in one thread (selectors): cheaper than a thread each, and fair."""

    def __init__(self, port, count):
        super().__init__(daemon=True)
        self.viewers, self.stop = [], threading.Event()
        self.refused = []
        for _ in range(count):
            try:
                self.viewers.append(Viewer(port))
            except Exception as e:  # noqa: BLE001 — a refused page is a result
                self.refused.append(str(e) or type(e).__name__)

    def run(self):
        sel = selectors.DefaultSelector()
        for v in self.viewers:
            sel.register(v.sock, selectors.EVENT_READ, v)
        while not self.stop.is_set():
            for key, _ in sel.select(timeout=0.2):
                v = key.data
                try:
                    chunk = v.sock.recv(262144)
                    if not chunk:
                        raise ConnectionError("connection closed")
                    v.feed(chunk)
                except BlockingIOError:
                    continue
                except Exception as e:  # noqa: BLE001 — reported per viewer
                    v.error, v.connected = str(e) or type(e).__name__, False
                    sel.unregister(v.sock)
        for v in self.viewers:
            v.sock.close()


def read_log(path, state_prefix, accel_channel):
    """Latencies from the monitor's --log: per wall_state_t, publish − sample utime, publish − receive [µs]."""
    received = {}  # input seq -> receive time (log time of the input event)
    to_state, to_publish = [], []
    per_wall = {}
    with open(path, "rb") as f:
        data = f.read()
    at, n = 0, len(data)
    while at + 28 <= n:
        sync, _number, t, clen, dlen = struct.unpack_from(">IqqII", data, at)
        if sync != 0xEDA1DA01 or at + 28 + clen + dlen > n:
            break
        channel = data[at + 28:at + 28 + clen].decode()
        payload = at + 28 + clen + 8  # after the 8-byte LCM fingerprint
        if channel == accel_channel:
            _utime, seq = struct.unpack_from(">qq", data, payload)
            received.setdefault(seq, t)
        elif channel.startswith(state_prefix):
            utime, _seq, input_seq = struct.unpack_from(">qqq", data, payload)
            to_state.append(t - utime)
            r = received.get(input_seq)
            if r is not None:
                to_publish.append(t - r)
            per_wall[channel] = per_wall.get(channel, 0) + 1
        at += 28 + clen + dlen
    return to_state, to_publish, per_wall


def percentiles(values):
    if not values:
        return {}
    v = sorted(values)

    def p(q):
        return v[min(len(v) - 1, int(q * len(v)))]
    return {"n": len(v), "p50_us": p(0.50), "p99_us": p(0.99), "p999_us": p(0.999), "max_us": v[-1]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--walls", type=int, default=64, help="walls of the one monitor (default 64)")
    ap.add_argument("--rate", type=float, default=1000.0, help="samples per second of the ground stream (default 1000)")
    ap.add_argument("--viewers", type=int, default=50, help="WebSocket viewers of the dashboard (default 50; 0: no dashboard)")
    ap.add_argument("--pga", type=float, default=0.3, help="scale of the record's peak ground acceleration [g] (default 0.3)")
    ap.add_argument("--seconds", type=float, default=20.0, help="seconds of record replayed (default 20, the whole record)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"), help="build tree (default build/release)")
    ap.add_argument("--monitor", help="rockwatch-monitor (default BUILD/host_tools/rockwatch-monitor)")
    ap.add_argument("--rockwatch", help="rockwatch (default BUILD/host_tools/rockwatch)")
    ap.add_argument("--lcm-url", help="LCM URL (default: a random group and port, ttl=0)")
    ap.add_argument("--monitor-args", default="", help="more options for rockwatch-monitor, e.g. '--realtime 50'")
    ap.add_argument("--keep", help="keep the files (config, log, outputs) in this directory")
    ap.add_argument("--json", help="write the figures as JSON to this file")
    ap.add_argument("--no-wait-idle", action="store_true", help="do not wait for running compilers to finish")
    o = ap.parse_args()
    if not 1 <= o.walls <= 1024 or o.rate <= 0 or o.viewers < 0 or o.seconds <= 0:
        ap.error("--walls 1..1024, --rate > 0, --viewers >= 0, --seconds > 0")
    monitor = o.monitor or os.path.join(o.build, "host_tools", "rockwatch-monitor")
    rockwatch = o.rockwatch or os.path.join(o.build, "host_tools", "rockwatch")
    for p in (monitor, rockwatch):
        if not os.access(p, os.X_OK):
            print(f"load-test: {p}: not found (build it, or --build / --monitor / --rockwatch)", file=sys.stderr)
            return 2
    url = o.lcm_url or f"udpm://239.255.76.{random.randint(151, 190)}:{random.randint(7751, 7950)}?ttl=0"
    if not o.no_wait_idle:
        waited = 0
        while builds_running() and waited < 600:
            if waited == 0:
                print("load-test: a build is running; waiting for it to finish (--no-wait-idle: measure anyway)")
            time.sleep(5)
            waited += 5
    load_before = os.getloadavg()

    work = o.keep or tempfile.mkdtemp(prefix="rockwatch-load-", dir="/dev/shm" if os.path.isdir("/dev/shm") else None)
    os.makedirs(work, exist_ok=True)
    names = [f"w{i:02d}" for i in range(o.walls)]
    config = {"sample_rate_hz": o.rate, "walls": [{"name": n} for n in names]}
    with open(os.path.join(work, "walls.json"), "w") as f:
        json.dump(config, f)
    log_path = os.path.join(work, "monitor.lcmlog")
    procs = []

    def start(args, name):
        p = subprocess.Popen(args, stdout=open(os.path.join(work, name + ".out"), "w"),
                             stderr=open(os.path.join(work, name + ".err"), "w"), stdin=subprocess.DEVNULL)
        procs.append(p)
        return p

    group = None
    viewers = []
    try:
        mon = start([monitor, "--config", os.path.join(work, "walls.json"), "--lcm-url", url, "--log", log_path]
                    + o.monitor_args.split(), "monitor")
        dash = None
        port = None
        if o.viewers > 0:
            dash = start([rockwatch, "dashboard", "--lcm-url", url, "--http", "127.0.0.1:0"], "dashboard")
            deadline = time.monotonic() + 15
            while port is None and time.monotonic() < deadline:
                m = re.search(r"serving on http://127\.0\.0\.1:(\d+)/", open(os.path.join(work, "dashboard.out")).read())
                port = int(m.group(1)) if m else None
                time.sleep(0.1)
            if port is None:
                print("load-test: the dashboard did not say its port", file=sys.stderr)
                return 2
            group = Viewers(port, o.viewers)
            viewers = group.viewers
            group.start()
        time.sleep(2.0)  # the monitor's start-up, the viewers' handshakes
        if mon.poll() is not None:
            print("load-test: the monitor stopped at start:\n" + open(os.path.join(work, "monitor.err")).read(),
                  file=sys.stderr)
            return 2
        cpu0 = {"monitor": cpu_seconds(mon.pid)}
        if dash:
            cpu0["dashboard"] = cpu_seconds(dash.pid)
        drops0 = udp_drops(mon.pid)
        self0 = os.times()
        t0 = time.monotonic()
        replay = start([rockwatch, "replay", "--suite", os.path.join(ROOT, "sim", "suites", "npr9998-2015"), "--set",
                        "1", "--component", "X", "--scale-pga", str(o.pga), "--rate", str(o.rate), "--lcm-url", url,
                        "--json"], "replay")
        try:
            replay.wait(timeout=o.seconds + 0.5)
        except subprocess.TimeoutExpired:
            replay.send_signal(signal.SIGINT)
            replay.wait(timeout=20)
        time.sleep(0.5)  # the last samples through the monitor
        elapsed = time.monotonic() - t0
        cpu1 = {"monitor": cpu_seconds(mon.pid)}
        if dash:
            cpu1["dashboard"] = cpu_seconds(dash.pid)
        drops = udp_drops(mon.pid) - drops0
        self1 = os.times()
        cpu1["viewers (this script)"] = self1.user + self1.system
        cpu0["viewers (this script)"] = self0.user + self0.system
        connected = sum(1 for v in viewers if v.connected)
        if group:
            group.stop.set()
            group.join(timeout=5)
        mon.send_signal(signal.SIGTERM)
        if dash:
            dash.send_signal(signal.SIGTERM)
        mon.wait(timeout=30)
        if dash:
            dash.wait(timeout=30)
    finally:
        if group:
            group.stop.set()
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()

    # ----- figures
    def last_json(path, key):
        found = None
        for line in open(path):
            try:
                j = json.loads(line)
            except ValueError:
                continue
            if isinstance(j, dict) and (key is None or key in j):
                found = j
        return found

    summary = (last_json(os.path.join(work, "monitor.out"), "summary") or {}).get("summary", {})
    try:  # the replay's --json summary (also written when SIGINT stops it)
        sent = json.load(open(os.path.join(work, "replay.out"))).get("samples_sent")
    except ValueError:
        sent = None
    walls = summary.get("walls", [])
    bad = []
    for w in walls:
        c = w["counters"]
        lost = (sent - c["samples_received"]) if sent is not None else None
        faults = {k: c[k] for k in ("gaps", "state_resets", "duplicates", "out_of_order") if c.get(k)}
        if lost or faults:
            bad.append({"wall": w["name"], "lost": lost, **faults})
    to_state, to_publish, per_wall = read_log(log_path, "ROCKWATCH_WALL_STATE_", "ROCKWATCH_ACCEL")
    cpu = {k: cpu1[k] - cpu0[k] for k in cpu1}
    dash_line = ""
    if dash:
        err = open(os.path.join(work, "dashboard.out")).read() + open(os.path.join(work, "dashboard.err")).read()
        m = re.search(r"rockwatch dashboard: stopped[^\n]*", err)
        dash_line = m.group(0) if m else ""
    result = {
        "walls": o.walls, "rate_hz": o.rate, "viewers": o.viewers, "pga_g": o.pga, "lcm_url": url,
        "monitor_args": o.monitor_args,
        "replay_seconds": round(elapsed, 2), "load_average_before": [round(x, 2) for x in load_before],
        "samples_sent": sent,
        "walls_in_summary": len(walls),
        "walls_with_dropped_samples": bad,
        "kernel_drops_at_monitor_sockets": drops,
        "wall_states_in_log": sum(per_wall.values()),
        "log": summary.get("log", {}),
        "latency_sample_to_state": percentiles(to_state),
        "latency_receive_to_publish": percentiles(to_publish),
        "cpu_s": {k: round(v, 3) for k, v in cpu.items()},
        "monitor_cpu_percent_of_core": round(100 * cpu["monitor"] / elapsed, 1),
        "monitor_cpu_percent_per_wall": round(100 * cpu["monitor"] / elapsed / o.walls, 3),
        "monitor_cpu_us_per_wall_sample": round(1e6 * cpu["monitor"] / (o.walls * sent), 3) if sent else None,
        "worst_step_ns": max((w["counters"].get("worst_step_ns", 0) for w in walls), default=None),
        "viewers_connected_at_end": connected,
        "viewer_frames_min": min((v.frames for v in viewers), default=0),
        "viewer_frames_total": sum(v.frames for v in viewers),
        "viewer_bytes_total": sum(v.bytes for v in viewers),
        "viewer_errors": sorted({v.error for v in viewers if v.error} | set(group.refused if group else [])),
        "dashboard": dash_line,
    }
    if dash:
        result["dashboard_cpu_percent_of_core"] = round(100 * cpu["dashboard"] / elapsed, 1)
    print(json.dumps(result, indent=1))
    if o.json:
        with open(o.json, "w") as f:
            json.dump(result, f, indent=1)
    if not o.keep:
        shutil.rmtree(work, ignore_errors=True)
    ok = (not bad and len(walls) == o.walls and connected == o.viewers and sent is not None)
    print("load-test: " + ("PASS" if ok else "FAIL") + f": {o.walls} walls at {o.rate:g} Hz, {o.viewers} viewers; "
          f"{len(bad)} walls with dropped samples; p99 sample to state "
          f"{result['latency_sample_to_state'].get('p99_us')} us; monitor CPU "
          f"{result['monitor_cpu_percent_of_core']} % of a core ({result['monitor_cpu_percent_per_wall']} % per wall)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
