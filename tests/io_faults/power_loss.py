#!/usr/bin/python3
"""Power loss under `rockwatch-monitor --log` (issue 41, item 3; docs/RELIABILITY.md "Power loss").

  power_loss.py --monitor M --rockwatch R --shim S [--runs N] [--first-seed K] [--keep DIR]

Each run (seeded): `rockwatch replay` sends a collapse record at 1 kHz; the monitor logs its traffic with --log under
the LD_PRELOAD shim io_fault_shim, which records the file's size after every fsync/fdatasync that succeeded
($ROCKWATCH_IOFAULT_DURABLE): the bytes a power cut cannot take. At a seeded moment the monitor is killed (SIGKILL)
while writing. Then, by seed:
  sigkill     nothing more: the page cache survives a killed process;
  power-cut   the page cache is lost too: the file is cut at a seeded length between the last durable size and its
              size, and what a write in flight leaves is appended: a page of zeros (not written back), a torn event
              (a prefix of the next one), or both.
Checks (each failure names it and prints the seed and the command that replays the run):
  durable   the last durable size is within the file, and the file's first durable bytes are unchanged after the
            restart (in the log, or in the copy kept aside as FILE.N when the damage is not at the end);
  reader    the project's reader (`rockwatch-monitor --offline-in`, lcm::LogFile) reads the cut file without failing,
            at least every event below the durable size;
  restart   a monitor restarted on the same file (the replay still sending) keeps every complete event (its summary's
            log.events_kept, the numbers continuing at log.first_event_number), cuts the torn tail
            (log.torn_bytes_cut), and appends; after SIGINT the whole log reads to its end, event numbers increasing,
            and holds the kept events plus those the restarted monitor reported written (log.events_written).
Exit 0 pass, 1 fail, 2 bad options, 77 skipped (no multicast on loopback).
"""

import argparse
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RECORD = os.path.join(SOURCE_DIR, "tests", "data", "records", "RSN753_LOMAP_CLS000-hor1.AT2")
SYNC = 0xEDA1DA01
SKIP = 77


class Failure(Exception):
    pass


class Skip(Exception):
    pass


def scan(data):
    """The complete events of LCM log bytes: list of (offset, end, number); the monitor's own rule (traffic_log.cpp)."""
    events, at = [], 0
    while at + 28 <= len(data):
        sync, number, _utime, clen, dlen = struct.unpack(">IqqII", data[at:at + 28])
        if sync != SYNC or clen == 0 or clen > 255 or dlen > (256 << 20) or at + 28 + clen + dlen > len(data):
            break
        events.append((at, at + 28 + clen + dlen, number))
        at += 28 + clen + dlen
    return events


def wait_for(pred, timeout, what):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if pred():
            return
        time.sleep(0.02)
    raise Failure(f"timed out waiting for {what}")


def start_monitor(a, url, log_path, durable, err_path, out_path):
    env = dict(os.environ, LD_PRELOAD=a.shim, ROCKWATCH_IOFAULT_MATCH=os.path.basename(log_path),
               ROCKWATCH_IOFAULT_DURABLE=durable)
    p = subprocess.Popen([a.monitor, "--lcm-url", url, "--rate", "1000", "--log", log_path],
                         stdout=open(out_path, "w"), stderr=open(err_path, "w"), env=env)

    def listening():
        if p.poll() is not None:
            err = open(err_path).read()
            if p.returncode == 2 and ("multicast" in err or "LCM could not start" in err):
                raise Skip(err.strip())
            raise Failure(f"restart: the monitor exited at start ({p.returncode}): {err.strip()}")
        return "listening on" in open(err_path).read()
    wait_for(listening, 10, "the monitor to listen")
    return p


def summary_of(out_path):
    for line in open(out_path):
        if line.startswith('{"summary"'):
            return json.loads(line)["summary"]
    raise Failure(f"restart: no summary line in {out_path}")


