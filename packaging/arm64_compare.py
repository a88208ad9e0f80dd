#!/usr/bin/python3
"""Compares two programs' JSON outputs: the x86-64 build's (REFERENCE) and the aarch64 build's (CANDIDATE), as
ctest arm64_cross_check runs them (issue 45; docs/packaging.md "64-bit ARM").

    arm64_compare.py [--rel R] [--label NAME] REFERENCE CANDIDATE
    arm64_compare.py --lcm-logs [--rel R] [--label NAME] REFERENCE.lcmlog CANDIDATE.lcmlog

Each file is one JSON document (rockwatch simulate --json) or JSON lines (rockwatch-monitor's stdout: one alarm
transition a line, then the summary). Strings (verdicts, alarm levels, reasons), booleans, nulls, integers (counts,
sequence numbers, utime) and the structure must be identical; every other number within R relative (1e-12):
|a - b| <= R * max(|a|, |b|). Prints the largest relative difference, where it is, and max_abs_x_m of each side
when there is one. With --lcm-logs the two are rockwatch-monitor --offline-out logs: the same channels in the same
order, every wall_state_t's alarm level identical and its x_m within R (max |x| of each side printed), and whether
the two logs are the same bytes. Exit 0 when equal within R, 1 when not (each difference listed), 2 on bad input.
"""
import json
import struct
import sys


def die(message):
    print(message, file=sys.stderr)
    sys.exit(2)


def load(path):
    try:
        text = open(path, encoding="utf-8").read()
    except OSError as e:
        die(f"arm64_compare: cannot read {path}: {e.strerror} (expected a JSON or JSON-lines file)")
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        pass
    docs = []
    for n, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            docs.append(json.loads(line))
        except json.JSONDecodeError as e:
            die(f"arm64_compare: {path} line {n} is not JSON ({e.msg}): expected one JSON document or JSON lines")
    if not docs:
        die(f"arm64_compare: {path} is empty: expected one JSON document or JSON lines")
    return docs


def lcm_log(path):
    """The events of an LCM log: (channel, data) pairs (the log format: sync word, event number, time, lengths)."""
    try:
        raw = open(path, "rb").read()
    except OSError as e:
        die(f"arm64_compare: cannot read {path}: {e.strerror} (expected an LCM log)")
    events, pos = [], 0
    while pos < len(raw):
        if len(raw) - pos < 28 or struct.unpack_from(">I", raw, pos)[0] != 0xEDA1DA01:
            die(f"arm64_compare: {path}: no LCM event at byte {pos} (expected an LCM log)")
        clen, dlen = struct.unpack_from(">ii", raw, pos + 20)
        channel = raw[pos + 28:pos + 28 + clen].decode("utf-8", "replace")
        events.append((channel, raw[pos + 28 + clen:pos + 28 + clen + dlen]))
        pos += 28 + clen + dlen
    return raw, events


def compare_logs(ref_path, cand_path, rel, label):
    raw_a, a = lcm_log(ref_path)
    raw_b, b = lcm_log(cand_path)
    name = label or cand_path
    if [c for c, _ in a] != [c for c, _ in b]:
        print(f"arm64_compare: {name}: the logs' channel sequences differ ({len(a)} against {len(b)} events)")
        return 1
    # wall_state_t: fingerprint (8), utime, seq, input_seq (8 each), schema_version (4), then x_m (big-endian double);
    # alarm_level is at 8 + 28 + 8 * 3 + 2 + 8 = 70.
    worst, max_a, max_b, states, bad = 0.0, 0.0, 0.0, 0, []
    for n, ((ch, da), (_, db)) in enumerate(zip(a, b)):
        if not ch.startswith("ROCKWATCH_WALL_STATE"):
            continue
        states += 1
        xa, xb = struct.unpack_from(">d", da, 36)[0], struct.unpack_from(">d", db, 36)[0]
        max_a, max_b = max(max_a, abs(xa)), max(max_b, abs(xb))
        scale = max(abs(xa), abs(xb))
        d = abs(xa - xb) / scale if scale > 0 else 0.0
        worst = max(worst, d)
        if d > rel or da[70] != db[70]:
            bad.append(f"event {n} ({ch}): x_m {xa!r} against {xb!r}, alarm level {da[70]} against {db[70]}")
    same = raw_a == raw_b
    d_max = abs(max_a - max_b) / max(max_a, max_b) if max(max_a, max_b) > 0 else 0.0
    print(f"arm64_compare: {name}: {len(a)} events, {states} wall states; max |x| x86-64 {max_a!r}, aarch64 {max_b!r} "
          f"(relative {d_max:.3g}); largest relative x difference {worst:.3g}; "
          + ("the logs are the same bytes" if same else "the logs' bytes differ"))
    if bad or d_max > rel:
        for line in bad[:20]:
            print("  " + line)
        return 1
    return 0


