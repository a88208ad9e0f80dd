#!/usr/bin/env python3
"""The host side of scripts/m4-monitor.sh: writes the image's configuration from `rockwatch-monitor --print-config`,
boots the monitor image in QEMU (mps2-an386, -icount) with its LAN9118 on a QEMU socket network (`-nic socket,udp=`:
each Ethernet frame one UDP datagram between QEMU and this process on 127.0.0.1), bridges that network to the LCM
URL's UDP multicast group (LCM datagrams from the group -> Ethernet/IPv4/UDP frames to the image; the image's frames
-> their UDP payload to the group), prints `lcm-url: URL` once the image listens, and on SIGINT/SIGTERM stops QEMU and
prints one JSON object (see scripts/m4-monitor.sh).

  m4-monitor-run.py --image ELF --qemu QEMU --print-config FILE.json --lcm-url URL --work DIR [--timeout S]
"""
import argparse, collections, json, math, os, select, signal, socket, struct, subprocess, sys, time
from urllib.parse import urlparse, parse_qs

LEVELS = ["QUIET", "ROCKING", "WARNING", "IMMINENT", "COLLAPSED"]
SHIFT = 10               # -icount shift: 1024 ns of virtual time per instruction
NS_PER_TICK = 40.0       # the board's 25 MHz TIMER0
IMAGE_IP = "192.168.76.2"
BRIDGE_MAC = bytes([0x02, 0x52, 0x57, 0x00, 0x00, 0x01])
IMAGE_MAC = bytes([0x02, 0x52, 0x57, 0x00, 0x00, 0x02])


def fail(message, status=1):
    sys.stderr.write("m4-monitor: " + message + "\n")
    sys.exit(status)


# --- configuration file (firmware/embedded/m4_monitor/monitor_main.cpp, "CONFIG") ---
ENGINE_KEYS = {  # EngineInputKey (rockwatch/firmware/engine_input_format.hpp)
    ("wall", "b"): 1, ("wall", "h1"): 2, ("wall", "h2"): 3, ("wall", "rho"): 4, ("wall", "fp"): 5,
    ("wall", "a"): 6, ("wall", "a_prime"): 7, ("wall", "g"): 8, ("r_energy_ratio",): 9, ("kappa",): 10,
    ("alarm", "lambda_w"): 13, ("alarm", "hold_s"): 14, ("alarm", "energy_margin"): 15, ("max_step_s",): 16,
    ("observer", "x_noise_m"): 18, ("observer", "a_noise_mps2"): 19, ("observer", "process_accel_mps2"): 20,
    ("observer", "gate_chi2"): 25, ("observer", "dropout_s"): 27, ("observer", "max_age_s"): 28,
    ("observer", "capacity_sigmas"): 35, ("observer", "accel_inform_peak_noises"): 36,
    ("alarm", "imminent_horizon_s"): 37, ("observer", "doubt_nis"): 44, ("observer", "capacity_min_x"): 48,
    ("observer", "doubt_capacity_min_x"): 49, ("observer", "model_form_sigma"): 50,
    ("observer", "doubt_model_form_sigma"): 51, ("observer", "quiet_motion_spread_noises"): 52,
    ("alarm", "energy_min_x"): 53, ("observer", "capacity_correlation"): 54,
    ("observer", "noise_learn_readings"): 55,
}
# The settings groups whose every key must reach the image (a key the table above does not map fails the run instead
# of the image running its default while the host runs what it was told).
MAPPED_GROUPS = ("wall", "alarm", "observer")
CHANNELS = ["accel", "accel_batch", "wall_state", "alarm", "status", "wall_sensor", "wall_estimate"]
CHANNEL_DEFAULTS = ["ROCKWATCH_ACCEL", "ROCKWATCH_ACCEL_BATCH", "ROCKWATCH_WALL_STATE", "ROCKWATCH_ALARM",
                    "ROCKWATCH_STATUS", "ROCKWATCH_WALL_SENSOR", "ROCKWATCH_WALL_ESTIMATE"]


