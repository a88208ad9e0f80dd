#!/usr/bin/env python3
"""Whole-process start-up times, paired and alternated (docs/BENCHMARKS.md, "Start-up").

Runs each command once per round, in turn, for --rounds rounds (after --warmup rounds not counted), so that a change
of the machine's load touches every command alike; `/bin/true` is the floor (what starting any process costs here).
Each run is posix_spawn + waitpid, timed with time.perf_counter; stdout and stderr go to /dev/null; a command that
exits non-zero stops the measurement. Prints the load average before and after, and per command the median, mean,
10th and 90th percentiles, and the median of the paired differences against the floor.

  startup_timing.py BUILD_DIR [--rounds N] [--warmup N] [--record FILE]...

The default records: RSN175 (39.1 s at 200 Hz: "a 40 s record") and RSN6 El Centro 180 (53.7 s at 100 Hz), each
through `rockwatch simulate --scale-pga 0.2` (text output; both survive).
"""
import argparse
import os
import statistics
import sys
import time


def run_once(argv, devnull):
    t0 = time.perf_counter()
    pid = os.posix_spawn(argv[0], argv, os.environ, file_actions=[
        (os.POSIX_SPAWN_DUP2, devnull, 1), (os.POSIX_SPAWN_DUP2, devnull, 2)])
    _, status = os.waitpid(pid, 0)
    t1 = time.perf_counter()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"startup_timing: {' '.join(argv)} exited with {os.waitstatus_to_exitcode(status)}")
    return t1 - t0


def percentile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, max(0, round(q * (len(s) - 1))))]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("build_dir")
    p.add_argument("--rounds", type=int, default=200)
    p.add_argument("--warmup", type=int, default=20)
    p.add_argument("--record", action="append")
    a = p.parse_args()
    tools = os.path.join(a.build_dir, "host_tools")
    rockwatch = os.path.join(tools, "rockwatch")
    commands = [
        ("/bin/true", ["/bin/true"]),
        ("rockwatch --version", [rockwatch, "--version"]),
        ("rockwatch-monitor --version", [os.path.join(tools, "rockwatch-monitor"), "--version"]),
    ]
    records = a.record or ["tests/data/records/RSN175_IMPVALL.H_H-E12140.AT2",
                           "tests/data/records/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"]
    for record in records:
        commands.append((f"rockwatch simulate --record {os.path.basename(record)} --scale-pga 0.2",
                         [rockwatch, "simulate", "--record", record, "--scale-pga", "0.2"]))
    devnull = os.open(os.devnull, os.O_WRONLY)
    times = {name: [] for name, _ in commands}
    load_before = os.getloadavg()
    for r in range(a.warmup + a.rounds):
        for name, argv in commands:
            t = run_once(argv, devnull)
            if r >= a.warmup:
                times[name].append(t)
    load_after = os.getloadavg()
    print(f"load average before {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f}, "
          f"after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}; {a.rounds} rounds, {a.warmup} warm-up")
    floor = times["/bin/true"]
    print(f"{'command':72s} {'median':>8s} {'mean':>8s} {'p10':>8s} {'p90':>8s} {'- floor':>8s}  [ms]")
    for name, _ in commands:
        v = times[name]
        diff = statistics.median(x - f for x, f in zip(v, floor))
        print(f"{name:72s} {1e3 * statistics.median(v):8.2f} {1e3 * statistics.mean(v):8.2f} "
              f"{1e3 * percentile(v, 0.1):8.2f} {1e3 * percentile(v, 0.9):8.2f} {1e3 * diff:8.2f}")


if __name__ == "__main__":
    main()
