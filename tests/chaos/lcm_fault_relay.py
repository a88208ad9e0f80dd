#!/usr/bin/python3
"""A fault-injecting relay for LCM over UDP multicast, and the same seeded fault schedule applied offline to an LCM log.

Live (issue 41):
    lcm_fault_relay.py --in 'udpm://239.255.76.141:7741?ttl=0' --out 'udpm://239.255.76.142:7742?ttl=0' \
        --seed 7 --loss 0.05 --burst 0.0005 --burst-len 50 --dup 0.02 --reorder 0.02 --corrupt 0.01 \
        --truncate 0.002 --delay-ms 1 --jitter-ms 0.5 --log relay.jsonl [--duration S] [--idle-exit S]
  joins the input group, re-sends every datagram to the output group (ttl 0, multicast loop on) with the faults
  below, and writes a JSON-lines log of exactly what it did. SIGINT/SIGTERM (or --duration, --idle-exit) ends it:
  held datagrams are released, the log closed.
Offline:
    lcm_fault_relay.py --offline-in clean.lcmlog --offline-out faulty.lcmlog --seed 7 --loss 0.05 [...] [--log F]
  each event of the log is one datagram (its LC02 frame: magic, the event number as LCM sequence, channel, data);
  the schedule is applied in the same way and the frames the monitor's receive path would accept are written as
  events (timestamp = the event's + delay, never before the previous event written) in delivery order.

The schedule is a pure function of (seed, arrival index, datagram): the same seed and the same input replay the same
faults. Per arrival index i (a datagram received, or a log event), with u(i, tag) uniform in [0, 1) from
blake2b(seed, i, tag):
  burst   i lies in [j, j + L) for a j with u(j, "burst") < --burst (L = --burst-len), or in [k, k + L) for a
          --burst-at k: not sent ("burst");
  loss    else u(i, "loss") < --loss: not sent ("lost");
  truncate u(i, "truncate") < --truncate: cut to a length drawn in [0, len);
  corrupt u(i, "corrupt") < --corrupt: 1..--corrupt-bytes bytes at drawn positions XORed with drawn non-zero
          bytes (positions over the whole datagram, header included). A corruption never forges an LC03 fragment
          header: if the first four bytes come out as "LC03" the fourth is XORed with 0x80 too ("LC0\\xb3": a bad
          magic), so every corrupted datagram is a single (LC02) datagram or rejected;
  dup     u(i, "dup") < --dup: sent twice, back to back;
  reorder u(i, "reorder") < --reorder: held, and released after k later arrivals (k drawn in 1..--reorder-max);
  delay   every copy is sent --delay-ms + u(i, "jitter") * --jitter-ms after its arrival (or release).

Log (JSON lines): first {"relay": {seed, faults, in, out, argv, replay}}; per arrival
{"i", "t_us" (CLOCK_REALTIME at arrival), "len", "lcm_seq", "channel", "seq" (the message's sample seq when it
parses as a rockwatch input), "actions": [...], "sha1" of the datagram}; per datagram sent
{"send" (send order from 0), "i", "t_us" (CLOCK_REALTIME at send), "len", "hex" (the bytes sent; --log-bytes
modified: only for corrupted / truncated ones, else "sha1")}; last {"end": {arrivals, sent, by action}}.
"""

import argparse
import hashlib
import heapq
import json
import os
import select
import signal
import socket
import struct
import sys
import time
import urllib.parse

MAGIC_SHORT = 0x4C433032  # "LC02"
MAGIC_FRAGMENT = 0x4C433033  # "LC03"
LOG_SYNC = 0xEDA1DA01

# ---------------------------------------------------------------------------------------------------------------
# LCM wire format and logs


def _signed64(v):
    v &= 0xFFFFFFFFFFFFFFFF
    return v - (1 << 64) if v >= (1 << 63) else v


def lcm_hash_update(v, c):
    """lcm-gen's hash step on a signed 64-bit v and a signed char c: v = ((v << 8) ^ (v >> 55)) + c."""
    return _signed64((_signed64(v << 8) ^ (v >> 55)) + c)


def lcm_hash_string(v, s):
    v = lcm_hash_update(v, len(s))
    for ch in s.encode():
        v = lcm_hash_update(v, ch if ch < 128 else ch - 256)
    return v


