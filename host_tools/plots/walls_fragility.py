# The fragility medians of a wall portfolio (`rockwatch study --walls FILE --plots`): per case, the lognormal median
# PGA of collapse of every wall against its slenderness h/b = (h1 + h2)/b, walls with overburden (Fp > 0) marked apart.
# Embedded in the rockwatch binary:
#   walls_fragility.py SUMMARY_JSON PNG TITLE
import json
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt

MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def main():
    summary_path, png, title = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(summary_path, encoding="utf-8") as f:
        summary = json.load(f)
    walls = summary["walls"]
    fig, ax = plt.subplots(figsize=(8, 5))
    n_cases = len(walls[0]["cases"]) if walls else 0
    for c in range(n_cases):
        case_title = walls[0]["cases"][c]["title"]
        for loaded, fill in ((False, True), (True, False)):
            xs, ys = [], []
            for wall in walls:
                median = wall["cases"][c]["lognormal"]["median_g"]
                if median is None or (wall["wall"]["fp_npm"] > 0) != loaded:
                    continue
                xs.append(wall["h_over_b"])
                ys.append(median)
            if not xs:
                continue
            colour = "C%d" % c
            ax.scatter(xs, ys, marker=MARKERS[c % len(MARKERS)], s=28,
                       facecolors=colour if fill else "none", edgecolors=colour,
                       label=case_title + (" (Fp > 0)" if loaded else ""))
    ax.set_xlabel("slenderness h/b = (h1 + h2) / b [-]")
    ax.set_ylabel("lognormal median PGA of collapse [g]")
    ax.set_title("Fragility medians of the portfolio: " + title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
