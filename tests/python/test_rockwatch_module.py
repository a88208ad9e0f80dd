"""`import rockwatch` against the `rockwatch` tool: for the same input every function gives the tool's numbers, bit
for bit (the tool's JSON printed in shortest round-trip form, so json.loads gives back the very doubles), and bad
arguments raise ValueError (TypeError for a wrong type) with the tool's message.

Run by ctest (test_python_module) with PYTHONPATH=<build>/python and ROCKWATCH_CLI=<build>/host_tools/rockwatch.
"""
import csv
import json
import os
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import rockwatch

REPO = pathlib.Path(__file__).resolve().parents[2]
RECORDS = REPO / "tests" / "data" / "records"
ELC = str(RECORDS / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2")
ELC_UP = str(RECORDS / "RSN6_IMPVALL.I_I-ELC-UP.AT2")
NORTHRIDGE = str(RECORDS / "RSN960_NORTHR_LOS270.AT2")
ITACA = str(RECORDS / "16833_H1.cor.acc")
MSEED = str(RECORDS / "NL.BGAR.mseed")
CLI = os.environ.get("ROCKWATCH_CLI") or str(pathlib.Path(rockwatch.__file__).resolve().parents[1] / "host_tools" / "rockwatch")


def cli(*args, expect=0):
    """Runs the tool; returns its stdout (parsed when --json) or, with expect=2, its error message."""
    p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=300)
    assert p.returncode == expect, p.stderr
    if expect != 0:
        return p.stderr.strip().split(": error: ", 1)[1]
    return json.loads(p.stdout) if "--json" in args else p.stdout


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


# ------------------------------------------------------------------------------------------------------- simulate

SIMULATE_CASES = [
    # (the CLI's options beyond --record/--vertical, the module's arguments)
    (["--scale-pga", "0.25"], dict(scale_pga_g=0.25)),
    (["--scale-pga", "0.35", "--r", "ana"], dict(scale_pga_g=0.35, r="ana")),
    (["--scale-pga", "0.3", "--r", "0.71", "--kappa", "1.5", "--max-step", "0.005"],
     dict(scale_pga_g=0.3, r=0.71, kappa=1.5, max_step_s=0.005)),
    (["--scale-pga", "0.4", "--r", "impulse", "--b", "0.12", "--h1", "1.6", "--h2", "1.8", "--fp", "1500", "--a", "0.3",
      "--a-prime", "0.1", "--rho", "1900"],
     dict(scale_pga_g=0.4, r="impulse",
          wall=rockwatch.Wall(b_m=0.12, h1_m=1.6, h2_m=1.8, fp_npm=1500, a=0.3, a_prime=0.1, rho_kgpm3=1900))),
    (["--scale-pga", "0.3", "--alarms", "--arith", "fixed"], dict(scale_pga_g=0.3, alarms=True, arith="fixed")),
    (["--scale-pga", "0.3", "--alarms", "--lambda-w", "0.6", "--alarm-hold", "0.5", "--energy-margin", "2"],
     dict(scale_pga_g=0.3, alarms=True, lambda_w=0.6, alarm_hold_s=0.5, energy_margin=2)),
    (["--scale-pga", "0.25", "--alarms", "--imminent-horizon", "0.17", "--energy-min-x", "0.5"],
     dict(scale_pga_g=0.25, alarms=True, imminent_horizon_s=0.17, energy_min_x=0.5)),
    (["--model", "full", "--t-end", "20", "--scale-pga", "0.3"], dict(model="full", t_end_s=20, scale_pga_g=0.3)),
    ([], {}),
]


@pytest.mark.parametrize("options,kwargs", SIMULATE_CASES)
def test_simulate_equals_the_tool_to_the_bit(options, kwargs, tmp_path):
    expected = cli("simulate", "--record", ELC, *options, "--json", "--out", tmp_path / "h.csv")
    rec = rockwatch.read_record(ELC)
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, **kwargs)
    assert got.keys() == list(expected.keys())
    assert got.as_dict() == expected
    for key, value in expected.items():
        assert getattr(got, key) == value
    header, rows = read_csv(tmp_path / "h.csv")
    names = ["t_s", "ug_mps2", "vg_mps2", "x_m", "xd_mps", "xdd_mps2", "alpha1_rad", "alpha2_rad", "side"]
    assert len(header) == len(names)
    for i, name in enumerate(names):
        assert np.array_equal(getattr(got, name), rows[:, i]), name