def lcm_fingerprint(members):
    """lcm-gen's fingerprint of a struct of primitive members [(name, type, [array dims])], as encoded (rotated)."""
    v = 0x12345678
    for name, typ, dims in members:
        v = lcm_hash_string(v, name)
        v = lcm_hash_string(v, typ)
        v = lcm_hash_update(v, len(dims))
        for d in dims:
            v = lcm_hash_update(v, 0)  # LCM_CONST dimension
            v = lcm_hash_string(v, str(d))
    u = v & 0xFFFFFFFFFFFFFFFF
    return ((u << 1) & 0xFFFFFFFFFFFFFFFF) | (u >> 63)


# The monitor's input types (firmware/lcmtypes/*.lcm): members in order.
GROUND_ACCEL_MEMBERS = [("utime", "int64_t", []), ("seq", "int64_t", []), ("schema_version", "int32_t", []),
                        ("ug_mps2", "double", []), ("vg_mps2", "double", []), ("sensor_status", "int32_t", [])]
GROUND_BATCH_MEMBERS = [("utime", "int64_t", []), ("seq", "int64_t", []), ("schema_version", "int32_t", []),
                        ("sample_period_us", "int32_t", []), ("count", "int32_t", []),
                        ("ug_mps2", "double", [50]), ("vg_mps2", "double", [50]), ("sensor_status", "int32_t", [])]
WALL_SENSOR_MEMBERS = [("utime", "int64_t", []), ("seq", "int64_t", []), ("schema_version", "int32_t", []),
                       ("x_mid_m", "double", []), ("a_mid_mps2", "double", []), ("valid", "int32_t", []),
                       ("sensor_status", "int32_t", [])]
FP_GROUND_ACCEL = lcm_fingerprint(GROUND_ACCEL_MEMBERS)
FP_GROUND_BATCH = lcm_fingerprint(GROUND_BATCH_MEMBERS)
FP_WALL_SENSOR = lcm_fingerprint(WALL_SENSOR_MEMBERS)
GROUND_ACCEL_SIZE = 8 + 8 + 8 + 4 + 8 + 8 + 4
GROUND_BATCH_SIZE = 8 + 8 + 8 + 4 + 4 + 4 + 400 + 400 + 4
WALL_SENSOR_SIZE = 8 + 8 + 8 + 4 + 8 + 8 + 4 + 4


def decode_ground_accel(data):
    """(utime, seq, schema, ug, vg, status) or None when lcm-gen's decode() would fail (fingerprint, size)."""
    if len(data) != GROUND_ACCEL_SIZE or struct.unpack_from(">Q", data, 0)[0] != FP_GROUND_ACCEL:
        return None
    return struct.unpack_from(">qqiddi", data, 8)


def decode_ground_batch(data):
    """(utime, seq, schema, period_us, count, ug[50], vg[50], status) or None."""
    if len(data) != GROUND_BATCH_SIZE or struct.unpack_from(">Q", data, 0)[0] != FP_GROUND_BATCH:
        return None
    utime, seq, schema, period, count = struct.unpack_from(">qqiii", data, 8)
    ug = struct.unpack_from(">50d", data, 36)
    vg = struct.unpack_from(">50d", data, 436)
    status = struct.unpack_from(">i", data, 836)[0]
    return utime, seq, schema, period, count, ug, vg, status


def decode_wall_sensor(data):
    """(utime, seq, schema, x, a, valid, status) or None."""
    if len(data) != WALL_SENSOR_SIZE or struct.unpack_from(">Q", data, 0)[0] != FP_WALL_SENSOR:
        return None
    return struct.unpack_from(">qqiddii", data, 8)


def encode_lc02(channel, data, lcm_seq):
    return struct.pack(">II", MAGIC_SHORT, lcm_seq & 0xFFFFFFFF) + channel.encode() + b"\0" + bytes(data)


MAX_CHANNEL = 63
# The monitor's reject reasons (firmware/include/rockwatch/firmware/lcm_datagram.hpp, DatagramReject).
REJECT_TRUNCATED_HEADER = "truncated_header"
REJECT_BAD_MAGIC = "bad_magic"
REJECT_CHANNEL_UNTERMINATED = "channel_unterminated"
REJECT_CHANNEL_LENGTH = "channel_length"


