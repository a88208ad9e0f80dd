#!/usr/bin/python3
"""A noisier transducer on kept truths, in seconds: copies a truth set (tests/truth/README.md layout) to DIR with
each sensors.csv's x_mid_m given more Gaussian noise, so that its standard deviation becomes --noise-x-m (the kept
readings already carry the truth.json's `sensor.noise_x_m`: the added noise has sqrt(S^2 - s0^2), a sum of
independent Gaussians being Gaussian), and truth.json's `sensor.noise_x_m` set to S. The same in distribution as
`make_truths.py --sensor noise_x_m=S` (which recomputes every truth: 15 min), used by the ctest
`model_error_noisy_transducer` (SPEC §11 "The transducer's noise").

    /usr/bin/python3 tests/truth/noisier_sensors.py --truths tests/data/truths --noise-x-m 0.002 --out DIR [--seed N]
"""
import argparse
import json
import os
import random
import shutil
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--truths", required=True)
    ap.add_argument("--noise-x-m", type=float, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if os.path.abspath(a.out) == os.path.abspath(a.truths):
        sys.exit("noisier_sensors: --out must not be --truths")
    if not (a.noise_x_m > 0 and a.noise_x_m < 1):
        sys.exit("noisier_sensors: --noise-x-m %r: expected a standard deviation in (0, 1) m" % a.noise_x_m)
    rng = random.Random(a.seed)
    cases = 0
    for fam in sorted(os.listdir(a.truths)):
        fam_dir = os.path.join(a.truths, fam)
        if not os.path.isdir(fam_dir):
            continue
        for case in sorted(os.listdir(fam_dir)):
            src = os.path.join(fam_dir, case)
            tj = os.path.join(src, "truth.json")
            if not os.path.isfile(tj):
                continue
            dst = os.path.join(a.out, fam, case)
            os.makedirs(dst, exist_ok=True)
            with open(tj) as f:
                truth = json.load(f)
            s0 = float(truth.get("sensor", {}).get("noise_x_m", 0.0))
            if not a.noise_x_m >= s0:
                sys.exit("noisier_sensors: %s: sensor.noise_x_m %g is above --noise-x-m %g (noise can only be added)"
                         % (tj, s0, a.noise_x_m))
            extra = (a.noise_x_m ** 2 - s0 ** 2) ** 0.5
            for name in os.listdir(src):
                if name not in ("sensors.csv", "truth.json"):
                    shutil.copy(os.path.join(src, name), os.path.join(dst, name))
            with open(os.path.join(src, "sensors.csv")) as f:
                lines = f.read().splitlines()
            head = lines[0].split(",")
            if "x_mid_m" not in head:
                sys.exit("noisier_sensors: %s: no x_mid_m column" % os.path.join(src, "sensors.csv"))
            ix = head.index("x_mid_m")
            out = [lines[0]]
            for n, line in enumerate(lines[1:], start=2):
                cols = line.split(",")
                if cols[ix] != "":
                    try:
                        cols[ix] = "%.7g" % (float(cols[ix]) + rng.gauss(0.0, extra))
                    except ValueError:
                        sys.exit("noisier_sensors: %s line %d: x_mid_m '%s' is not a number"
                                 % (os.path.join(src, "sensors.csv"), n, cols[ix]))
                out.append(",".join(cols))
            with open(os.path.join(dst, "sensors.csv"), "w") as f:
                f.write("\n".join(out) + "\n")
            truth.setdefault("sensor", {})["noise_x_m"] = a.noise_x_m
            truth["sensor"]["derived_by"] = "tests/truth/noisier_sensors.py --seed %d" % a.seed
            with open(os.path.join(dst, "truth.json"), "w") as f:
                json.dump(truth, f, indent=1)
                f.write("\n")
            cases += 1
    if cases == 0:
        sys.exit("noisier_sensors: %s: no truth.json found (expected FAMILY/CASE/truth.json)" % a.truths)
    print("noisier_sensors: %d cases, x noise %g m, written to %s" % (cases, a.noise_x_m, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
