#!/usr/bin/python3
"""A shipped-suite record (time_s x_mps2 ...) resampled to 1 kHz, linear between its samples: one 1 ms step per
sample for the 1 kHz cases of tests/firmware/m4/m4_cases.sh and tests/bench/arm64_monitor_instructions.sh.

    resample_1khz.py IN.txt OUT.txt      (the first data column after time: set N X)
"""
import sys

if len(sys.argv) != 3:
    sys.exit(__doc__)
rows = [l.split() for l in open(sys.argv[1]) if l.strip() and not l.startswith("#")]
t, x = [float(r[0]) for r in rows], [float(r[1]) for r in rows]
dt = t[1] - t[0]
with open(sys.argv[2], "w") as f:
    f.write("# set 1 X of sim/suites/npr9998-2015 resampled to 1 kHz (linear); columns: time_s x_mps2\n")
    for k in range(round(t[-1] / 0.001) + 1):
        tk = k * 0.001
        i = min(int(tk / dt + 1e-9), len(x) - 2)
        a = (tk - t[i]) / dt
        f.write("%.3f %.9e\n" % (tk, x[i] + (x[i + 1] - x[i]) * a))