def parse_datagram(b):
    """The monitor's reassembler on one datagram with no fragment in flight (LcmDatagramReassembler::accept):
    ("message", channel (str, latin-1), payload, lcm_seq) | ("rejected", reason) | ("fragment", None)."""
    if len(b) < 4:
        return ("rejected", REJECT_TRUNCATED_HEADER)
    magic = struct.unpack_from(">I", b, 0)[0]
    if magic == MAGIC_FRAGMENT:
        return ("fragment", None)
    if magic != MAGIC_SHORT:
        return ("rejected", REJECT_BAD_MAGIC)
    if len(b) < 8:
        return ("rejected", REJECT_TRUNCATED_HEADER)
    avail = len(b) - 8
    limit = min(avail, MAX_CHANNEL + 1)
    nul = b.find(b"\0", 8, 8 + limit)
    if nul < 0:
        return ("rejected", REJECT_CHANNEL_LENGTH if avail > MAX_CHANNEL else REJECT_CHANNEL_UNTERMINATED)
    if nul == 8:
        return ("rejected", REJECT_CHANNEL_LENGTH)
    return ("message", b[8:nul].decode("latin-1"), b[nul + 1:], struct.unpack_from(">I", b, 4)[0])


def describe(b):
    """(lcm_seq, channel, sample seq) of a datagram where they parse; None for what does not."""
    p = parse_datagram(b)
    if p[0] != "message":
        return None, None, None
    _, channel, payload, lcm_seq = p
    seq = None
    for dec in (decode_ground_accel, decode_ground_batch, decode_wall_sensor):
        m = dec(payload)
        if m is not None:
            seq = m[1]
            break
    return lcm_seq, channel, seq


def iter_lcm_log(path):
    """Events of an LCM log, streamed: (event_number, timestamp_us, channel, data). A torn last event ends it."""
    with open(path, "rb") as f:
        pos = 0
        while True:
            head = f.read(28)
            if len(head) < 28:
                return
            sync, num, ts, clen, dlen = struct.unpack(">IqqiI", head)
            if sync != LOG_SYNC:
                raise ValueError(f"{path}: not an LCM log (no sync word at byte {pos})")
            if clen < 0:
                return
            body = f.read(clen + dlen)
            if len(body) < clen + dlen:
                return
            pos += 28 + clen + dlen
            yield num, ts, body[:clen].decode("latin-1"), body[clen:]


def read_lcm_log(path):
    """Events of an LCM log: [(event_number, timestamp_us, channel, data)]. A torn last event ends the list."""
    return list(iter_lcm_log(path))


def write_lcm_log(path, events):
    """events: [(timestamp_us, channel, data)], numbered from 0."""
    with open(path, "wb") as f:
        for n, (ts, channel, data) in enumerate(events):
            c = channel.encode("latin-1")
            f.write(struct.pack(">IqqiI", LOG_SYNC, n, ts, len(c), len(data)) + c + bytes(data))


# ---------------------------------------------------------------------------------------------------------------
# The schedule


FAULT_KEYS = ("loss", "burst", "burst_len", "burst_at", "dup", "reorder", "reorder_max", "corrupt", "corrupt_bytes",
              "truncate", "delay_ms", "jitter_ms")


