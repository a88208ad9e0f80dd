#!/usr/bin/env python3
"""ctest-timeouts.py LABEL BUILD_DIR JUNIT_XML...: the entries closest to their timeouts (scripts/test.sh, issue 42).

Each ctest entry must take at most a quarter of its TIMEOUT, also with one core busy (docs/BENCHMARKS.md "The test
loop"), so that a loaded machine slows a run without failing it. Reads the times of the JUnit files and the timeouts
of `ctest --show-only=json-v1` in BUILD_DIR (an entry without TIMEOUT has ctest's default, 1500 s) and prints the
five entries with the largest share of their timeout, and every entry over a quarter, e.g.
  release: closest to their timeouts: m4_monitor_wire 83.1 s of 400 (21 %), ...; over a quarter: none
Informational: it exits 0 (the timeout itself is what fails a run).
"""
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

DEFAULT_TIMEOUT_S = 1500.0

label, build, paths = sys.argv[1], sys.argv[2], sys.argv[3:]
try:
    shown = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1"], capture_output=True, text=True,
                           check=True).stdout
    timeouts = {t["name"]: next((p["value"] for p in t.get("properties", []) if p["name"] == "TIMEOUT"),
                                DEFAULT_TIMEOUT_S) for t in json.loads(shown)["tests"]}
except (OSError, subprocess.CalledProcessError, ValueError, KeyError) as e:
    print(f"{label}: no timeouts ({e})")
    sys.exit(0)
shares = []
for path in paths:
    try:
        cases = ET.parse(path).getroot().iter("testcase")
    except (OSError, ET.ParseError) as e:
        print(f"{label}: no ctest results in {path} ({e})")
        continue
    for c in cases:
        if c.get("status") not in ("run", "fail"):
            continue
        name, time_s = c.get("name"), float(c.get("time") or 0.0)
        limit_s = float(timeouts.get(name, DEFAULT_TIMEOUT_S))
        shares.append((time_s / limit_s, name, time_s, limit_s))
shares.sort(reverse=True)
fmt = lambda s: f"{s[1]} {s[2]:.1f} s of {s[3]:.0f} ({100 * s[0]:.0f} %)"
over = [fmt(s) for s in shares if s[0] > 0.25]
print(f"{label}: closest to their timeouts: " + ", ".join(fmt(s) for s in shares[:5]) +
      "; over a quarter: " + (", ".join(over) if over else "none"))
