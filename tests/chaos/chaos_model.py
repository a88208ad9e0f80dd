"""What rockwatch-monitor must count, re-derived from the datagrams it was sent (issue 41's chaos runs).

The rules are the monitor's documented ones, transcribed:
- the receive path (docs/RELIABILITY.md "The receive path"; firmware/src/lcm_datagram.cpp, host_tools/monitor/
  datagram_input.cpp): every datagram is counted (received); an LC02 datagram is a message or rejected by reason;
  a message on a channel some wall reads is an input message (handed to the walls that read it), any other one is
  counted in other_channels (the monitor's own outputs, looped back, among them);
- the loop (firmware/include/rockwatch/firmware/monitor_loop.hpp, top comment): decode (fingerprint, exact size,
  schema_version, batch count and period), then per sample the sequence rules (first sample, seq = last + 1,
  duplicates over the last 64 seqs, out of order, publisher restart by time or by restart_window, gaps bridged up
  to max_bridge_samples or a state reset beyond), NaN/Inf and range, lift-off, lateness and untrusted time; wall
  sensors (with the observer): decode, time against the ground stream, repeated datagram.
LcmTypes decodes any rockwatch message from its .lcm file (primitive members and fixed arrays, as lcm-gen encodes).
"""

import math
import os
import re
import struct

import lcm_fault_relay as relay

INT64_MAX = (1 << 63) - 1
INT64_MIN = -(1 << 63)
SEEN_BITS = 64
MASK64 = (1 << 64) - 1


def sat(v):
    return INT64_MAX if v > INT64_MAX else INT64_MIN if v < INT64_MIN else v


LOOP_COUNTERS = ("samples_received", "samples_processed", "samples_bridged", "gaps", "state_resets", "duplicates",
                 "out_of_order", "late", "rejected_not_finite", "rejected_out_of_range", "lift_off",
                 "publisher_restarts", "decode_errors", "sensor_flags", "messages_ignored", "time_untrusted")
SENSOR_COUNTERS = ("sensor_samples_received", "sensor_time_untrusted", "sensor_duplicates")


class LoopModel:
    """One wall's MonitorLoop, counters only."""

    def __init__(self, name, settings, observer):
        self.name = name
        ch = settings["channels"]
        self.accel, self.accel_batch = ch["accel"], ch["accel_batch"]
        self.wall_sensor = ch.get("wall_sensor", "ROCKWATCH_WALL_SENSOR")
        self.observer = observer
        self.max_bridge = int(settings["max_bridge_samples"])
        self.restart_window = int(settings["restart_window"])
        self.range = float(settings["sensor_range_mps2"])
        self.late_limit_us = round(float(settings["late_limit_s"]) * 1e6)
        self.tolerance_us = round(float(settings.get("clock_tolerance_s", 10.0)) * 1e6)
        self.g = float(settings["wall"]["g"])
        self.c = {k: 0 for k in LOOP_COUNTERS + SENSOR_COUNTERS}
        self.have_last = False
        self.last_seq = 0
        self.last_utime = 0
        self.have_trusted_time = False
        self.last_trusted_utime = 0
        self.seen = 0
        self.last_ug = 0.0
        self.last_vg = 0.0
        self.have_sensor = False
        self.last_sensor = None

    def inputs(self):
        return {self.accel, self.accel_batch} | ({self.wall_sensor} if self.observer else set())

    def on_message(self, channel, data, receive_us):
        if channel == self.accel:
            m = relay.decode_ground_accel(data)
            if m is None or m[2] != 1:
                self.c["decode_errors"] += 1
                return
            utime, seq, _, ug, vg, status = m
            self.c["samples_received"] += 1
            self.sample(utime, seq, ug, vg, status, sat(receive_us - utime))
        elif channel == self.accel_batch:
            m = relay.decode_ground_batch(data)
            if m is None or m[2] != 1 or not 1 <= m[4] <= 50 or m[3] <= 0:
                self.c["decode_errors"] += 1
                return
            utime, seq, _, period, count, ug, vg, status = m
            self.c["samples_received"] += count
            newest = sat(utime + (count - 1) * period)
            for i in range(count):
                self.sample(sat(utime + i * period), sat(seq + i), ug[i], vg[i], status, sat(receive_us - newest))
        elif self.observer and channel == self.wall_sensor:
            m = relay.decode_wall_sensor(data)
            if m is None or m[2] != 1:
                self.c["decode_errors"] += 1
                return
            self.c["sensor_samples_received"] += 1
            ref = self.last_utime if self.have_last else receive_us
            d = sat(ref - m[0])
            if not -self.tolerance_us <= d <= self.tolerance_us:
                self.c["time_untrusted"] += 1
                self.c["sensor_time_untrusted"] += 1
                return
            if self.have_sensor and self.last_sensor == (m[1], m[0]):
                self.c["sensor_duplicates"] += 1
                return
            self.have_sensor = True
            self.last_sensor = (m[1], m[0])
        else:
            self.c["messages_ignored"] += 1

    def sample(self, utime, seq, ug, vg, status, delay_us):
        c = self.c
        trusted = -self.tolerance_us <= delay_us <= self.tolerance_us
        if not trusted:
            c["time_untrusted"] += 1
        reset = not self.have_last
        missing = 0
        if self.have_last:
            d = sat(seq - self.last_seq)
            if d <= 0:
                forward = trusted and self.have_trusted_time and utime > self.last_trusted_utime
                if d < -self.restart_window or forward:
                    c["publisher_restarts"] += 1
                    reset = True
                else:
                    if d > -SEEN_BITS and (self.seen >> (-d)) & 1:
                        c["duplicates"] += 1
                    else:
                        c["out_of_order"] += 1
                    return
            elif d > 1:
                c["gaps"] += 1
                if d - 1 <= self.max_bridge:
                    missing = d - 1
                else:
                    c["state_resets"] += 1
                    reset = True
        c["samples_bridged"] += missing
        c["samples_processed"] += missing
        if status != 0:
            c["sensor_flags"] += 1
        ug_finite, vg_finite = math.isfinite(ug), math.isfinite(vg)
        if not ug_finite or not vg_finite:
            c["rejected_not_finite"] += 1
        ug_in = not ug_finite or abs(ug) <= self.range
        vg_in = not vg_finite or abs(vg) <= self.range
        if not ug_in or not vg_in:
            c["rejected_out_of_range"] += 1
        if ug_finite and ug_in:
            self.last_ug = ug
        else:
            ug = self.last_ug
        if vg_finite and vg_in:
            self.last_vg = vg
        else:
            vg = self.last_vg
        if not self.g + vg > 0.0:
            c["lift_off"] += 1
        if delay_us > self.late_limit_us:
            c["late"] += 1
        shift = SEEN_BITS if reset else missing + 1
        self.seen = ((0 if shift >= SEEN_BITS else (self.seen << shift) & MASK64)) | 1
        self.have_last = True
        self.last_seq = seq
        self.last_utime = utime
        if trusted:
            self.have_trusted_time = True
            self.last_trusted_utime = utime
        c["samples_processed"] += 1