class FaultSchedule:
    """Fault decisions as a pure function of (seed, arrival index, datagram)."""

    def __init__(self, seed, loss=0.0, burst=0.0, burst_len=50, burst_at=(), dup=0.0, reorder=0.0, reorder_max=3,
                 corrupt=0.0, corrupt_bytes=1, truncate=0.0, delay_ms=0.0, jitter_ms=0.0):
        for name, p in (("loss", loss), ("burst", burst), ("dup", dup), ("reorder", reorder), ("corrupt", corrupt),
                        ("truncate", truncate)):
            if not 0.0 <= p <= 1.0:
                raise ValueError(f"--{name} {p}: a probability in [0, 1]")
        if burst_len < 1 or reorder_max < 1 or corrupt_bytes < 1:
            raise ValueError("--burst-len, --reorder-max and --corrupt-bytes must be at least 1")
        if delay_ms < 0 or jitter_ms < 0:
            raise ValueError("--delay-ms and --jitter-ms must not be negative")
        if not 0 <= seed < 2 ** 64:
            raise ValueError(f"--seed {seed}: 0 to 2^64-1")
        self.seed = seed
        self.loss, self.burst, self.burst_len, self.burst_at = loss, burst, burst_len, sorted(set(burst_at))
        self.dup, self.reorder, self.reorder_max = dup, reorder, reorder_max
        self.corrupt, self.corrupt_bytes, self.truncate = corrupt, corrupt_bytes, truncate
        self.delay_ms, self.jitter_ms = delay_ms, jitter_ms

    def params(self):
        return {k: getattr(self, k) for k in ("seed",) + FAULT_KEYS}

    def _bytes(self, i, tag, n=8):
        return hashlib.blake2b(f"{i}:{tag}".encode(), digest_size=n, key=self.seed.to_bytes(8, "big")).digest()

    def u(self, i, tag):
        return int.from_bytes(self._bytes(i, tag), "big") / 2.0 ** 64

    def draw(self, i, tag, n):
        """An integer in [0, n)."""
        return int.from_bytes(self._bytes(i, tag), "big") % n

    def in_burst(self, i):
        if self.burst > 0:
            for j in range(max(0, i - self.burst_len + 1), i + 1):
                if self.u(j, "burst") < self.burst:
                    return True
        return any(k <= i < k + self.burst_len for k in self.burst_at)

    def decide(self, i, datagram):
        """-> (actions [str], bytes to send or None when not sent, copies, hold k (0: none), delay_s)."""
        if self.in_burst(i):
            return ["burst"], None, 0, 0, 0.0
        if self.loss > 0 and self.u(i, "loss") < self.loss:
            return ["lost"], None, 0, 0, 0.0
        actions = []
        b = bytearray(datagram)
        if self.truncate > 0 and self.u(i, "truncate") < self.truncate and len(b) > 0:
            n = self.draw(i, "truncate-len", len(b))
            del b[n:]
            actions.append(f"truncate:{n}")
        if self.corrupt > 0 and self.u(i, "corrupt") < self.corrupt and len(b) > 0:
            flips = 1 + self.draw(i, "corrupt-n", self.corrupt_bytes)
            for k in range(flips):
                pos = self.draw(i, f"corrupt-pos{k}", len(b))
                x = 1 + self.draw(i, f"corrupt-xor{k}", 255)
                b[pos] ^= x
                actions.append(f"corrupt:{pos}^{x:#04x}")
            if bytes(b[:4]) == b"LC03":
                b[3] ^= 0x80
                actions.append("corrupt:3^0x80(no-LC03)")
        copies = 1
        if self.dup > 0 and self.u(i, "dup") < self.dup:
            copies = 2
            actions.append("dup")
        hold = 0
        if self.reorder > 0 and self.u(i, "reorder") < self.reorder:
            hold = 1 + self.draw(i, "reorder-k", self.reorder_max)
            actions.append(f"hold:{hold}")
        delay = (self.delay_ms + self.u(i, "jitter") * self.jitter_ms) * 1e-3 if self.delay_ms or self.jitter_ms else 0.0
        if not actions:
            actions.append("pass")
        return actions, bytes(b), copies, hold, delay


class ScheduleRunner:
    """Applies a FaultSchedule to a stream of arrivals: the sends in order (before delays) and the log records.
    on_arrival(i, datagram, t) -> [(due_time, i, bytes, modified)] released by this arrival, in order."""

    def __init__(self, schedule, time_unit=1.0):
        self.s = schedule
        self.unit = time_unit  # the arrival times' unit per second (1: seconds, 1e6: microseconds)
        self.held = []  # [remaining arrivals, i, bytes, copies, delay, modified]
        self.counts = {}

    def _count(self, a):
        key = a.split(":")[0]
        self.counts[key] = self.counts.get(key, 0) + 1

    def on_arrival(self, i, datagram, t):
        actions, b, copies, hold, delay = self.s.decide(i, datagram)
        for a in actions:
            self._count(a)
        record = {"i": i, "len": len(datagram), "actions": actions, "sha1": hashlib.sha1(datagram).hexdigest()}
        lcm_seq, channel, seq = describe(datagram)
        record.update({"lcm_seq": lcm_seq, "channel": channel, "seq": seq})
        modified = b is not None and b != datagram
        out = []
        if b is not None and hold == 0:
            out += [(t + delay * self.unit, i, b, modified)] * copies
        # Held ones count this arrival; those due now follow (after this arrival's own copies).
        still = []
        for h in self.held:
            h[0] -= 1
            if h[0] <= 0:
                out += [(t + h[4] * self.unit, h[1], h[2], h[5])] * h[3]
            else:
                still.append(h)
        self.held = still
        if b is not None and hold > 0:
            self.held.append([hold, i, b, copies, delay, modified])
        return record, out

    def flush(self, t):
        out = []
        for h in self.held:
            out += [(t + h[4] * self.unit, h[1], h[2], h[5])] * h[3]
        self.held = []
        return out