def test_simulate_with_a_vertical_record_equals_the_tool():
    expected = cli("simulate", "--record", ELC, "--vertical", ELC_UP, "--scale-pga", "0.3", "--r", "ana", "--json")
    rec = rockwatch.read_record(ELC, vertical=ELC_UP)
    assert rec.vertical_mps2 is not None and len(rec.vertical_mps2) == len(rec.accel_mps2)
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, vertical_mps2=rec.vertical_mps2, scale_pga_g=0.3, r="ana")
    assert got.as_dict() == expected


@pytest.mark.parametrize("path,options,read_kwargs", [
    (ITACA, [], {}),
    (NORTHRIDGE, ["--g", "9.80665"], dict(g_mps2=9.80665)),
])
def test_other_readers_equal_the_tool(path, options, read_kwargs):
    expected = cli("simulate", "--record", path, "--scale-pga", "0.3", *options, "--json")
    rec = rockwatch.read_record(path, **read_kwargs)
    wall = rockwatch.Wall(g_mps2=read_kwargs["g_mps2"]) if read_kwargs else None
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, wall=wall, scale_pga_g=0.3)
    assert got.as_dict() == expected


def test_suite_record_equals_the_tool():
    # simulate takes samples, not files: the keys that name the file's selection (suite, component, channel,
    # vertical_channel, gain_counts_per_mps2) are the tool's alone.
    suite = REPO / "sim" / "suites" / "npr9998-2015"
    expected = cli("simulate", "--suite", suite, "--set", "3", "--component", "Y", "--vertical-from-suite",
                   "--scale-pga", "0.2", "--r", "ana", "--json")
    assert expected.pop("suite")["file"] == str(suite / "set03.txt")
    rec = rockwatch.read_record(str(suite / "set03.txt"), component="Y", vertical=str(suite / "set03.txt"),
                                vertical_channel="Z")
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, vertical_mps2=rec.vertical_mps2, scale_pga_g=0.2, r="ana")
    assert got.as_dict() == expected
    assert rec.format == "rockwatch-suite" and rec.source == "component Y"


def test_wall_file_equals_the_tool(tmp_path):
    wall_file = tmp_path / "wall.json"
    wall_file.write_text(json.dumps({"format": "rockwatch-wall", "version": 1, "b_m": 0.11, "h1_m": 1.7, "h2_m": 1.65,
                                     "rho_kgpm3": 1850.0, "fp_npm": 0.0, "a": 0.0, "a_prime": 0.0, "g_mps2": 9.81,
                                     "r": 0.8}))
    wall = rockwatch.Wall.from_file(str(wall_file))
    assert (wall.b_m, wall.h1_m, wall.r, wall.wall_file) == (0.11, 1.7, 0.8, str(wall_file))
    rec = rockwatch.read_record(ELC)
    for options, kwargs in [([], {}), (["--r", "ana"], dict(r="ana"))]:
        expected = cli("simulate", "--record", ELC, "--wall-file", wall_file, "--scale-pga", "0.3", *options, "--json")
        got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, wall=wall, scale_pga_g=0.3, **kwargs)
        assert got.as_dict() == expected
        assert got.wall_file == str(wall_file)
    assert rockwatch.Wall.from_file(str(wall_file), b_m=0.1).b_m == 0.1


def test_simulate_with_wall_sensors_equals_the_tool(tmp_path):
    sensors = tmp_path / "sensors.csv"
    cli("simulate", "--record", ELC, "--scale-pga", "0.2", "--r", "0.8", "--sensors-out", sensors)
    expected = cli("simulate", "--record", ELC, "--scale-pga", "0.2", "--wall-sensors", sensors, "--alarms", "--json")
    rec = rockwatch.read_record(ELC)
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, scale_pga_g=0.2, wall_sensors=str(sensors), alarms=True)
    assert got.as_dict() == expected
    assert got.observer["n_updates"] > 0


def test_read_record_metadata():
    rec = rockwatch.read_record(ELC)
    assert rec.format == "peer-at2" and rec.units == "g" and rec.dt_s == 0.01
    assert rec.vertical_mps2 is None
    assert isinstance(rec.accel_mps2, np.ndarray) and rec.accel_mps2.dtype == np.float64
    assert len(rec) == len(rec.accel_mps2) > 1000
    assert "IMPERIAL" in rec.description.upper()
    assert rockwatch.read_record(ELC, units="cmps2").accel_mps2[5] == pytest.approx(rec.accel_mps2[5] / 9.81 / 100)