def ipv4_number(text):
    return struct.unpack("!I", socket.inet_aton(text))[0]


def write_config(printed, group, port, path):
    s = printed["settings"]
    for key in ("walls", "forecast", "accept_from"):
        if key in s:
            fail("the monitor image runs one wall without --forecast or accept_from (the settings have '%s')" % key, 2)
    if s.get("arith") != "fixed":
        fail("the Cortex-M4 image runs the fixed-point engine: --arith must be fixed", 2)
    if s.get("model") != "linear":
        fail("the fixed-point engine runs the linear model only (--model linear)", 2)
    for settings_group in MAPPED_GROUPS:
        for name in s.get(settings_group, {}):
            if (settings_group, name) not in ENGINE_KEYS and (settings_group, name) != ("observer", "enabled"):
                fail("the monitor image cannot be given the setting %s.%s (scripts/m4-monitor-run.py ENGINE_KEYS, "
                     "EngineInputKey in firmware/include/rockwatch/firmware/engine_input_format.hpp)"
                     % (settings_group, name), 2)
    pairs = []
    for path_keys, key in ENGINE_KEYS.items():
        v = s
        for k in path_keys:
            v = v.get(k) if isinstance(v, dict) else None
        if v is not None:
            pairs.append((key, struct.pack("<d", float(v))))
    pairs.append((11, struct.pack("<d", 0.0)))  # model: linear
    observer = bool(s.get("observer", {}).get("enabled", False))
    pairs.append((17, struct.pack("<d", 1.0 if observer else 0.0)))
    if "work_overflow" in s:
        pairs.append((34, struct.pack("<d", 1.0 if s["work_overflow"] == "finish" else 0.0)))
    tolerance_us = round(s.get("clock_tolerance_s", 10.0) * 1e6)
    digest = int(printed["config_digest"], 16)
    monitor = [(1001, float(s["sample_rate_hz"])), (1002, float(s["max_bridge_samples"])),
               (1003, float(s["sensor_range_mps2"])), (1004, float(s["late_limit_s"])),
               (1005, float(s["restart_window"])), (1006, float(tolerance_us)),
               (1008, float(s.get("work_budget_units", 0))), (1009, float(ipv4_number(group))),
               (1010, float(port)), (1011, float(ipv4_number(IMAGE_IP)))]
    pairs += [(k, struct.pack("<d", v)) for k, v in monitor]
    pairs.append((1007, struct.pack("<Q", digest)))
    with open(path, "wb") as f:
        f.write(b"RWMONCF1" + struct.pack("<Q", len(pairs)))
        for k, v in pairs:
            f.write(struct.pack("<Q", k) + v)
        channels = s.get("channels", {})
        for name, default in zip(CHANNELS, CHANNEL_DEFAULTS):
            text = channels.get(name, default).encode()
            f.write(text + b"\0" * (64 - len(text)))
    return observer