def schedule_from_args(a):
    return FaultSchedule(a.seed, loss=a.loss, burst=a.burst, burst_len=a.burst_len, burst_at=a.burst_at or (),
                         dup=a.dup, reorder=a.reorder, reorder_max=a.reorder_max, corrupt=a.corrupt,
                         corrupt_bytes=a.corrupt_bytes, truncate=a.truncate, delay_ms=a.delay_ms,
                         jitter_ms=a.jitter_ms)


def fault_args(schedule):
    """The command-line options that rebuild `schedule`."""
    p = schedule.params()
    out = ["--seed", str(p["seed"])]
    for k in FAULT_KEYS:
        v = p[k]
        if k == "burst_at":
            for x in v:
                out += ["--burst-at", str(x)]
            continue
        defaults = {"burst_len": 50, "reorder_max": 3, "corrupt_bytes": 1}
        if v != defaults.get(k, 0.0):
            out += ["--" + k.replace("_", "-"), f"{v:g}" if isinstance(v, float) else str(v)]
    return out


# ---------------------------------------------------------------------------------------------------------------
# Offline: a log in, a log out


def apply_offline(schedule, events, log=None):
    """events: [(num, ts, channel, data)] -> [(ts, channel, data)] as the monitor would receive them, and the
    records (arrivals and sends) that the live relay would log."""
    runner = ScheduleRunner(schedule, time_unit=1e6)
    out, records, sends = [], [], []
    last_ts = None

    def deliver(pending):
        nonlocal last_ts
        for due_us, i, b, modified in pending:
            ts = int(round(due_us))
            if last_ts is not None and ts < last_ts:
                ts = last_ts
            last_ts = ts
            rec = {"send": len(sends), "i": i, "t_us": ts, "len": len(b), "hex": b.hex()}
            sends.append(rec)
            records.append(rec)
            p = parse_datagram(b)
            if p[0] == "message":
                out.append((ts, p[1], p[2]))

    for i, (num, ts, channel, data) in enumerate(events):
        frame = encode_lc02(channel, data, num)
        record, pending = runner.on_arrival(i, frame, ts)
        record["t_us"] = ts
        records.append(record)
        deliver(pending)
    deliver(runner.flush(events[-1][1] if events else 0))
    if log is not None:
        for r in records:
            log.write(json.dumps(r) + "\n")
        log.write(json.dumps({"end": {"arrivals": len(events), "sent": len(sends), "actions": runner.counts}}) + "\n")
    return out, records, runner.counts


# ---------------------------------------------------------------------------------------------------------------
# Live


def parse_udpm(url, what):
    u = urllib.parse.urlparse(url)
    if u.scheme != "udpm" or not u.hostname or not u.port:
        raise ValueError(f"{what} {url!r}: expected udpm://GROUP:PORT[?ttl=0]")
    try:
        group = socket.inet_aton(u.hostname)
    except OSError:
        raise ValueError(f"{what} {url!r}: {u.hostname!r} is not an IPv4 address") from None
    if not 224 <= group[0] <= 239:
        raise ValueError(f"{what} {url!r}: {u.hostname} is not a multicast group (224.0.0.0/4)")
    q = urllib.parse.parse_qs(u.query)
    ttl = int(q.get("ttl", ["0"])[0])
    return u.hostname, u.port, ttl


def open_input(group, port):
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    if hasattr(socket, "SO_REUSEPORT"):
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
    s.bind(("", port))
    mreq = struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0"))
    s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, mreq)
    s.setblocking(False)
    return s


