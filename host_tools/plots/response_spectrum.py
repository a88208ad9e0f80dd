# Elastic response spectrum Sa(T) of a record on a log period axis, with the design (target) spectrum when given.
# Embedded in the rockwatch binary and run by `rockwatch spectrum --plot`:
#   response_spectrum.py CSV PNG TITLE G [TARGET_LABEL]
# CSV: the columns rockwatch writes (period_s, sa_mps2 and, with a target, target_sa_mps2). G [m/s2] converts
# accelerations to units of g for the axis; TARGET_LABEL names the target curve in the legend.
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter


def main(argv):
    if len(argv) not in (5, 6):
        sys.exit("usage: response_spectrum.py CSV PNG TITLE G [TARGET_LABEL]")
    csv_path, png_path, title, g = argv[1], argv[2], argv[3], float(argv[4])
    target_label = argv[5] if len(argv) == 6 else None

    periods, sa, target = [], [], []
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            periods.append(float(row["period_s"]))
            sa.append(float(row["sa_mps2"]) / g)
            if target_label is not None:
                target.append(float(row["target_sa_mps2"]) / g)
    if not periods:
        sys.exit("no rows in " + csv_path)

    fig, ax = plt.subplots(figsize=(8, 5.5))
    ax.plot(periods, sa, color="C0", linewidth=1.8, label="record (PSA)")
    if target_label is not None:
        ax.plot(periods, target, color="C3", linestyle="--", linewidth=1.6, label=target_label)
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
    ax.set_ylabel("spectral acceleration Sa  [g]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", linewidth=0.4, alpha=0.6)
    ax.legend(fontsize=9)
    fig.tight_layout()
    fig.savefig(png_path, dpi=150)
    plt.close(fig)


if __name__ == "__main__":
    main(sys.argv)
