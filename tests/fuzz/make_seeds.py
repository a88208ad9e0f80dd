#!/usr/bin/env python3
"""Writes the seed corpora of the record, manifest and configuration fuzz targets (tests/fuzz/corpus/<target>/)
from the repository's test files, cut down to a few hundred bytes to a few kB, plus small hand-made variants of
each format (the ones the reader tests write to temporary files). Deterministic; the provenance of every file is
in tests/fuzz/corpus/README.md. The monitor loop's seeds come from make_monitor_seeds.cpp instead.

    python3 tests/fuzz/make_seeds.py            # from the repository root
"""
import json
import re
import pathlib
import shutil
import struct

ROOT = pathlib.Path(__file__).resolve().parents[2]
RECORDS = ROOT / "tests/data/records"
SUITE = ROOT / "sim/suites/npr9998-2015"
CORPUS = ROOT / "tests/fuzz/corpus"
GENERATED = ["record_at2", "record_plain", "record_esm", "record_itaca", "record_miniseed", "record_suite",
             "read_record", "suite_manifest", "monitor_config", "monitor_args", "wall_sensor_csv"]


def put(target, name, data):
    path = CORPUS / target / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data if isinstance(data, bytes) else data.encode())


def lines_of(path):
    return path.read_bytes().splitlines(keepends=True)


# ---- PEER AT2 ----------------------------------------------------------------------------------------------------

def at2_cut(name, data_lines, npts=None):
    """The 4 header lines and the first data_lines lines of values (5 per line); NPTS set to npts when given."""
    lines = lines_of(RECORDS / name)
    head, data = lines[:4], lines[4:4 + data_lines]
    if npts is not None:
        head[3] = re.sub(rb"(NPTS\s*=\s*)\d+", lambda m: m.group(1) + str(npts).encode(), head[3], count=1)
    return b"".join(head + data)