def read_with_monitor(a, path, work, tag):
    """The project's reader on a log: its offline summary (exit 0 required)."""
    out = os.path.join(work, f"{tag}.offline.lcmlog")
    r = subprocess.run([a.monitor, "--offline-in", path, "--offline-out", out], capture_output=True, text=True,
                       timeout=120)
    if r.returncode != 0:
        raise Failure(f"reader: `rockwatch-monitor --offline-in` failed on the {tag} log ({r.returncode}): "
                      f"{r.stderr.strip()[-400:]}")
    for line in r.stdout.splitlines():
        if line.startswith('{"summary"'):
            return json.loads(line)["summary"]
    raise Failure(f"reader: no summary reading the {tag} log")


def one_run(a, seed, work):
    rng = random.Random(seed)
    mode = "power-cut" if seed % 2 == 0 else "sigkill"
    port = 7760 + rng.randrange(0, 200)
    url = f"udpm://239.255.76.{160 + seed % 40}:{port}?ttl=0"
    log_path = os.path.join(work, "traffic.lcmlog")
    durable = os.path.join(work, "durable.txt")
    first = start_monitor(a, url, log_path, durable, os.path.join(work, "m1.err"), os.path.join(work, "m1.out"))
    replay = subprocess.Popen([a.rockwatch, "replay", "--record", RECORD, "--scale-pga", "0.3", "--rate", "1000",
                               "--lcm-url", url], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    second = None
    try:
        kill_at = rng.uniform(1.2, 3.2)
        time.sleep(kill_at)
        if replay.poll() is not None:
            err = replay.stderr.read()
            if replay.returncode == 2 and "multicast" in err:
                raise Skip(err.strip())
            raise Failure(f"rockwatch replay stopped early ({replay.returncode}): {err.strip()[-300:]}")
        first.send_signal(signal.SIGKILL)
        first.wait(timeout=10)
        size = os.path.getsize(log_path)
        sizes = [int(x) for x in open(durable).read().split()] if os.path.exists(durable) else []
        d = sizes[-1] if sizes else 0
        if d > size:
            raise Failure(f"durable: the last synced size {d} is beyond the file's {size} bytes")
        with open(log_path, "rb") as f:
            data = f.read()
        prefix = data[:d]
        durable_events = len([e for e in scan(data) if e[1] <= d])
        cut, tail = size, "none"
        if mode == "power-cut":
            # What was not synced is gone: the file cut at a seeded length above the durable size ...
            cut = rng.randint(d, size)
            data = bytearray(data[:cut])
            # ... and what a write in flight left: a page not written back (zeros), a torn event (a prefix of the
            # next one), or both.
            tail = rng.choice(["zeros", "torn", "zeros+torn"])
            whole = scan(bytes(data))
            if "zeros" in tail:
                data += bytes(rng.randint(1, 4096))
            if "torn" in tail and whole:
                start, end, number = whole[-1]
                event = bytearray(data[start:end])
                event[4:12] = struct.pack(">q", number + 1)
                data += event[:rng.randint(1, len(event) - 1)]
            with open(log_path, "wb") as f:
                f.write(data)
        data = bytes(data)
        events = scan(data)
        read = read_with_monitor(a, log_path, work, "cut")
        if read["log_events"] < durable_events:
            raise Failure(f"reader: {read['log_events']} events read of the cut log, fewer than the "
                          f"{durable_events} below its durable size {d}")
        # The restart, while the replay still sends.
        second = start_monitor(a, url, log_path, durable, os.path.join(work, "m2.err"), os.path.join(work, "m2.out"))
        time.sleep(1.5)
        second.send_signal(signal.SIGINT)
        second.wait(timeout=30)
        if second.returncode != 0:
            raise Failure(f"restart: the restarted monitor exited {second.returncode}: "
                          f"{open(os.path.join(work, 'm2.err')).read().strip()[-400:]}")
        s = summary_of(os.path.join(work, "m2.out"))["log"]
        with open(log_path, "rb") as f:
            final = f.read()
        rotated = s.get("rotated_to")
        kept_file = open(rotated, "rb").read() if rotated else final
        if kept_file[:d] != prefix:
            raise Failure(f"durable: the first {d} synced bytes changed after the restart"
                          + (f" (in {rotated})" if rotated else ""))
        if rotated:
            if kept_file != data:
                raise Failure(f"restart: the damaged log kept aside as {rotated} is not the file as it was")
            expect_kept, expect_first = 0, 0
        else:
            expect_kept = len(events)
            expect_first = events[-1][2] + 1 if events else 0
            if s["torn_bytes_cut"] != len(data) - (events[-1][1] if events else 0):
                raise Failure(f"restart: torn_bytes_cut {s['torn_bytes_cut']}, the file had "
                              f"{len(data) - (events[-1][1] if events else 0)} bytes after its last complete event")
        if s["events_kept"] != expect_kept or s["first_event_number"] != expect_first:
            raise Failure(f"restart: kept {s['events_kept']} events from number {s['first_event_number']}; expected "
                          f"{expect_kept} from {expect_first}")
        final_events = scan(final)
        if final_events and final_events[-1][1] != len(final):
            raise Failure(f"restart: the final log has {len(final) - final_events[-1][1]} unreadable bytes at its end")
        numbers = [e[2] for e in final_events]
        if any(b <= x for x, b in zip(numbers, numbers[1:])):
            raise Failure("restart: event numbers do not increase through the final log")
        if len(final_events) != expect_kept + s["events_written"] or s["events_lost"] != 0:
            raise Failure(f"restart: the final log has {len(final_events)} events; kept {expect_kept} + written "
                          f"{s['events_written']} (lost {s['events_lost']})")
        read = read_with_monitor(a, log_path, work, "final")
        if not read["input_log_complete"] or read["log_events"] != len(final_events):
            raise Failure(f"reader: the final log read {read['log_events']} of {len(final_events)} events "
                          f"(complete {read['input_log_complete']})")
        return (f"seed {seed} {mode}: killed at {kill_at:.2f} s, {size} bytes, synced {d} ({durable_events} events, "
                f"{len(sizes)} syncs), cut at {cut} + {tail}: {len(events)} complete; restart kept {s['events_kept']}"
                f"{' (rotated)' if rotated else ''}, cut {s['torn_bytes_cut']} torn bytes, wrote {s['events_written']}")
    finally:
        for p in (first, second, replay):
            if p is not None and p.poll() is None:
                p.kill()
                p.wait()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--monitor", required=True)
    ap.add_argument("--rockwatch", required=True)
    ap.add_argument("--shim", required=True, help="io_fault_shim.so")
    ap.add_argument("--runs", type=int, default=4)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--keep", help="keep each run's files under this directory")
    a = ap.parse_args()
    for path, what in ((a.monitor, "--monitor"), (a.rockwatch, "--rockwatch"), (a.shim, "--shim"), (RECORD, "record")):
        if not os.path.exists(path):
            print(f"power_loss.py: {what} {path!r} does not exist", file=sys.stderr)
            return 2
    failed = 0
    for seed in range(a.first_seed, a.first_seed + a.runs):
        work = tempfile.mkdtemp(prefix=f"rockwatch-power-loss-{seed}-", dir=a.keep)
        try:
            print(one_run(a, seed, work), flush=True)
        except Skip as e:
            print(f"power_loss.py: skipped: no multicast on loopback ({e})", file=sys.stderr)
            return SKIP
        except Failure as e:
            failed += 1
            print(f"FAIL seed {seed}: {e}\n  replay: {sys.argv[0]} --monitor {a.monitor} --rockwatch {a.rockwatch} "
                  f"--shim {a.shim} --runs 1 --first-seed {seed} --keep DIR", flush=True)
        finally:
            if not a.keep:
                shutil.rmtree(work, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