class MonitorModel:
    """The receive path and every wall. settings: `rockwatch-monitor --print-config`'s "settings"."""

    def __init__(self, settings):
        observer = bool(settings.get("observer", {}).get("enabled", False))
        walls = settings.get("walls")
        if walls:
            self.walls = []
            for w in walls:
                s = dict(settings)
                s["channels"] = dict(settings["channels"], **w.get("channels", {}))
                s["wall"] = w.get("wall", settings["wall"])
                self.walls.append(LoopModel(w["name"], s, observer))
        else:
            self.walls = [LoopModel("wall", settings, observer)]
        self.inputs = set().union(*(w.inputs() for w in self.walls))
        self.d = {"received": 0, "rejected": 0, "input_messages": 0, "other_channels": 0, "short_messages": 0}
        self.reasons = {}

    def on_datagram(self, b):
        """-> (channel, payload) when the datagram is an input message (to be fed with its receive time), else None."""
        self.d["received"] += 1
        p = relay.parse_datagram(b)
        if p[0] == "rejected":
            self.d["rejected"] += 1
            self.reasons[p[1]] = self.reasons.get(p[1], 0) + 1
            return None
        if p[0] == "fragment":
            raise ValueError("an LC03 datagram: the relay never sends one (the model does not reassemble)")
        self.d["short_messages"] += 1
        if p[1] in self.inputs:
            self.d["input_messages"] += 1
            return p[1], p[2]
        self.d["other_channels"] += 1
        return None

    def on_input(self, channel, data, receive_us):
        routed = False
        for w in self.walls:
            if channel in w.inputs():
                w.on_message(channel, data, receive_us)
                routed = True
        if not routed:
            self.walls[0].on_message(channel, data, receive_us)


# ---------------------------------------------------------------------------------------------------------------
# Decoding the monitor's outputs from its .lcm files

_SIZES = {"int8_t": (1, "b"), "int16_t": (2, "h"), "int32_t": (4, "i"), "int64_t": (8, "q"), "float": (4, "f"),
          "double": (8, "d"), "boolean": (1, "b"), "byte": (1, "B")}


class LcmTypes:
    """Structs of primitive members (and fixed-size arrays) from firmware/lcmtypes/*.lcm."""

    def __init__(self, directory):
        self.types = {}
        for f in sorted(os.listdir(directory)):
            if f.endswith(".lcm"):
                self._parse(open(os.path.join(directory, f), encoding="utf-8").read())

    def _parse(self, text):
        text = re.sub(r"//[^\n]*", "", text)
        text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        for name, body in re.findall(r"struct\s+(\w+)\s*\{(.*?)\}", text, flags=re.S):
            members = []
            for stmt in body.split(";"):
                stmt = stmt.strip()
                if not stmt or stmt.startswith("const"):
                    continue
                m = re.fullmatch(r"(\w+)\s+(\w+)\s*((?:\[\s*\w+\s*\]\s*)*)", stmt)
                if not m or m.group(1) not in _SIZES:
                    members = None
                    break
                dims = [int(x) for x in re.findall(r"\[\s*(\d+)\s*\]", m.group(3))]
                members.append((m.group(2), m.group(1), dims))
            if members is not None:
                self.types[name] = (relay.lcm_fingerprint(members), members)

    def decode(self, name, data):
        fp, members = self.types[name]
        if len(data) < 8 or struct.unpack_from(">Q", data, 0)[0] != fp:
            return None
        out, pos = {}, 8
        for mname, typ, dims in members:
            size, code = _SIZES[typ]
            n = 1
            for d in dims:
                n *= d
            vals = struct.unpack_from(f">{n}{code}", data, pos)
            pos += size * n
            out[mname] = list(vals) if dims else vals[0]
        return out if pos == len(data) else None