def write_at2():
    put("record_at2", "elc180_20lines.AT2", at2_cut("RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 20, npts=100))
    put("record_at2", "elc_up_npts_mismatch.AT2", at2_cut("RSN6_IMPVALL.I_I-ELC-UP.AT2", 12))
    put("record_at2", "imperial1979_crlf.AT2", at2_cut("RSN175_IMPVALL.H_H-E12140.AT2", 16, npts=80))
    put("record_at2", "bevagna_spaced_header.AT2", at2_cut("RSN4346_UBMARCHE.P_A-BEV000.AT2", 10, npts=50))
    put("record_at2", "northridge_poles_crlf.AT2", at2_cut("RSN960_NORTHR_LOS270.AT2", 10, npts=49))
    head = b"".join(lines_of(RECORDS / "RSN6_IMPVALL.I_I-ELC270-hor2.AT2")[:3])
    values = "   .1000000E-02  -.2000000E-02   .3000000E-02  -.4000000E-02   .5000000E-02\n"
    put("record_at2", "old_npts_dt_variant.AT2", head + b"   5    0.0100    NPTS, DT\n" + values.encode())
    put("record_at2", "truncated_mid_number.AT2",
        head + b"NPTS=      6, DT=   .0100 SEC,\n" + values.encode() + b"   .60000")


# ---- plain text / CSV --------------------------------------------------------------------------------------------

def write_plain():
    knmi = lines_of(RECORDS / "NL.BGAR.20200502_Zijldijk_ML2.5.acc_ms2.txt")
    put("record_plain", "knmi_4_columns.txt", b"".join(knmi[:6] + knmi[6:26]))
    rows = [line.split()[:2] for line in knmi[6:36]]
    two = "# units: m/s2\n" + "".join(f"{t.decode()} {a.decode()}\n" for t, a in rows)
    put("record_plain", "knmi_2_columns_units_comment.txt", two)
    three = "t [s], ah [cm/s^2], av [cm/s^2]\n" + "".join(
        f"{t.decode()}, {float(a) * 100:.6e}, {float(line.split()[3]) * 100:.6e}\n"
        for (t, a), line in zip(rows, knmi[6:36]))
    put("record_plain", "three_columns_header_units.csv", three)
    put("record_plain", "csv_bom_crlf_g.csv", "\ufefftime_s;accel_g\r\n0,0\r\n0,01;0,5\r\n")
    put("record_plain", "csv_accel_g.csv", "time_s,accel_g\n0.00,0.0\n0.01,0.05\n0.02,-0.10\n0.03,0.02,\n")
    put("record_plain", "one_column.txt", "# one value per line; pass --dt\n# unit = g\n0.0\n0.1\n-0.2\n+3e-2\n")
    put("record_plain", "uneven_time.txt", "# units: gal\n0.00 1\n0.01 2\n0.025 3\n")


# ---- ESM ASCII ---------------------------------------------------------------------------------------------------

ESM_HEADER = [
    ("EVENT_NAME", "TEST EVENT"), ("EVENT_ID", "TEST-20190728_0000001"), ("EVENT_DATE_YYYYMMDD", "20190728"),
    ("EVENT_TIME_HHMMSS", "160908"), ("EVENT_LATITUDE_DEGREE", "45.0000"), ("EVENT_LONGITUDE_DEGREE", "10.0000"),
    ("EVENT_DEPTH_KM", "5.0"), ("HYPOCENTER_REFERENCE", "TEST"), ("MAGNITUDE_W", ""), ("MAGNITUDE_W_REFERENCE", ""),
    ("MAGNITUDE_L", "4.0"), ("MAGNITUDE_L_REFERENCE", "TEST"), ("FOCAL_MECHANISM", ""), ("NETWORK", "XX"),
    ("STATION_CODE", "TST1"), ("STATION_NAME", "Test site, Nowhere"), ("STATION_LATITUDE_DEGREE", "45.100000"),
    ("STATION_LONGITUDE_DEGREE", "10.100000"), ("STATION_ELEVATION_M", "10"), ("LOCATION", ""),
    ("SENSOR_DEPTH_M", "0.0"), ("VS30_M/S", ""), ("SITE_CLASSIFICATION_EC8", ""), ("MORPHOLOGIC_CLASSIFICATION", ""),
    ("EPICENTRAL_DISTANCE_KM", "13.6"), ("EARTHQUAKE_BACKAZIMUTH_DEGREE", "210.0"),
    ("DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS", "20190728_160919.870"),
    ("DATE_TIME_FIRST_SAMPLE_PRECISION", "milliseconds"), ("SAMPLING_INTERVAL_S", "0.010000"), ("NDATA", "4"),
    ("DURATION_S", "0.040"), ("STREAM", "HNE"), ("UNITS", "cm/s^2"),
    ("INSTRUMENT", "sensor = TEST_ACCELEROMETER [Unknown] | digitizer = Unknown [Unknown]"),
    ("INSTRUMENT_ANALOG/DIGITAL", "D"), ("INSTRUMENTAL_FREQUENCY_HZ", ""), ("INSTRUMENTAL_DAMPING", ""),
    ("FULL_SCALE_G", ""), ("N_BIT_DIGITAL_CONVERTER", ""), ("PGA_CM/S^2", "100.000000"), ("TIME_PGA_S", "0.030000"),
    ("BASELINE_CORRECTION", "BASELINE REMOVED"), ("FILTER_TYPE", "BUTTERWORTH"), ("FILTER_ORDER", "2"),
    ("LOW_CUT_FREQUENCY_HZ", "0.100"), ("HIGH_CUT_FREQUENCY_HZ", "30.000"), ("LATE/NORMAL_TRIGGERED", "NT"),
    ("DATABASE_VERSION", "DYNA 1.0"), ("HEADER_FORMAT", "DYNA 1.2"), ("DATA_TYPE", "ACCELERATION"),
    ("PROCESSING", "manual"), ("DATA_TIMESTAMP_YYYYMMDD_HHMMSS", "20190730_115604.782"), ("DATA_LICENSE", ""),
    ("DATA_CITATION", ""), ("DATA_CREATOR", ""), ("ORIGINAL_DATA_MEDIATOR_CITATION", ""),
    ("ORIGINAL_DATA_MEDIATOR", ""), ("ORIGINAL_DATA_CREATOR_CITATION", ""), ("ORIGINAL_DATA_CREATOR", ""),
    ("USER1", "hand-made test file: a value with a colon: ok"), ("USER2", ""), ("USER3", ""), ("USER4", ""),
    ("USER5", "")]


def esm(changes=None, drop=(), values="0.000000\n1.500000\n-2.250000\n100.000000\n"):
    changes = changes or {}
    header = [(k, changes.get(k, v)) for k, v in ESM_HEADER if k not in drop]
    return "".join(f"{k}: {v}\n" for k, v in header) + values


def write_esm():
    put("record_esm", "esm_cmps2.ASC", esm())
    put("record_esm", "esm_mps2_no_time.ASC", esm({"UNITS": "m/s^2"}, drop=("DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS",)))
    crlf = esm({"UNITS": "g", "NDATA": "3"}, values="0.1\n-0.2\n0.3\n").replace("\n", "\r\n")
    put("record_esm", "esm_g_crlf.ASC", crlf)
    put("record_esm", "esm_minimal.ASC", "SAMPLING_INTERVAL_S: 0.005\nNDATA: 2\nUNITS: m/s^2\n1.0\n-1.0\n")


# ---- ITACA .cor.acc ----------------------------------------------------------------------------------------------

def write_itaca():
    lines = lines_of(RECORDS / "16833_H1.cor.acc")
    head = [line.replace(b"59220", b"40") for line in lines[:10]]
    put("record_itaca", "laquila_40_values.cor.acc", b"".join(head + lines[10:18]))
    head38 = [line.replace(b"59220", b"38") for line in lines[:10]]
    put("record_itaca", "laquila_short_last_line.cor.acc", b"".join(head38 + lines[10:17]) + lines[17][:42] + b"\n")
    put("record_itaca", "itaca_minimal_g.cor.acc",
        "Time Increment (s) : 0.01\nNumber of Data : 3\nAcceleration time series in g\n"
        " 1.0000000E-02-2.0000000E-02 3.0000000E-02\n")


# ---- miniSEED ----------------------------------------------------------------------------------------------------

def mseed_record(encoding, samples, channel=b"HGE", seq=1, second=14, fract=0, rate=200, reclen_exp=9):
    """A 512-byte miniSEED 2 data record with blockette 1000, big-endian, uncompressed samples."""
    if encoding == 4:
        data = b"".join(struct.pack(">f", s) for s in samples)
    elif encoding == 5:
        data = b"".join(struct.pack(">d", s) for s in samples)
    elif encoding == 3:
        data = b"".join(struct.pack(">i", int(s)) for s in samples)
    else:  # 0: ASCII text
        data = samples
    count = len(samples)
    header = b"%06dD " % seq + b"BGAR " + b"  " + channel + b"NL"
    header += struct.pack(">HHBBBBH", 2020, 123, 3, 11, second, 0, fract)
    header += struct.pack(">HhhBBBBiHH", count, rate, 1, 0, 0, 0, 1, 0, 64, 48)
    blockette = struct.pack(">HHBBBB", 1000, 0, encoding, 1, reclen_exp, 0) + b"\0" * 8
    record = header + blockette + data
    return record + b"\0" * ((1 << reclen_exp) - len(record))


def write_miniseed():
    raw = (RECORDS / "NL.BGAR.mseed").read_bytes()
    rec = [raw[i:i + 512] for i in range(0, len(raw), 512)]
    put("record_miniseed", "bgar_hge_2_records.mseed", rec[0] + rec[1])
    put("record_miniseed", "bgar_hge_1_record.mseed", rec[0])
    put("record_miniseed", "bgar_3_channels.mseed", rec[0] + rec[249] + rec[502])
    put("record_miniseed", "bgar_hge_gap.mseed", rec[0] + rec[2])
    put("record_miniseed", "bgar_hge_padded.mseed", rec[0] + b"\0" * 512)
    put("record_miniseed", "bgar_truncated.mseed", rec[0][:300])
    ramp = [0.001 * k for k in range(100)]
    put("record_miniseed", "float32_hgz.mseed", mseed_record(4, ramp, channel=b"HGZ"))
    put("record_miniseed", "float64_2_records.mseed",
        mseed_record(5, ramp[:50], channel=b"HGZ") + mseed_record(5, ramp[50:], channel=b"HGZ", seq=2, fract=2500))
    put("record_miniseed", "int32_and_log.mseed",
        mseed_record(3, range(-50, 50)) + mseed_record(0, b"hand-made LOG record", channel=b"LOG", seq=2))


# ---- suite set files and manifest --------------------------------------------------------------------------------

def write_suite():
    lines = lines_of(SUITE / "set01.txt")
    put("record_suite", "set01_header_40_rows.txt", b"".join(lines[:13] + lines[13 + 600:13 + 640]))
    # The first file's rows do not start at t = 0 (an error path); here later rows are renumbered from t = 0.
    rows = []
    for k, line in enumerate(lines[13 + 800:13 + 820]):
        parts = line.split()
        rows.append(b"%.6f " % (k * 0.005) + b" ".join(parts[1:]) + b"\n")
    put("record_suite", "set01_renumbered_rows.txt", b"".join(lines[:13] + rows))
    minimal = ("# rockwatch-suite-record: 1\n# units: m/s2\n# dt_s: 0.01\n# columns: time_s x_mps2 y_mps2 z_mps2\n"
               "0.000000 1e-3 -2e-3 3e-3\n0.010000 0 0 0\n")
    put("record_suite", "suite_minimal.txt", minimal)

    manifest = json.loads((SUITE / "manifest.json").read_text())
    manifest["sets"] = manifest["sets"][:2]
    put("suite_manifest", "npr9998_2_sets.json", json.dumps(manifest, indent=1))
    put("suite_manifest", "minimal.json",
        '{"format": "rockwatch-suite-manifest", "version": 1, "sets": [{"set": 1, "file": "set01.txt"}, '
        '{"set": 3, "file": "sub/set03.txt"}]}')


def write_read_record():
    # A few of each format: content detection picks the reader. scripts/fuzz.sh adds the per-format corpora.
    for target, name in [("record_at2", "elc180_20lines.AT2"), ("record_plain", "three_columns_header_units.csv"),
                         ("record_esm", "esm_cmps2.ASC"), ("record_itaca", "laquila_40_values.cor.acc"),
                         ("record_miniseed", "bgar_hge_2_records.mseed"), ("record_suite", "suite_minimal.txt")]:
        put("read_record", name, (CORPUS / target / name).read_bytes())
    put("read_record", "at2_like_comment_line4.txt", "time_s,accel_g\n0,0\n0.01,0.1\n# NPTS and DT are not here\n")


# ---- rockwatch-monitor configuration and command line -----------------------------------------------------------

def write_monitor():
    configs = {
        "full.json": {"wall": {"b": 0.1, "h1": 1.75, "h2": 1.75, "rho": 1800, "fp": 0, "a": 0, "a_prime": 0,
                               "g": 9.81},
                      "r": "exp", "model": "linear", "kappa": 2, "alarm": {"lambda_w": 0.4, "hold_s": 1,
                                                                          "energy_margin": 1.5},
                      "sample_rate_hz": 200, "max_bridge_samples": 10, "sensor_range_mps2": 80, "late_limit_s": 0.05,
                      "channels": {"accel": "A", "accel_batch": "B", "wall_state": "S", "alarm": "L", "status": "T"},
                      "lcm_url": "udpm://239.255.76.67:7667?ttl=0"},
        "r_value_rate.json": {"r": 0.7, "sample_rate_hz": 1000, "wall": {"h1": 2.0}},
        "double_full.json": {"arith": "double", "model": "full", "r": "impulse"},
        "wall_invalid.json": {"wall": {"b": 0.5, "h1": 0.3}},
    }
    for name, value in configs.items():
        put("monitor_config", name, json.dumps(value))
    put("monitor_config", "duplicate_key.json", '{"kappa": 2, "alarm": {"hold_s": 1, "hold_s": 2}}')
    put("monitor_config", "empty_object.json", "{}")

    args = {
        "wall_rate.args": ["--h1", "1.5", "--h2", "1.5", "--r", "ana", "--rate", "100"],
        "config_override.args": ["--config", "x.json", "--kappa", "3", "--lambda-w", "0.5"],
        "offline.args": ["--offline-in", "in.lcmlog", "--offline-out", "out.lcmlog", "--print-config"],
        "help.args": ["--help"],
        "version.args": ["--version"],
        "arith_double.args": ["--arith", "double", "--model", "full", "--alarm-hold", "2", "--energy-margin", "2"],
        "wall_paper_b.args": ["--wall", "paper", "--b", "0.2", "--fp", "100", "--a", "0.5", "--g", "9.8"],
        "lcm_url.args": ["--lcm-url=udpm://239.255.76.67:7667?ttl=0", "--log", "monitor.lcmlog"],
    }
    for name, argv in args.items():
        put("monitor_args", name, "\0".join(argv))


# ---- wall-sensor CSV (--wall-sensors) ---------------------------------------------------------------------------

def write_wall_sensor_csv():
    rows = "".join(f"{k * 0.005:.3f},{0.002 * (k % 7 - 3):.4f},{0.05 * (k % 5 - 2):.3f}\n" for k in range(20))
    put("wall_sensor_csv", "x_and_a_20_rows.csv", "t_s,x_mid_m,a_mid_mps2\n" + rows)
    put("wall_sensor_csv", "x_only_absent_fields.csv", "# logger export\nt_s,x_mid_m\n0,0.001\n0.01,\n0.02,-2e-3\n")
    put("wall_sensor_csv", "reordered_crlf_bom.csv",
        "\ufeffa_mid_mps2, t_s ,X_MID_M\r\n0.5,-0.1,0.25\r\n,0.2,\r\n+1e-3,0.3,-0\r\n".encode("utf-8"))
    put("wall_sensor_csv", "times_not_increasing.csv", "t_s,x_mid_m\n0,0\n0.01,0\n0.005,0\n")


def main():
    for target in GENERATED:
        shutil.rmtree(CORPUS / target, ignore_errors=True)
    write_at2()
    write_plain()
    write_esm()
    write_itaca()
    write_miniseed()
    write_suite()
    write_read_record()
    write_monitor()
    write_wall_sensor_csv()


if __name__ == "__main__":
    main()