def open_output(ttl):
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, ttl)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    return s


def realtime_us():
    return time.time_ns() // 1000


def run_live(a, schedule, log):
    in_group, in_port, _ = parse_udpm(a.in_url, "--in")
    out_group, out_port, out_ttl = parse_udpm(a.out_url, "--out")
    if (in_group, in_port) == (out_group, out_port):
        raise ValueError("--in and --out name the same group and port: the relay would feed itself")
    try:
        sin = open_input(in_group, in_port)
        sout = open_output(out_ttl)
    except OSError as e:
        print(f"lcm_fault_relay: cannot open the sockets ({e}); a multicast route? "
              "(scripts/multicast-route.sh)", file=sys.stderr)
        return 77
    stop = []
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.append(1))
    runner = ScheduleRunner(schedule)
    queue = []  # (due monotonic, order, i, bytes, modified)
    order = 0
    sent = 0
    arrivals = 0
    t_start = time.monotonic()
    last_arrival = t_start
    if a.ready_file:
        with open(a.ready_file, "w") as f:
            f.write("ready\n")

    def enqueue(pending):
        nonlocal order
        for due, i, b, modified in pending:
            heapq.heappush(queue, (due, order, i, b, modified))
            order += 1

    def send_due(now):
        nonlocal sent
        while queue and queue[0][0] <= now:
            _, _, i, b, modified = heapq.heappop(queue)
            try:
                sout.sendto(b, (out_group, out_port))
            except OSError as e:
                log.write(json.dumps({"send_error": str(e), "i": i}) + "\n")
                continue
            rec = {"send": sent, "i": i, "t_us": realtime_us(), "len": len(b)}
            if a.log_bytes == "all" or modified:
                rec["hex"] = b.hex()
            else:
                rec["sha1"] = hashlib.sha1(b).hexdigest()
            log.write(json.dumps(rec) + "\n")
            sent += 1

    while not stop:
        now = time.monotonic()
        if a.duration and now - t_start >= a.duration:
            break
        if a.idle_exit and arrivals > 0 and now - last_arrival >= a.idle_exit:
            break
        send_due(now)
        timeout = 0.05 if not queue else max(0.0, min(0.05, queue[0][0] - now))
        try:
            r, _, _ = select.select([sin], [], [], timeout)
        except InterruptedError:
            continue
        if not r:
            continue
        while True:
            try:
                datagram = sin.recv(65536)
            except BlockingIOError:
                break
            except InterruptedError:
                continue
            t = time.monotonic()
            last_arrival = t
            record, pending = runner.on_arrival(arrivals, datagram, t)
            record["t_us"] = realtime_us()
            log.write(json.dumps(record) + "\n")
            arrivals += 1
            enqueue(pending)
            send_due(time.monotonic())
    enqueue(runner.flush(time.monotonic()))
    while queue:
        time.sleep(max(0.0, queue[0][0] - time.monotonic()))
        send_due(time.monotonic())
    log.write(json.dumps({"end": {"arrivals": arrivals, "sent": sent, "actions": runner.counts}}) + "\n")
    print(f"lcm_fault_relay: {arrivals} datagrams in, {sent} sent; {runner.counts}", file=sys.stderr)
    return 0


