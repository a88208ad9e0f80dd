# Measured and fitted displacement x_mid(t) of an identification (`rockwatch identify --plot`), with the residual.
#   identify_fit.py CSV PNG TITLE
# CSV: t_s, measured_m, fitted_m (the transducer's samples used and the identified wall's response plus offset).
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt


def main(argv):
    if len(argv) != 4:
        sys.exit("usage: identify_fit.py CSV PNG TITLE")
    csv_path, png_path, title = argv[1], argv[2], argv[3]
    t, measured, fitted = [], [], []
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            t.append(float(row["t_s"]))
            measured.append(1000.0 * float(row["measured_m"]))
            fitted.append(1000.0 * float(row["fitted_m"]))
    if not t:
        sys.exit("no rows in " + csv_path)
    fig, (ax, ax_res) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(t, measured, ".", color="0.55", markersize=2.5, label="measured x_mid")
    ax.plot(t, fitted, color="C3", linewidth=1.3, label="identified wall (+ offset)")
    ax.set_ylabel("x_mid [mm]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right")
    ax.set_title(title, fontsize=10)
    ax_res.plot(t, [m - f for m, f in zip(measured, fitted)], color="C0", linewidth=0.8)
    ax_res.set_ylabel("residual [mm]")
    ax_res.set_xlabel("t [s]")
    ax_res.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    main(sys.argv)
