# Allowable PGA versus the instability factor lambda, one curve per slenderness h/b (the design paper's Figure 3).
# Embedded in the rockwatch binary and run by `rockwatch static --sweep`:
#   static_sweep.py CSV PNG TITLE [LAMBDA LABEL]...
# CSV: the columns rockwatch writes (h_over_b, lambda, allowable_pga_g, ...). Each LAMBDA LABEL pair draws a
# vertical marker (the codes' lambda values).
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt


def main(argv):
    if len(argv) < 4 or (len(argv) - 4) % 2 != 0:
        sys.exit("usage: static_sweep.py CSV PNG TITLE [LAMBDA LABEL]...")
    csv_path, png_path, title = argv[1], argv[2], argv[3]
    markers = [(float(argv[i]), argv[i + 1]) for i in range(4, len(argv), 2)]

    curves = {}
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            curves.setdefault(float(row["h_over_b"]), []).append(
                (float(row["lambda"]), float(row["allowable_pga_g"])))
    if not curves:
        sys.exit("no rows in " + csv_path)

    fig, ax = plt.subplots(figsize=(8, 5.5))
    for slenderness in sorted(curves):
        points = sorted(curves[slenderness])
        ax.plot([p[0] for p in points], [p[1] for p in points], linewidth=1.6, label="h/b = %g" % slenderness)
    for lam, label in markers:
        ax.axvline(lam, color="0.35", linestyle="--", linewidth=1.0)
        ax.annotate("%s\n\u03bb = %g" % (label, lam), xy=(lam, 1.0), xycoords=("data", "axes fraction"),
                    xytext=(4, -4), textcoords="offset points", va="top", fontsize=9, color="0.25")
    ax.set_xlabel("instability factor \u03bb = x_eq,max / X  [-]")
    ax.set_ylabel("allowable PGA  [g]")
    ax.set_xlim(min(p[0] for c in curves.values() for p in c), max(p[0] for c in curves.values() for p in c))
    ax.set_ylim(bottom=0.0)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", linewidth=0.4, alpha=0.6)
    ax.legend(fontsize=9)
    fig.tight_layout()
    fig.savefig(png_path, dpi=150)
    plt.close(fig)


if __name__ == "__main__":
    main(sys.argv)