def main(argv):
    if argv and argv[0] == "--lcm-logs":
        rest, rel, label = argv[1:], 1e-12, ""
        while len(rest) > 2 and rest[0] in ("--rel", "--label"):
            if rest[0] == "--rel":
                try:
                    rel = float(rest[1])
                except ValueError:
                    die(f"arm64_compare: --rel expects a number, got '{rest[1]}'")
            else:
                label = rest[1]
            rest = rest[2:]
        if len(rest) != 2:
            die("usage: arm64_compare.py --lcm-logs [--rel R] [--label NAME] REFERENCE.lcmlog CANDIDATE.lcmlog")
        return compare_logs(rest[0], rest[1], rel, label)
    rel, label, files = 1e-12, "", []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--rel", "--label"):
            if i + 1 >= len(argv):
                die(f"arm64_compare: {a} needs a value")
            if a == "--rel":
                try:
                    rel = float(argv[i + 1])
                except ValueError:
                    die(f"arm64_compare: --rel expects a number, got '{argv[i + 1]}'")
            else:
                label = argv[i + 1]
            i += 2
            continue
        files.append(a)
        i += 1
    if len(files) != 2:
        die("usage: arm64_compare.py [--rel R] [--label NAME] REFERENCE CANDIDATE")
    ref, cand = load(files[0]), load(files[1])
    diffs, worst = [], [0.0, ""]
    maxx = {}

    def walk(a, b, where):
        if isinstance(a, dict) and isinstance(b, dict):
            if sorted(a) != sorted(b):
                diffs.append(f"{where}: keys differ: {sorted(set(a) ^ set(b))}")
                return
            for k in a:
                if k == "max_abs_x_m":
                    maxx.setdefault(where + "/" + k, (a[k], b[k]))
                walk(a[k], b[k], f"{where}/{k}")
        elif isinstance(a, list) and isinstance(b, list):
            if len(a) != len(b):
                diffs.append(f"{where}: {len(a)} items against {len(b)}")
                return
            for n, (x, y) in enumerate(zip(a, b)):
                walk(x, y, f"{where}[{n}]")
        elif isinstance(a, float) or isinstance(b, float):
            if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) \
                    or not isinstance(b, (int, float)):
                diffs.append(f"{where}: {a!r} against {b!r}")
                return
            scale = max(abs(a), abs(b))
            d = abs(a - b) / scale if scale > 0 else 0.0
            if d > worst[0]:
                worst[:] = [d, where]
            if d > rel:
                diffs.append(f"{where}: {a!r} against {b!r} (relative {d:.3g} > {rel:g})")
        elif type(a) is not type(b) or a != b:
            diffs.append(f"{where}: {a!r} against {b!r}")

    walk(ref, cand, "")
    name = label or files[1]
    for where, (a, b) in maxx.items():
        print(f"arm64_compare: {name}: {where or '/'}: x86-64 {a!r}, aarch64 {b!r}")
    print(f"arm64_compare: {name}: largest relative difference {worst[0]:.3g}" + (f" at {worst[1]}" if worst[1] else ""))
    if diffs:
        print(f"arm64_compare: {name}: {len(diffs)} difference(s) beyond {rel:g} or in kind:")
        for d in diffs[:40]:
            print("  " + d)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