def test_alarm_transitions_are_dicts():
    rec = rockwatch.read_record(ELC)
    got = rockwatch.simulate(rec.accel_mps2, rec.dt_s, scale_pga_g=0.4, alarms=True)
    assert got.alarm_transitions == got.alarm["transitions"]
    assert got.alarm_transitions and set(got.alarm_transitions[0]) >= {"t_s", "level", "previous", "x_m", "reasons"}
    assert rockwatch.simulate(rec.accel_mps2, rec.dt_s, scale_pga_g=0.4).alarm_transitions == []


def test_the_paper_wall_is_the_default():
    w = rockwatch.Wall.paper()
    assert (w.b_m, w.h1_m, w.h2_m, w.rho_kgpm3, w.fp_npm, w.a, w.a_prime, w.g_mps2) == (0.1, 1.75, 1.75, 1800, 0, 0, 0, 9.81)
    assert w.r is None and w.wall_file is None
    rec = rockwatch.read_record(ELC)
    assert (rockwatch.simulate(rec.accel_mps2, rec.dt_s, wall=w, scale_pga_g=0.3).as_dict() ==
            rockwatch.simulate(rec.accel_mps2, rec.dt_s, scale_pga_g=0.3, history=False).as_dict())


# ------------------------------------------------------------------------------------------- the other functions

@pytest.mark.parametrize("options,kwargs", [
    ([], {}),
    (["--code", "nzsee2016", "--h", "4.2", "--b", "0.14", "--fp", "2000", "--a", "0.5"],
     dict(code="nzsee2016", h_m=4.2, b_m=0.14, fp_npm=2000, a=0.5)),
    (["--lambda", "0.5", "--psi", "0.01", "--spectrum", "ec8-1A"], dict(lambda_=0.5, psi_rad=0.01, spectrum="ec8-1A")),
])
def test_static_check_equals_the_tool(options, kwargs):
    assert rockwatch.static_check(**kwargs) == cli("static", *options, "--json")


def test_static_check_of_a_wall():
    wall = rockwatch.Wall(b_m=0.12, h1_m=1.5, h2_m=1.9, fp_npm=800, a=0.2)
    expected = cli("static", "--b", "0.12", "--h1", "1.5", "--h2", "1.9", "--fp", "800", "--a", "0.2", "--code",
                   "ntc2008", "--json")
    assert rockwatch.static_check(wall=wall, code="ntc2008") == expected


@pytest.mark.parametrize("options,args", [([], ()), (["--periods", "0.05:3:40"], ("0.05:3:40",))])
def test_response_spectrum_equals_the_tool(options, args):
    expected = cli("spectrum", "--record", ELC, *options, "--json")
    rec = rockwatch.read_record(ELC)
    got = rockwatch.response_spectrum(rec.accel_mps2, rec.dt_s, *args)
    assert got.periods_s.tolist() == expected["periods_s"]
    assert got.sa_mps2.tolist() == expected["sa_mps2"]
    for key in ["pga_mps2", "pgv_mps", "pgd_m", "arias_mps", "d5_75_s", "d5_95_s"]:
        assert getattr(got, key) == expected[key], key
    periods = np.array(expected["periods_s"])
    assert np.array_equal(rockwatch.response_spectrum(rec.accel_mps2, rec.dt_s, periods).psa_mps2, got.psa_mps2)


def test_identify_equals_the_tool(tmp_path):
    sensors = tmp_path / "snap.csv"
    cli("simulate", "--x0", "0.03", "--b", "0.12", "--r", "0.8", "--t-end", "4", "--sensors-out", sensors)
    expected = cli("identify", "--wall-sensors", sensors, "--wall-out", tmp_path / "cli_wall.json", "--json")
    got = rockwatch.identify(str(sensors), wall_out=str(tmp_path / "py_wall.json"))
    curve = {k: got.pop(k) for k in ("t_s", "measured_m", "fitted_m")}
    expected["wall_out"] = str(tmp_path / "py_wall.json")
    assert got == expected
    assert len(curve["t_s"]) == got["samples_used"]
    assert (json.loads((tmp_path / "py_wall.json").read_text()) ==
            json.loads((tmp_path / "cli_wall.json").read_text()))
    wall = rockwatch.Wall.from_file(str(tmp_path / "py_wall.json"))
    assert wall.r == got["r"] and wall.b_m == got["wall"]["b_m"]
    # From another starting wall and r, and a forced test.
    expected = cli("identify", "--wall-sensors", sensors, "--b", "0.13", "--h1", "1.8", "--r", "ana", "--json")
    got = rockwatch.identify(str(sensors), wall=rockwatch.Wall(b_m=0.13, h1_m=1.8), r="ana")
    assert {k: v for k, v in got.items() if k not in curve} == expected
    # With a bootstrap (its spread the standard errors), on two threads.
    expected = cli("identify", "--wall-sensors", sensors, "--bootstrap", "3", "--jobs", "2", "--json")
    got = rockwatch.identify(str(sensors), bootstrap=3, jobs=2)
    assert {k: v for k, v in got.items() if k not in curve} == expected
    assert got["sigma_method"] == "bootstrap" and got["bootstrap"]["replicates"] == 3
    forced = tmp_path / "forced.csv"
    cli("simulate", "--record", ELC, "--scale-pga", "0.18", "--b", "0.12", "--r", "0.8", "--t-end", "12",
        "--sensors-out", forced)
    expected = cli("identify", "--wall-sensors", forced, "--record", ELC, "--scale-pga", "0.18", "--json")
    got = rockwatch.identify(str(forced), record=ELC, scale_pga_g=0.18)
    assert {k: v for k, v in got.items() if k not in curve} == expected


