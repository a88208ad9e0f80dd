#!/usr/bin/env python3
"""ctest m4_monitor_config: every setting rockwatch-monitor was told reaches the monitor image's configuration.

scripts/m4-monitor-run.py turns `rockwatch-monitor --print-config` into the image's configuration file (key/value
pairs, firmware::EngineInputKey numbers). Until issue 40's follow-up it passed only the keys its table knew, so the
image ran the defaults of the others (model doubt, the model-form σ, the look-ahead horizon, the capacity minimums)
while the host ran what it was told, and both published the same configuration digest. This check, without QEMU:
  1. a configuration setting every alarm and observer key the monitor accepts, each to a value other than its
     default, printed by the real rockwatch-monitor, gives a file holding every one of them, value for value;
  2. the script's key numbers are the C++ enum's (engine_input_format.hpp), name for name;
  3. a setting the table does not map fails the script (exit 2, naming it) instead of being dropped.

  m4_monitor_config_check.py ROCKWATCH_MONITOR WORK_DIR
"""
import importlib.util, json, os, re, struct, subprocess, sys

root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def load_runner():
    spec = importlib.util.spec_from_file_location("m4_monitor_run", os.path.join(root, "scripts", "m4-monitor-run.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def read_pairs(path):
    data = open(path, "rb").read()
    assert data[:8] == b"RWMONCF1", "bad magic"
    (n,) = struct.unpack_from("<Q", data, 8)
    pairs, off = {}, 16
    for _ in range(n):
        (k,) = struct.unpack_from("<Q", data, off)
        (v,) = struct.unpack_from("<d", data, off + 8)
        pairs[k] = v
        off += 16
    return pairs


def enum_keys():
    text = open(os.path.join(root, "firmware", "include", "rockwatch", "firmware", "engine_input_format.hpp")).read()
    body = text[text.index("enum class EngineInputKey"):]
    body = body[:body.index("};")]
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^\s*(\w+)\s*=\s*(\d+),", body, re.M)}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: m4_monitor_config_check.py ROCKWATCH_MONITOR WORK_DIR")
    monitor, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    run = load_runner()

    # 1. Every alarm and observer key the monitor accepts, off its default.
    alarm = {"lambda_w": 0.35, "hold_s": 0.75, "energy_margin": 1.75, "imminent_horizon_s": 0.17, "energy_min_x": 0.4}
    observer = {"enabled": True, "x_noise_m": 0.0007, "a_noise_mps2": 0.07, "process_accel_mps2": 0.3,
                "gate_chi2": 20.0, "dropout_s": 0.3, "max_age_s": 0.06, "capacity_sigmas": 0.5,
                "accel_inform_peak_noises": 5.0, "doubt_nis": 8.0, "quiet_motion_spread_noises": 30.0,
                "model_form_sigma": 0.05, "doubt_model_form_sigma": 0.3, "capacity_min_x": 0.1,
                "doubt_capacity_min_x": 0.2, "capacity_correlation": 0.5, "noise_learn_readings": 100}
    cfg = os.path.join(work, "all_keys.json")
    json.dump({"alarm": alarm, "observer": observer}, open(cfg, "w"))
    printed = subprocess.run([monitor, "--print-config", "--config", cfg, "--arith", "fixed", "--model", "linear"],
                             check=True, capture_output=True, text=True).stdout
    settings = json.loads(printed)["settings"]
    for group, values in (("alarm", alarm), ("observer", observer)):
        for k, v in values.items():
            if k != "enabled":
                check(settings[group].get(k) == v, "--print-config does not show %s.%s = %r" % (group, k, v))
    path = os.path.join(work, "monitor.cfg")
    run.write_config(json.loads(printed), "239.255.76.67", 7667, path)
    pairs = read_pairs(path)
    for path_keys, key in run.ENGINE_KEYS.items():
        if len(path_keys) == 2 and path_keys[0] in ("alarm", "observer"):
            group, name = path_keys
            want = (alarm if group == "alarm" else observer)[name]
            check(pairs.get(key) == want, "key %d (%s.%s) is %r in the image's file, told %r" %
                  (key, group, name, pairs.get(key), want))
    told = {("alarm", k) for k in alarm} | {("observer", k) for k in observer if k != "enabled"}
    check(told <= set(run.ENGINE_KEYS), "not mapped: %s" % sorted(told - set(run.ENGINE_KEYS)))

    # 2. The script's numbers are the enum's (the monitor's key names differ from the engine's field names in places).
    keys = enum_keys()
    aliases = {("observer", "capacity_sigmas"): "observer_alarm_capacity_sigmas",
               ("observer", "capacity_min_x"): "observer_capacity_min_x_fraction",
               ("observer", "doubt_capacity_min_x"): "observer_doubt_capacity_min_x_fraction",
               ("alarm", "lambda_w"): "alarm_lambda_warning", ("alarm", "hold_s"): "alarm_hold_s",
               ("alarm", "energy_margin"): "alarm_energy_margin", ("alarm", "imminent_horizon_s"): "alarm_imminent_horizon_s",
               ("wall", "rho"): "wall_rho_kgpm3", ("wall", "fp"): "wall_fp_npm", ("wall", "g"): "wall_g_mps2",
               ("wall", "b"): "wall_b_m", ("wall", "h1"): "wall_h1_m", ("wall", "h2"): "wall_h2_m",
               ("r_energy_ratio",): "r_energy"}
    for path_keys, key in run.ENGINE_KEYS.items():
        name = aliases.get(path_keys, "_".join(path_keys))
        check(keys.get(name) == key, "script key %s = %d, engine_input_format.hpp %s = %r" %
              (".".join(path_keys), key, name, keys.get(name)))

    # 3. A setting without a key fails the run, naming it.
    unknown = json.loads(printed)
    unknown["settings"]["observer"]["a_future_setting"] = 1.0
    try:
        run.write_config(unknown, "239.255.76.67", 7667, os.path.join(work, "unknown.cfg"))
        check(False, "an unmapped observer setting was written without a word")
    except SystemExit as e:
        check(e.code == 2, "an unmapped setting exits %r, not 2" % e.code)

    for f in failures:
        print("FAILED: " + f)
    if failures:
        return 1
    print("m4_monitor_config: %d alarm and observer settings reach the image's file; %d script keys match the enum"
          % (len(told), len(run.ENGINE_KEYS)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
