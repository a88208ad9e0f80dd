#!/usr/bin/python3
"""Compares the Cortex-M4 replay of a record (scripts/m4-replay.sh: its JSON and --m4-trace CSV) with the host's
`rockwatch simulate --arith fixed --alarms --json --out HISTORY.csv` of the same options. Exit 0 when
  - the alarm transitions are the same, at the same samples, with the same levels (the host's times t_s mapped to the
    sample whose interval ended there: t_s in ((k-1)·T, k·T] is sample k, T = n·dt the sample interval of n
    sub-steps of dt; a collapse ends its sample early),
  - the replay ran exactly the host's samples (the history has one row for the start and one per sub-step: n per
    sample, the last sample cut at the collapse), and
  - the published displacement x_m and velocity xd_mps are bit-identical at every sample (so the engine's fixed-point
    constants, set up in double on each machine, are the same in effect),
  - the verdict is the one the case expects (collapse | survive);
else exit 1 naming the first difference.

  compare_m4_host.py M4_JSON M4_TRACE_CSV HOST_JSON HOST_HISTORY_CSV collapse|survive|any
"""
import csv
import json
import math
import sys


def fail(message):
    print("MISMATCH: " + message)
    sys.exit(1)


def main():
    if len(sys.argv) != 6 or sys.argv[5] not in ("collapse", "survive", "any"):
        sys.stderr.write(__doc__)
        sys.exit(2)
    m4 = json.load(open(sys.argv[1]))
    trace = list(csv.DictReader(open(sys.argv[2])))
    host = json.load(open(sys.argv[3]))
    history = list(csv.DictReader(open(sys.argv[4])))
    expect = sys.argv[5]

    if host.get("arithmetic") != "fixed":
        fail("the host ran %r, not the fixed-point engine" % host.get("arithmetic"))
    alarm = host["alarm"]
    if alarm["n_transitions"] != len(alarm["transitions"]):
        fail("the host listed %d of %d transitions: pick a shorter case" % (len(alarm["transitions"]), alarm["n_transitions"]))
    samples = m4["samples"]
    if samples < 2:
        fail("the M4 ran %d samples" % samples)
    n_sub = max(1, math.ceil((len(history) - 1) / (samples - 1)))  # sub-steps per sample
    if not (samples - 2) * n_sub + 1 < len(history) <= (samples - 1) * n_sub + 1:
        fail("the M4 ran %d samples, the host %d sub-steps + the start (%d per sample)" % (
            samples, len(history) - 1, n_sub))
    period = host["dt_s"] * n_sub
    host_transitions = [{"sample": math.ceil(t["t_s"] / period - 1e-6), "level": t["level"]}
                        for t in alarm["transitions"]]
    # The history's row at each sample's end (the last sample's: where it stopped).
    history = [history[min(k * n_sub, len(history) - 1)] for k in range(samples)]
    if len(trace) != m4["samples"]:
        fail("the trace has %d rows for %d samples" % (len(trace), m4["samples"]))
    if m4["transitions"] != host_transitions:
        for i, (a, b) in enumerate(zip(m4["transitions"], host_transitions)):
            if a != b:
                fail("transition %d: M4 %s, host %s" % (i, a, b))
        fail("M4 %d transitions, host %d" % (len(m4["transitions"]), len(host_transitions)))
    for k, (t, h) in enumerate(zip(trace, history)):
        for key in ("x_m", "xd_mps"):
            if float(t[key]) != float(h[key]):
                fail("sample %d: %s on the M4 %r, on the host %r" % (k, key, float(t[key]), float(h[key])))

    collapsed = host["collapsed"] or host.get("collapse_after_end", False)
    m4_collapsed = bool(m4["transitions"]) and m4["transitions"][-1]["level"] == "COLLAPSED"
    if collapsed != m4_collapsed:
        fail("the host says collapsed=%s, the M4's last level is %s" % (collapsed, m4["transitions"][-1:]))
    if expect != "any" and collapsed != (expect == "collapse"):
        fail("the case was chosen to %s but the wall %s" % (expect, "collapses" if collapsed else "survives"))

    ips = m4["insn_per_sample"]
    print("identical: %d samples, %d transitions (%s), x and xd bit-identical at every sample; M4 instructions per "
          "sample median %d, p99 %d, max %d (sample %d)" % (
              m4["samples"], len(host_transitions),
              ", ".join("%d %s" % (t["sample"], t["level"]) for t in host_transitions),
              ips["median"], ips["p99"], ips["max"], ips["max_sample"]))


main()