# ------------------------------------------------------------------------------------------------------- refusals

def message(call):
    with pytest.raises(ValueError) as e:
        call()
    return str(e.value)


def test_bad_arguments_raise_the_tools_message():
    rec = rockwatch.read_record(ELC)
    a, dt = rec.accel_mps2, rec.dt_s
    cases = [
        (lambda: rockwatch.Wall(b_m=-0.1), ["simulate", "--record", ELC, "--b", "-0.1"]),
        (lambda: rockwatch.Wall(h1_m=0.05), ["simulate", "--record", ELC, "--h1", "0.05"]),
        (lambda: rockwatch.simulate(a, dt, r="bogus"), ["simulate", "--record", ELC, "--r", "bogus"]),
        (lambda: rockwatch.simulate(a, dt, r=1.5), ["simulate", "--record", ELC, "--r", "1.5"]),
        (lambda: rockwatch.simulate(a, dt, scale_pga_g=-1), ["simulate", "--record", ELC, "--scale-pga", "-1"]),
        (lambda: rockwatch.simulate(a, dt, kappa=0.5), ["simulate", "--record", ELC, "--kappa", "0.5"]),
        (lambda: rockwatch.simulate(a, dt, arith="float"), ["simulate", "--record", ELC, "--arith", "float"]),
        (lambda: rockwatch.simulate(a, dt, max_step_s=0), ["simulate", "--record", ELC, "--max-step", "0"]),
        (lambda: rockwatch.simulate(a, dt, max_step_s=1e-5), ["simulate", "--record", ELC, "--max-step", "1e-5"]),
        (lambda: rockwatch.simulate(a, dt, t_end_s=1e9, history=False), ["simulate", "--record", ELC, "--t-end", "1e9"]),
        (lambda: rockwatch.static_check(code="ec8"), ["static", "--code", "ec8"]),
        (lambda: rockwatch.static_check(h_m=0.05), ["static", "--h", "0.05"]),
        (lambda: rockwatch.read_record(ELC, units="furlongs"), ["simulate", "--record", ELC, "--units", "furlongs"]),
        (lambda: rockwatch.read_record(MSEED), ["simulate", "--record", MSEED]),
        (lambda: rockwatch.simulate(a, dt, wall_sensors="/nonexistent.csv"),
         ["simulate", "--record", ELC, "--wall-sensors", "/nonexistent.csv"]),
        (lambda: rockwatch.identify("/nonexistent.csv"), ["identify", "--wall-sensors", "/nonexistent.csv"]),
        (lambda: rockwatch.identify(ELC, bootstrap=-1), ["identify", "--wall-sensors", ELC, "--bootstrap=-1"]),
        (lambda: rockwatch.Wall.from_file(ELC), ["simulate", "--record", ELC, "--wall-file", ELC]),
        # The typed settings' checks (one function for the parser and the module): non-finite numbers, combinations.
        (lambda: rockwatch.Wall(b_m=float("nan")), ["simulate", "--record", ELC, "--b", "nan"]),
        (lambda: rockwatch.static_check(b_m=float("inf")), ["static", "--b", "inf"]),
        (lambda: rockwatch.static_check(lambda_=0.5, code="ntc2008"), ["static", "--lambda", "0.5", "--code", "ntc2008"]),
        (lambda: rockwatch.static_check(p=2.5), ["static", "--p", "2.5"]),
        (lambda: rockwatch.static_check(spectrum="custom", p=2.5), ["static", "--spectrum", "custom", "--p", "2.5"]),
        (lambda: rockwatch.read_record(ELC, dt_s=-1), ["simulate", "--record", ELC, "--dt=-1"]),
        (lambda: rockwatch.read_record(ELC, component="Q"), ["simulate", "--record", ELC, "--component", "Q"]),
        (lambda: rockwatch.identify(ELC, jobs=2), ["identify", "--wall-sensors", ELC, "--jobs", "2"]),
        (lambda: rockwatch.identify(ELC, units="g"), ["identify", "--wall-sensors", ELC, "--units", "g"]),
        (lambda: rockwatch.identify(ELC, record=ELC, max_step_s=0),
         ["identify", "--wall-sensors", ELC, "--record", ELC, "--max-step", "0"]),
    ]
    for call, args in cases:
        assert message(call) == cli(*args, expect=2), args


