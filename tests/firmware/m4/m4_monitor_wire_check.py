#!/usr/bin/env python3
"""ctest m4_monitor_wire, the comparison and the traffic: listens on the LCM group while the replay runs, keeps the
wall_state_t payloads per publisher (the image's come from its bridge, the host's from rockwatch-monitor), sends the
hostile datagrams, and compares the two monitors' results.

  m4_monitor_wire_check.py listen URL OUT.json SECONDS [DONE_FILE]
                                                            collect WALL_STATE payloads by source for SECONDS; with
                                                            DONE_FILE, stop earlier: once that file exists (the stream
                                                            has been sent), both publishers were heard, and neither
                                                            has published for QUIET_S (a monitor publishes a state per
                                                            processed sample and nothing else, so a quiet group means
                                                            both have finished; compare checks every state was heard)
  m4_monitor_wire_check.py hostile URL CORPUS_FILE...       send the datagrams of fuzz corpus files to the group
  m4_monitor_wire_check.py compare IMAGE.json HOST.jsonl STATES.json NAME
  m4_monitor_wire_check.py budget IMAGE.json NAME MAX_INSN   issue 43's budget: every ground message's call, the
                                                            network receive included, <= MAX_INSN instructions; the
                                                            image's own part of every call (ground or sensor) within
                                                            the overhead it declares to the engine
"""
import json, os, socket, struct, sys, time
from urllib.parse import urlparse


def group_of(url):
    u = urlparse(url)
    return u.hostname, u.port


QUIET_S = 2.0


def listen(url, out, seconds, done_file=None):
    group, port = group_of(url)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
    s.bind(("", port))
    s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, socket.inet_aton(group) + socket.inet_aton("0.0.0.0"))
    s.settimeout(0.2)
    states = {}
    end = time.monotonic() + seconds
    last = time.monotonic()
    while time.monotonic() < end:
        if done_file and len(states) == 2 and time.monotonic() - last >= QUIET_S and os.path.exists(done_file):
            break
        try:
            data, src = s.recvfrom(65536)
        except socket.timeout:
            continue
        if data[:4] != b"LC02":
            continue
        nul = data.find(b"\0", 8)
        if nul < 0 or data[8:nul] != b"ROCKWATCH_WALL_STATE":
            continue
        states.setdefault("%s:%d" % src, []).append(data[nul + 1:].hex())
        last = time.monotonic()
    json.dump(states, open(out, "w"))


def hostile(url, files):
    group, port = group_of(url)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    n = 0
    for path in files:
        data = open(path, "rb").read()[1:]  # the settings byte (fuzz_monitor_datagrams.cpp)
        while len(data) >= 3:
            length = struct.unpack("<H", data[1:3])[0]
            payload, data = data[3:3 + length], data[3 + length:]
            s.sendto(payload, (group, port))
            n += 1
            time.sleep(0.01)
    print("hostile datagrams sent: %d" % n)


KEYS = ["samples_received", "samples_processed", "samples_bridged", "gaps", "duplicates", "out_of_order", "late",
        "time_untrusted", "decode_errors", "alarm_events", "states_published", "state_resets", "publisher_restarts",
        "sensor_samples_received", "sensor_duplicates", "estimates_published"]


def compare(image_path, host_path, states_path, name):
    image = json.load(open(image_path))
    host_lines = [json.loads(l) for l in open(host_path) if l.startswith("{")]
    summary = next(l["summary"] for l in host_lines if "summary" in l)
    host_transitions = [{"input_seq": l["input_seq"], "level": l["level"]} for l in host_lines if "input_seq" in l]
    failed = []
    if image["transitions"] != host_transitions:
        failed.append("transitions: image %s, host %s" % (image["transitions"], host_transitions))
    c, h = image["counters"], summary["counters"]
    for k in KEYS:
        if k in h and c.get(k) != h[k]:
            failed.append("%s: image %s, host %s" % (k, c.get(k), h[k]))
    d = summary["datagrams"]
    if c["lcm_rejected"] != d["rejected"]:
        failed.append("rejected datagrams: image %d, host %d" % (c["lcm_rejected"], d["rejected"]))
    if c["input_messages"] != d["input_messages"]:
        failed.append("input messages: image %d, host %d" % (c["input_messages"], d["input_messages"]))
    # Frames below UDP (m4-monitor.sh --m4-hostile-frames): each reject class counted exactly as often as it was sent.
    for counter, n in image.get("bridge", {}).get("hostile_frames", {}).items():
        if c.get(counter) != n:
            failed.append("hostile frames: %s %s, %d sent" % (counter, c.get(counter), n))
    states = json.load(open(states_path))
    if len(states) != 2:
        failed.append("wall_state_t publishers seen: %d (expected the image's bridge and the host)" % len(states))
    else:
        a, b = states.values()
        # Every state each monitor published was heard (the listener may stop when the group falls quiet).
        for who, n in (("image", c.get("states_published")), ("host", h.get("states_published"))):
            if n is None or n != len(a) or n != len(b):
                failed.append("wall_state_t: %s published %d, heard %d and %d" % (who, n, len(a), len(b)))
        if a != b:
            diff = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            failed.append("wall_state_t: %d and %d messages, first difference at message %d" % (len(a), len(b), diff))
    ins = image["insn_per_sample"]
    print("%-10s transitions %s samples %d rejected %d states %s; insn/sample median %d p99 %d max %d (receive %d)" % (
        name, [(t["input_seq"], t["level"]) for t in host_transitions], c["samples_received"], c["lcm_rejected"],
        "equal bit for bit (%d)" % len(next(iter(states.values()))) if len(states) == 2 and not any("wall_state" in f for f in failed) else "?",
        ins["median"], ins["p99"], ins["max"], image["receive_insn_per_sample"]["max"]))
    for f in failed:
        print("  DIFFERENT " + f)
    return 1 if failed else 0


def budget(image_path, name, max_insn):
    image = json.load(open(image_path))
    failed = []
    worst = image["insn_per_sample"]["max"]
    if worst > max_insn:
        failed.append("a call of %d instructions, over the %d budget" % (worst, max_insn))
    declared = image.get("declared_call_overhead_insn")
    over = image.get("image_overhead_over_declared_insn")
    if declared is None or over is None or over > 0:
        failed.append("the image's own part of a call %s instructions over what it declares (%s)" % (over, declared))
    own = max(image["image_overhead_insn_per_sample"]["max"], image["image_overhead_insn_per_sensor_datagram"]["max"])
    if image["samples_processed"] == 0:
        failed.append("no sample processed")
    c = image["counters"]
    print("%-10s budget: max %d <= %d instructions a call (p99 %d, median %d; engine max %d); the image's own part "
          "max %d (declared %s, the most beyond it %s); late %d, shed %d" % (
              name, worst, max_insn, image["insn_per_sample"]["p99"], image["insn_per_sample"]["median"],
              image["engine_insn_per_sample"]["max"], own, declared, over, c.get("samples_late", -1),
              c.get("samples_work_shed", -1)))
    for f in failed:
        print("  OVER BUDGET " + f)
    return 1 if failed else 0


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "listen":
        listen(sys.argv[2], sys.argv[3], float(sys.argv[4]), sys.argv[5] if len(sys.argv) > 5 else None)
    elif cmd == "hostile":
        hostile(sys.argv[2], sys.argv[3:])
    elif cmd == "compare":
        sys.exit(compare(*sys.argv[2:6]))
    elif cmd == "budget":
        sys.exit(budget(sys.argv[2], sys.argv[3], int(sys.argv[4])))
    else:
        sys.exit(2)