# --- frames ---
def checksum(data):
    if len(data) % 2:
        data += b"\0"
    s = sum(struct.unpack("!%dH" % (len(data) // 2), data))
    while s >> 16:
        s = (s & 0xFFFF) + (s >> 16)
    return (~s) & 0xFFFF


def frame_for(payload, src_ip, src_port, group, port, ip_id):
    g = socket.inet_aton(group)
    dst_mac = bytes([0x01, 0x00, 0x5E, g[1] & 0x7F, g[2], g[3]])
    udp_len = 8 + len(payload)
    src = socket.inet_aton(src_ip)
    pseudo = src + g + struct.pack("!BBH", 0, 17, udp_len)
    udp = struct.pack("!HHHH", src_port, port, udp_len, 0) + payload
    c = checksum(pseudo + udp) or 0xFFFF
    udp = udp[:6] + struct.pack("!H", c) + udp[8:]
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + udp_len, ip_id & 0xFFFF, 0x4000, 1, 17, 0, src, g)
    ip = ip[:10] + struct.pack("!H", checksum(ip)) + ip[12:]
    return dst_mac + BRIDGE_MAC + b"\x08\x00" + ip + udp


def hostile_frames(group, port):
    """Frames the image's receive path must reject below UDP, each with the counter that must count it once
    (firmware/embedded/m4_monitor/udp_ipv4.hpp NetCounters). All go to the group's multicast MAC, which the NIC passes."""
    payload = b"LC02\0\0\0\1HOSTILE\0" + bytes(8)
    src_ip, src_port = "127.0.0.1", 40000

    def build(ethertype=0x0800, ver_ihl=0x45, flags=0x4000, proto=17, dst=group, dport=port, udp_len=None,
              ip_total=None, bad_ip_sum=False, bad_udp_sum=False, options=b""):
        g = socket.inet_aton(group)
        dst_mac = bytes([0x01, 0x00, 0x5E, g[1] & 0x7F, g[2], g[3]])
        d = socket.inet_aton(dst)
        length = 8 + len(payload) if udp_len is None else udp_len
        udp = struct.pack("!HHHH", src_port, dport, length, 0) + payload
        c = checksum(socket.inet_aton(src_ip) + d + struct.pack("!BBH", 0, 17, length) + udp) or 0xFFFF
        if bad_udp_sum:
            c ^= 0x5A5A
        udp = udp[:6] + struct.pack("!H", c) + udp[8:]
        total = 20 + len(options) + len(udp) if ip_total is None else ip_total
        ip = struct.pack("!BBHHHBBH4s4s", ver_ihl, 0, total, 7, flags, 1, proto, 0, socket.inet_aton(src_ip), d)
        ip += options
        s_ = checksum(ip) ^ (0x1111 if bad_ip_sum else 0)
        ip = ip[:10] + struct.pack("!H", s_) + ip[12:]
        return dst_mac + BRIDGE_MAC + struct.pack("!H", ethertype) + ip + udp

    return [
        ("not_ipv4", build(ethertype=0x86DD)),
        ("not_ipv4", build(ethertype=0x0806)),
        ("ip_malformed", build(bad_ip_sum=True)),
        ("ip_malformed", build(ver_ihl=0x46, options=bytes(4))),
        ("ip_malformed", build(ip_total=1400)),
        ("ip_fragments", build(flags=0x2000)),
        ("ip_fragments", build(flags=0x0010)),
        ("not_udp", build(proto=6)),
        ("not_for_us", build(dport=port + 1)),
        ("not_for_us", build(dst="239.255.76.250")),
        ("udp_malformed", build(bad_udp_sum=True)),
        ("udp_malformed", build(udp_len=4)),
    ]


def lcm_channel(datagram):
    """The channel of a small LCM datagram (LC02), or None."""
    if len(datagram) < 9 or datagram[:4] != b"LC02":
        return None
    end = datagram.find(b"\0", 8)
    return datagram[8:end].decode("latin-1") if end > 8 else None


# Flow control: at most this many ground samples in the image's hands (sent, its wall_state_t not yet back). Under
# -icount the emulated board runs at the host's pace; on a loaded host it falls behind a stream sent in real time, and
# its NIC's receive FIFO (16 KiB) overflows. A real sensor network would not wait for the monitor; the bridge does,
# so that a loaded host cannot make the image lose what the host's monitor receives (tests compare the two).
WINDOW = 16
IDLE_RELEASE_S = 0.2  # nothing back for this long while samples are in hand: the image is idle, they were consumed


class ImageWindow:
    """The frames waiting for the window, in arrival order, and the ground samples in the image's hands."""

    def __init__(self, send):
        self.send = send  # send(frame): one frame to the image
        self.queue = collections.deque()  # (is_ground, frame)
        self.in_hand = 0
        self.last_back = time.monotonic()

    def release(self):
        """Sends what the window allows (non-ground frames go in their turn and do not count); the count sent."""
        if self.in_hand > 0 and time.monotonic() - self.last_back > IDLE_RELEASE_S:
            self.in_hand = 0
        sent = 0
        while self.queue and (not self.queue[0][0] or self.in_hand < WINDOW):
            is_ground, frame = self.queue.popleft()
            self.send(frame)
            sent += 1
            if is_ground:
                if self.in_hand == 0:
                    self.last_back = time.monotonic()
                self.in_hand += 1
        return sent

    def answered(self):
        """A wall_state_t came back from the image: one ground sample less in its hands."""
        self.in_hand = max(0, self.in_hand - 1)
        self.last_back = time.monotonic()


def payload_of(frame, group, port):
    """The UDP payload of a frame the image sent to the group's port, or None."""
    if len(frame) < 42 or frame[12:14] != b"\x08\x00" or frame[14] != 0x45 or frame[23] != 17:
        return None
    total = struct.unpack("!H", frame[16:18])[0]
    if frame[30:34] != socket.inet_aton(group) or struct.unpack("!H", frame[36:38])[0] != port:
        return None
    udp_len = struct.unpack("!H", frame[38:40])[0]
    if udp_len < 8 or 14 + 20 + udp_len > len(frame) or 20 + udp_len > total:
        return None
    return frame[42:34 + udp_len]


# --- statistics ---
def stats(values):
    if not values:
        return {"median": 0, "p99": 0, "max": 0}
    s = sorted(values)
    n = len(s)
    return {"median": s[(n + 1) // 2 - 1], "p99": s[max(0, math.ceil(0.99 * n) - 1)], "max": s[-1]}


def insns(ticks, overhead=0):
    return round(ticks * NS_PER_TICK / (1 << SHIFT)) - overhead


def summarise(output_path, qemu_version, observer, bridge):
    lines = open(output_path).read().splitlines() if os.path.exists(output_path) else []
    if not lines or lines[0] != "rockwatch-m4-monitor 1":
        fail("the image wrote no output")
    overhead = 0
    counters = {}
    transitions = []
    per = {"g": [], "s": [], "o": [], "r": [], "f": [], "n": []}
    receive = []
    engine, image_part, declared = [], {"g": [], "s": []}, None
    by_states, excess = collections.defaultdict(list), []
    catch_up, caught_up = [], 0
    for line in lines[1:]:
        f = line.split()
        if not f:
            continue
        if f[0] == "overhead":
            overhead = insns(int(f[1]))
        elif f[0] == "call_overhead" and len(f) == 3:
            declared = {"per_call": int(f[1]), "per_sample": int(f[2])}
        elif f[0] == "d" and len(f) == 7 and f[1] in per:
            total, rx = insns(int(f[2]), overhead), insns(int(f[3]), overhead)
            per[f[1]].append(total)
            if f[1] == "g":
                receive.append(rx)
                engine.append(insns(int(f[5])))
            if f[1] in image_part:
                own, states = total - insns(int(f[5])), int(f[6])
                image_part[f[1]].append(own)
                by_states[states].append(own)
                if declared is not None:
                    excess.append(own - declared["per_call"] - states * declared["per_sample"])
        elif f[0] == "k" and len(f) == 3:
            catch_up.append(insns(int(f[1]), overhead))
            caught_up += int(f[2])
        elif f[0] == "a" and len(f) == 3:
            transitions.append({"input_seq": int(f[1]), "level": LEVELS[int(f[2])]})
        elif f[0] == "c":
            counters = {f[i]: int(f[i + 1]) for i in range(1, len(f) - 1, 2)}
    c = counters
    result = {
        "machine": "mps2-an386 (Cortex-M4F, qemu-system-arm %s, -icount shift=%d), LAN9118 on a QEMU socket network"
                   % (qemu_version, SHIFT),
        "observer": observer,
        "frames_received": c.get("frames", 0),
        "datagrams_received": c.get("datagrams", 0),
        "samples_received": c.get("samples_received", 0),
        "samples_processed": c.get("samples_processed", 0),
        "gaps": c.get("gaps", 0),
        "duplicates": c.get("duplicates", 0),
        "out_of_order": c.get("out_of_order", 0),
        "transitions": transitions,
        "insn_per_sample": stats(per["g"]),
        "receive_insn_per_sample": stats(receive),
        "insn_per_sensor_datagram": stats(per["s"]),
        "insn_per_other_datagram": stats(per["o"] + per["r"] + per["f"] + per["n"]),
        "engine_insn_per_sample": stats(engine),
        "image_overhead_insn_per_sample": stats(image_part["g"]),
        "image_overhead_insn_per_sensor_datagram": stats(image_part["s"]),
        "image_overhead_insn_by_samples_published": {str(k): stats(v) | {"calls": len(v)} for k, v in sorted(by_states.items())},
        "catch_up_insn": stats(catch_up) | {"runs": len(catch_up), "samples": caught_up},
        "declared_call_overhead_insn": declared,
        "image_overhead_over_declared_insn": max(excess) if excess else None,
        "overhead_insn": overhead,
        "counters": counters,
        "bridge": bridge,
    }
    return result


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--image", required=True)
    ap.add_argument("--qemu", required=True)
    ap.add_argument("--print-config", required=True)
    ap.add_argument("--lcm-url", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--timeout", type=float, default=0)
    ap.add_argument("--hostile-frames", action="store_true",
                    help="once the image listens, send it malformed frames below UDP (tests)")
    a = ap.parse_args()

    url = urlparse(a.lcm_url)
    if url.scheme != "udpm" or not url.hostname or not url.port:
        fail("--lcm-url must be udpm://GROUP:PORT[?ttl=0] (got %r)" % a.lcm_url, 2)
    group, port = url.hostname, url.port
    try:
        if (ipv4_number(group) >> 28) != 0xE:
            raise OSError
    except OSError:
        fail("--lcm-url: %s is not an IPv4 multicast group (224.0.0.0/4)" % group, 2)
    printed = json.load(open(a.print_config))
    config = os.path.join(a.work, "monitor.cfg")
    observer = write_config(printed, group, port, config)

    # The QEMU side of the socket network: QEMU sends its frames to our port, and receives on its own.
    frames = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    frames.bind(("127.0.0.1", 0))
    bridge_port = frames.getsockname()[1]
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    probe.bind(("127.0.0.1", 0))
    qemu_port = probe.getsockname()[1]
    probe.close()
    # The LCM side: the group (as liblcm joins it), and a sender whose own datagrams are not bridged back.
    lcm_in = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    lcm_in.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    if hasattr(socket, "SO_REUSEPORT"):
        lcm_in.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    lcm_in.bind(("", port))
    lcm_in.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, socket.inet_aton(group) + socket.inet_aton("0.0.0.0"))
    lcm_in.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
    lcm_out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    ttl = int(parse_qs(url.query).get("ttl", ["0"])[0])
    lcm_out.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, ttl)
    lcm_out.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    lcm_out.bind(("", 0))
    own_port = lcm_out.getsockname()[1]

    output = os.path.join(a.work, "output.txt")
    qemu_version = subprocess.run([a.qemu, "--version"], capture_output=True, text=True).stdout.split("version ")[-1].split()[0]
    cmd = [a.qemu, "-M", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-icount", "shift=%d" % SHIFT,
           "-nic", "socket,model=lan9118,udp=127.0.0.1:%d,localaddr=127.0.0.1:%d" % (bridge_port, qemu_port),
           "-kernel", os.path.abspath(a.image), "-append", "output.txt monitor.cfg"]
    log = open(os.path.join(a.work, "qemu.log"), "w")
    qemu = subprocess.Popen(cmd, cwd=a.work, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)

    stop = {"flag": False}
    def on_signal(signum, frame):
        stop["flag"] = True
    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)

    bridge = {"to_image": 0, "from_image": 0, "from_image_not_lcm": 0, "held_max": 0}
    channels = printed["settings"]["channels"]
    ground_channels = {channels["accel"], channels["accel_batch"]}
    state_channel = channels["wall_state"]
    # What other monitors on the group publish on the image's own output channels (a host rockwatch-monitor beside it
    # in a test, a dashboard's peers) is not forwarded: the image never reads those channels, and on a loaded host,
    # where the emulated board falls behind, they would fill its NIC's receive FIFO (not paced by the window below).
    output_channels = {channels[k] for k in ("wall_state", "alarm", "status", "wall_estimate") if k in channels}
    window = ImageWindow(lambda frame: frames.sendto(frame, ("127.0.0.1", qemu_port)))

    def from_image(data):
        """A frame the image sent: its LCM payload to the group; a wall_state_t answers a ground sample."""
        payload = payload_of(data, group, port)
        if payload is None:
            bridge["from_image_not_lcm"] += 1
            return
        lcm_out.sendto(payload, (group, port))
        bridge["from_image"] += 1
        if lcm_channel(payload) == state_channel:
            window.answered()

    started = time.monotonic()
    ready = False
    ip_id = 0
    status = 0
    while not stop["flag"]:
        if qemu.poll() is not None:
            log.close()
            sys.stderr.write(open(os.path.join(a.work, "qemu.log")).read())
            reasons = {3: "the image did not get its command line", 4: "the image could not read its configuration",
                       5: "the configuration is invalid for the image", 6: "MonitorLoop::init refused the settings",
                       7: "no LAN9118 answered", 8: "the image could not write its output", 9: "the image faulted"}
            fail("QEMU exited with status %d: %s" % (qemu.returncode, reasons.get(qemu.returncode, "?")))
        if not ready and os.path.exists(output) and "\nready " in open(output).read():
            ready = True
            if a.hostile_frames:
                sent = {}
                for counter, frame in hostile_frames(group, port):
                    frames.sendto(frame, ("127.0.0.1", qemu_port))
                    sent[counter] = sent.get(counter, 0) + 1
                bridge["hostile_frames"] = sent
            print("lcm-url: %s" % a.lcm_url, flush=True)
        if not ready and time.monotonic() - started > 60:
            qemu.kill()
            fail("the image did not start listening within 60 s")
        if a.timeout and time.monotonic() - started > a.timeout:
            break
        bridge["to_image"] += window.release()
        try:
            readable, _, _ = select.select([frames, lcm_in], [], [], 0.005 if window.queue else 0.1)
        except InterruptedError:
            continue
        for s in readable:
            if s is frames:
                from_image(frames.recvfrom(65536)[0])
            else:
                data, (src_ip, src_port) = lcm_in.recvfrom(65536)
                if src_port == own_port:
                    continue  # the image's own publications, looped back by the host
                channel = lcm_channel(data)
                if channel in output_channels:
                    bridge["outputs_not_forwarded"] = bridge.get("outputs_not_forwarded", 0) + 1
                    continue
                if ready and len(data) <= 1472:
                    ip_id += 1
                    window.queue.append((channel in ground_channels,
                                         frame_for(data, src_ip, src_port, group, port, ip_id)))
                    bridge["held_max"] = max(bridge["held_max"], len(window.queue))
    # What the window still holds goes to the image (paced as above), then it finishes what it received (its output
    # is flushed whenever it is idle).
    drain_until = time.monotonic() + 30
    while window.queue and time.monotonic() < drain_until and qemu.poll() is None:
        bridge["to_image"] += window.release()
        for r in select.select([frames], [], [], 0.005)[0]:
            from_image(r.recvfrom(65536)[0])
    time.sleep(0.3)
    os.killpg(qemu.pid, signal.SIGTERM)
    try:
        qemu.wait(10)
    except subprocess.TimeoutExpired:
        os.killpg(qemu.pid, signal.SIGKILL)
        qemu.wait()
    print(json.dumps(summarise(output, qemu_version, observer, bridge), indent=2), flush=True)
    return status


if __name__ == "__main__":
    sys.exit(main())
