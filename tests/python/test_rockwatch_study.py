"""`rockwatch.study`: the statistics of `rockwatch study` for Python, against the tool (a small study's summary.json
recomputed from its runs.csv, bit for bit) and against numpy on hand-made inputs.

Run by ctest (test_python_module) with PYTHONPATH=<build>/python and ROCKWATCH_CLI=<build>/host_tools/rockwatch.
"""
import csv
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import rockwatch

REPO = pathlib.Path(__file__).resolve().parents[2]
SUITE = REPO / "sim" / "suites" / "npr9998-2015"
CLI = os.environ.get("ROCKWATCH_CLI") or str(pathlib.Path(rockwatch.__file__).resolve().parents[1] / "host_tools" / "rockwatch")


def test_quantile_type7_is_numpys_default():
    rng = np.random.default_rng(7)
    values = rng.normal(size=101)
    for p in (0.0, 0.05, 0.5, 0.9, 0.95, 1.0):
        assert rockwatch.study.quantile_type7(values, p) == pytest.approx(np.quantile(values, p), abs=1e-15)
    assert rockwatch.study.quantile_type7([3.0, 1.0, 2.0], 0.5) == 2.0  # any order
    assert rockwatch.study.quantile_type7([], 0.5) is None
    with pytest.raises(ValueError, match="p must be in"):
        rockwatch.study.quantile_type7([1.0], 1.5)


def test_fit_logistic_zeroes_the_likelihood_gradient():
    rng = np.random.default_rng(3)
    f = rng.uniform(0.0, 3.0, size=200)
    y = (rng.uniform(size=200) < 1.0 / (1.0 + np.exp(-(2.0 * f - 3.0)))).astype(float)
    x = np.column_stack([np.ones_like(f), f])
    w = rockwatch.study.fit_logistic(x, y)
    p = 1.0 / (1.0 + np.exp(-(x @ w)))
    assert np.max(np.abs(x.T @ (y - p))) < 1e-6  # the maximum-likelihood equations
    half = rockwatch.study.fit_logistic(x, y, use=np.arange(200) < 100)
    assert np.array_equal(half, rockwatch.study.fit_logistic(x[:100], y[:100]))
    with pytest.raises(ValueError, match="y has 3 outcomes"):
        rockwatch.study.fit_logistic(x, [0, 1, 0])
    with pytest.raises(ValueError, match="0 or 1"):
        rockwatch.study.fit_logistic(x, np.full(200, 0.5))


def test_reliability_and_brier():
    p = np.array([0.05, 0.05, 0.95, 0.5])
    o = np.array([0, 1, 1, 0])
    r = rockwatch.study.reliability(p, o)
    assert r["brier"] == pytest.approx(np.mean((p - o) ** 2), abs=1e-15)
    assert [b["n"] for b in r["bins"]] == [2, 1, 1]
    assert r["bins_judged"] == 0 and r["calibration_max_error"] is None


def _runs_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_alarm_outcome_equals_the_study(tmp_path):
    out = tmp_path / "study"
    subprocess.run([CLI, "study", "--suite", str(SUITE), "--sets", "1", "--r", "ana", "--vertical", "without",
                    "--pga", "0.2:0.6:0.2", "--alarms", "--jobs", "2", "--out", str(out)],
                   check=True, capture_output=True, timeout=300)
    summary = json.loads((out / "summary.json").read_text())["alarm"]
    rows = [r for r in _runs_csv(out / "runs.csv") if not r["error"]]
    time = lambda text: float(text) if text else math.nan  # noqa: E731
    a = rockwatch.study.alarm_outcome([r["collapsed"] == "true" for r in rows],
                                      [time(r["t_collapse_s"]) for r in rows],
                                      [time(r["t_first_imminent_s"]) for r in rows])
    assert a["counts"]["collapsed"] > 0
    for key in ("recall", "false_alarm_rate", "lead_time_s_median", "lead_time_s_p05", "lead_time_s_min", "counts"):
        assert a[key] == summary[key], key
    assert list(a["lead_times_s"]) == sorted(a["lead_times_s"])