def build_parser():
    p = argparse.ArgumentParser(
        description="Seeded fault-injecting relay for LCM over UDP multicast (live), or the same schedule applied to "
                    "an LCM log (offline). See the module's docstring for the schedule and the log.")
    p.add_argument("--in", dest="in_url", help="live: the LCM URL the publisher sends to (udpm://GROUP:PORT?ttl=0)")
    p.add_argument("--out", dest="out_url", help="live: the LCM URL the monitor listens on")
    p.add_argument("--offline-in", help="offline: an LCM log to apply the schedule to")
    p.add_argument("--offline-out", help="offline: the LCM log written (what the monitor would receive)")
    p.add_argument("--log", help="JSON-lines log of what was done to each datagram (default: none offline, "
                                 "required live)")
    p.add_argument("--log-bytes", choices=("all", "modified"), default="all",
                   help="live: log the bytes sent of every datagram (all, default) or only of modified ones")
    p.add_argument("--seed", type=int, default=1, help="seed of the schedule, 0 to 2^64-1 (default 1)")
    p.add_argument("--loss", type=float, default=0.0, help="probability that a datagram is lost")
    p.add_argument("--burst", type=float, default=0.0, help="probability that a loss burst starts at a datagram")
    p.add_argument("--burst-len", type=int, default=50, help="datagrams lost in a burst (default 50)")
    p.add_argument("--burst-at", type=int, action="append", help="a burst starts at this arrival index (repeatable)")
    p.add_argument("--dup", type=float, default=0.0, help="probability that a datagram is sent twice")
    p.add_argument("--reorder", type=float, default=0.0,
                   help="probability that a datagram is held and released after k later arrivals")
    p.add_argument("--reorder-max", type=int, default=3, help="largest k of --reorder (default 3)")
    p.add_argument("--corrupt", type=float, default=0.0, help="probability that bytes of a datagram are flipped")
    p.add_argument("--corrupt-bytes", type=int, default=1, help="at most this many bytes flipped (default 1)")
    p.add_argument("--truncate", type=float, default=0.0, help="probability that a datagram is cut short")
    p.add_argument("--delay-ms", type=float, default=0.0, help="delay of every datagram [ms]")
    p.add_argument("--jitter-ms", type=float, default=0.0, help="extra delay drawn uniformly in [0, J] [ms]")
    p.add_argument("--duration", type=float, default=0.0, help="live: stop after this many seconds (0: on SIGINT)")
    p.add_argument("--idle-exit", type=float, default=0.0,
                   help="live: stop when no datagram arrived for this many seconds after the first")
    p.add_argument("--ready-file", help="live: written once the input socket has joined the group")
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    a = build_parser().parse_args(argv)
    try:
        schedule = schedule_from_args(a)
    except ValueError as e:
        print(f"lcm_fault_relay: error: {e}", file=sys.stderr)
        return 2
    offline = a.offline_in is not None or a.offline_out is not None
    if offline and (a.in_url or a.out_url):
        print("lcm_fault_relay: error: --offline-in/--offline-out or --in/--out, not both", file=sys.stderr)
        return 2
    replay = "lcm_fault_relay.py " + " ".join(
        ([f"--offline-in {a.offline_in} --offline-out {a.offline_out}"] if offline
         else [f"--in '{a.in_url}' --out '{a.out_url}'"]) + fault_args(schedule))
    header = {"relay": {"seed": a.seed, "faults": schedule.params(), "mode": "offline" if offline else "live",
                        "in": a.offline_in if offline else a.in_url, "out": a.offline_out if offline else a.out_url,
                        "argv": argv, "replay": replay}}
    print(f"lcm_fault_relay: seed {a.seed}; replay with: {replay}", file=sys.stderr)
    if offline:
        if not a.offline_in or not a.offline_out:
            print("lcm_fault_relay: error: offline needs both --offline-in and --offline-out", file=sys.stderr)
            return 2
        try:
            events = read_lcm_log(a.offline_in)
        except (OSError, ValueError) as e:
            print(f"lcm_fault_relay: error: --offline-in: {e}", file=sys.stderr)
            return 2
        log = open(a.log, "w") if a.log else None
        if log:
            log.write(json.dumps(header) + "\n")
        out, _, counts = apply_offline(schedule, events, log)
        if log:
            log.close()
        try:
            write_lcm_log(a.offline_out, out)
        except OSError as e:
            print(f"lcm_fault_relay: error: --offline-out: {e}", file=sys.stderr)
            return 2
        print(f"lcm_fault_relay: {len(events)} events in, {len(out)} out; {counts}", file=sys.stderr)
        return 0
    if not a.in_url or not a.out_url or not a.log:
        print("lcm_fault_relay: error: live mode needs --in, --out and --log (or --offline-in/--offline-out)",
              file=sys.stderr)
        return 2
    try:
        log = open(a.log, "w", buffering=1 << 20)
    except OSError as e:
        print(f"lcm_fault_relay: error: --log: {e}", file=sys.stderr)
        return 2
    log.write(json.dumps(header) + "\n")
    try:
        return run_live(a, schedule, log)
    except ValueError as e:
        print(f"lcm_fault_relay: error: {e}", file=sys.stderr)
        return 2
    finally:
        log.close()


if __name__ == "__main__":
    sys.exit(main())