def test_bad_arguments_raise_clear_messages(tmp_path):
    rec = rockwatch.read_record(ELC)
    a, dt = rec.accel_mps2, rec.dt_s
    assert "does not exist" in message(lambda: rockwatch.read_record(str(tmp_path / "none.AT2"))) or \
        "none.AT2" in message(lambda: rockwatch.read_record(str(tmp_path / "none.AT2")))
    assert "--dt" in message(lambda: rockwatch.simulate(a, -0.01))
    assert "(history=True)" in message(lambda: rockwatch.simulate(a, dt, t_end_s=1e6))
    assert "one-dimensional" in message(lambda: rockwatch.simulate(np.zeros((3, 3)), dt))
    assert "vertical_mps2 has 3 samples" in message(lambda: rockwatch.simulate(a, dt, vertical_mps2=np.zeros(3)))
    assert "peak |u''| = 0" in message(lambda: rockwatch.simulate(np.zeros(100), dt, scale_pga_g=0.3))
    assert "NaN" in message(lambda: rockwatch.simulate(np.array([0.0, float("nan"), 0.0]), dt)) or \
        "finite" in message(lambda: rockwatch.simulate(np.array([0.0, float("nan"), 0.0]), dt))
    with pytest.raises(TypeError):
        rockwatch.simulate(a, dt, r=True)
    with pytest.raises(TypeError):
        rockwatch.Wall(thickness=0.1)
    with pytest.raises(TypeError):
        rockwatch.simulate(a, dt, wall="paper")
    assert "periods" in message(lambda: rockwatch.response_spectrum(a, dt, "4:0.02:10"))
    assert "does not identify" in message(lambda: rockwatch.identify(str(_still_wall_sensors(tmp_path))))


def _still_wall_sensors(tmp_path):
    path = tmp_path / "still.csv"
    path.write_text("t_s,x_mid_m\n" + "".join(f"{k * 0.01},0\n" for k in range(300)))
    return path


def test_the_engine_runs_without_the_gil():
    # A spinner thread stamps the time (perf_counter, at most once per 0.5 ms) while the main thread is inside one long
    # call; stamps from the middle of the call, away from its ends by more than the interpreter's switch interval,
    # can only come from a spinner that ran DURING the call: none when the extension holds the GIL (issue 42: counting
    # the spinner's iterations between two reads around the call also counted those before and after it).
    rec = rockwatch.read_record(ELC)
    stamps = []
    stop = threading.Event()
    started = threading.Event()

    def spin():
        last = 0.0
        started.set()
        while not stop.is_set():
            now = time.perf_counter()
            if now - last >= 0.0005:
                stamps.append(now)
                last = now

    t = threading.Thread(target=spin)
    t.start()
    started.wait()
    try:
        t0 = time.perf_counter()
        # A spectrum of 1000 periods of the record 20 times over: ~0.5 s in the engine (one pass of 100 periods: 2.5 ms).
        rockwatch.response_spectrum(np.tile(rec.accel_mps2, 20), rec.dt_s, "0.02:4:1000")
        t1 = time.perf_counter()
    finally:
        stop.set()
        t.join()
    margin = 4 * sys.getswitchinterval() + 0.01
    middle = t1 - t0 - 2 * margin
    assert middle >= 0.1, f"the call took {t1 - t0:.3f} s: too short to tell"
    inside = sum(1 for s in stamps if t0 + margin < s < t1 - margin)
    # Running freely the spinner stamps ~2 per ms; a tenth of that on a loaded machine is plenty.
    assert inside >= 0.2 * middle / 0.001, (
        f"the spinner stamped {inside} times in the middle {middle:.3f} s of the call: the extension held the GIL")
