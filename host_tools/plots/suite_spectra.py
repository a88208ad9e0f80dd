# Response spectra of a generated ground-motion suite against its targets, like the design paper's Figures 4
# (horizontal) and 5 (vertical): every record thin grey, the suite mean thick, the target and the acceptance limits
# dashed, the acceptance band shaded, on a log period axis.
# Embedded in the rockwatch binary and run by `rockwatch generate`:
#   suite_spectra.py CSV OUT_DIR TITLE G BAND_FROM BAND_TO ACCEPT_MIN ACCEPT_MAX H_TARGET_LABEL V_TARGET_LABEL
# CSV: period_s, target_h_mps2, target_v_mps2, then one column per record named setNN_C (C = X, Y or Z). Writes
# OUT_DIR/spectra_horizontal.png (X and Y), spectra_vertical.png (Z) and spectra_X.png, spectra_Y.png,
# spectra_Z.png. G [m/s2] converts accelerations to units of g for the axis.
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

# (file, components, target column, subtitle)
FIGURES = [
    ("spectra_horizontal.png", "XY", "target_h_mps2", "horizontal components (X and Y)"),
    ("spectra_vertical.png", "Z", "target_v_mps2", "vertical components (Z)"),
    ("spectra_X.png", "X", "target_h_mps2", "component X"),
    ("spectra_Y.png", "Y", "target_h_mps2", "component Y"),
    ("spectra_Z.png", "Z", "target_v_mps2", "component Z (vertical)"),
]


def read_columns(csv_path, g):
    columns = {}
    with open(csv_path, newline="") as f:
        reader = csv.DictReader(f)
        for row in reader:
            for name, value in row.items():
                columns.setdefault(name, []).append(float(value) / (1.0 if name == "period_s" else g))
    if not columns.get("period_s"):
        sys.exit("no rows in " + csv_path)
    return columns


def draw(columns, png_path, title, components, target_column, target_label, band, limits):
    periods = columns["period_s"]
    records = [name for name in columns if "_" in name and name.rsplit("_", 1)[1] in components
               and name.startswith("set")]
    if not records:
        sys.exit("no record columns for components " + components)
    target = columns[target_column]

    fig, ax = plt.subplots(figsize=(8, 5.5))
    ax.axvspan(band[0], band[1], color="C0", alpha=0.07, linewidth=0,
               label="acceptance band %g-%g s" % (band[0], band[1]))
    for i, name in enumerate(records):
        ax.plot(periods, columns[name], color="0.6", linewidth=0.6, label="records (%d)" % len(records) if i == 0 else None)
    mean = [sum(columns[name][k] for name in records) / len(records) for k in range(len(periods))]
    ax.plot(periods, mean, color="C0", linewidth=2.4, label="suite mean")
    ax.plot(periods, target, color="C3", linewidth=1.8, label=target_label)
    for factor in limits:
        ax.plot(periods, [factor * t for t in target], color="C3", linestyle="--", linewidth=1.0,
                label="%g / %g x target" % limits if factor == limits[0] else None)
    ax.set_xscale("log")
    ax.set_xlim(periods[0], periods[-1])
    # Periods read as plain numbers (0.1, 0.2, 0.5, 1, 2 s), not powers of ten.
    ticks = [m * 10.0 ** e for e in range(-4, 4) for m in (1, 2, 5) if periods[0] <= m * 10.0 ** e <= periods[-1]]
    if len(ticks) >= 2:
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: "%g" % x))
        ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("period T  [s]")
    ax.set_ylabel("pseudo-spectral acceleration  [g]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", linewidth=0.4, alpha=0.6)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png_path, dpi=150)
    plt.close(fig)


def main(argv):
    if len(argv) != 11:
        sys.exit("usage: suite_spectra.py CSV OUT_DIR TITLE G BAND_FROM BAND_TO ACCEPT_MIN ACCEPT_MAX "
                 "H_TARGET_LABEL V_TARGET_LABEL")
    csv_path, out_dir, title, g = argv[1], argv[2], argv[3], float(argv[4])
    band = (float(argv[5]), float(argv[6]))
    limits = (float(argv[7]), float(argv[8]))
    labels = {"target_h_mps2": argv[9], "target_v_mps2": argv[10]}
    columns = read_columns(csv_path, g)
    for file_name, components, target_column, subtitle in FIGURES:
        draw(columns, os.path.join(out_dir, file_name), title + "\n" + subtitle, components, target_column,
             labels[target_column], band, limits)


if __name__ == "__main__":
    main(sys.argv)
