# The design paper's Figures 6-8 for one `rockwatch study`, per case: the collapse map (record x PGA level:
# collapsed or survived; Figure 6) and the maximum displacement versus PGA with the survival rate per level and the
# fitted normal survival curve (Figures 7-8).
# Embedded in the rockwatch binary and run by `rockwatch study --plots`:
#   study_figures.py RUNS_CSV SUMMARY_JSON [CASE VERTICAL R_LABEL FIG6_PNG FIG7_PNG TITLE]...
# RUNS_CSV and SUMMARY_JSON are the study's own files; CASE is the index of the case in summary.json's "cases",
# VERTICAL true|false and R_LABEL select its rows of runs.csv (columns vertical and r).
import csv
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

SURVIVED, COLLAPSED, REFUSED, MISSING = 0, 1, 2, 3
COLOURS = ["#9ecf8b", "#c0392b", "#8c8c8c", "#ffffff"]


def normal_cdf(x):
    return 0.5 * math.erfc(-x / math.sqrt(2.0))


def record_label(record):
    return record["name"] + (" " + record["component"] if record["component"] else "")


def collapse_map(rows, records, levels, png, title):
    index = {(r["name"], r["component"]): i for i, r in enumerate(records)}
    level_index = {level: j for j, level in enumerate(levels)}
    grid = [[MISSING] * len(levels) for _ in records]
    for row in rows:
        i = index[(row["record"], row["component"])]
        j = level_index[float(row["pga_g"])]
        if row["error"]:
            grid[i][j] = REFUSED
        else:
            grid[i][j] = COLLAPSED if row["collapsed"] == "true" else SURVIVED

    height = max(3.0, 0.28 * len(records) + 1.6)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.38 * len(levels) + 2.5), height))
    ax.imshow(grid, cmap=ListedColormap(COLOURS), vmin=0, vmax=3, aspect="auto", interpolation="nearest")
    ax.set_xticks(range(len(levels)))
    ax.set_xticklabels(["%g" % level for level in levels], rotation=90, fontsize=8)
    ax.set_yticks(range(len(records)))
    ax.set_yticklabels([record_label(r) for r in records], fontsize=8)
    ax.set_xticks([j - 0.5 for j in range(1, len(levels))], minor=True)
    ax.set_yticks([i - 0.5 for i in range(1, len(records))], minor=True)
    ax.grid(which="minor", color="white", linewidth=0.8)
    ax.tick_params(which="minor", length=0)
    ax.set_xlabel("PGA  [g]")
    ax.set_ylabel("record")
    ax.set_title(title, fontsize=10)
    used = sorted({v for line in grid for v in line})
    names = {SURVIVED: "survived", COLLAPSED: "collapsed", REFUSED: "refused by the engine", MISSING: "not run"}
    ax.legend(handles=[Patch(facecolor=COLOURS[v], edgecolor="0.5", label=names[v]) for v in used],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(png, dpi=150)
    plt.close(fig)


def displacement_figure(rows, case, capacities, png, title):
    fig, ax = plt.subplots(figsize=(8, 6))
    survived = [(float(r["pga_g"]), 1000.0 * float(r["max_abs_x_m"])) for r in rows
                if not r["error"] and r["collapsed"] == "false"]
    collapsed = [(float(r["pga_g"]), 1000.0 * float(r["max_abs_x_m"])) for r in rows
                 if not r["error"] and r["collapsed"] == "true"]
    if survived:
        ax.scatter([p[0] for p in survived], [p[1] for p in survived], s=14, marker="o", facecolors="none",
                   edgecolors="#2c7fb8", linewidths=0.8, label="survived")
    if collapsed:
        ax.scatter([p[0] for p in collapsed], [p[1] for p in collapsed], s=18, marker="x", color="#c0392b",
                   linewidths=0.9, label="collapsed")
    ax.set_xlabel("PGA  [g]")
    ax.set_ylabel("max |x|  [mm]")
    ax.set_ylim(bottom=0.0)
    ax.grid(True, which="both", linewidth=0.4, alpha=0.5)

    rate = ax.twinx()
    levels = [p["pga_g"] for p in case["survival"]]
    rate.plot(levels, [p["survival_rate"] for p in case["survival"]], color="0.15", marker="s", markersize=4,
              linewidth=1.2, label="survival rate")
    if case["fit_mean_g"] is not None and case["fit_std_g"] is not None and levels:
        mean, sd = case["fit_mean_g"], case["fit_std_g"]
        low, high = min(levels), max(levels)
        xs = [low + (high - low) * k / 200.0 for k in range(201)]
        rate.plot(xs, [1.0 - normal_cdf((x - mean) / sd) for x in xs], color="0.15", linestyle="--", linewidth=1.2,
                  label="fitted normal: mean %.3f g, sd %.3f g" % (mean, sd))
    for capacity, label in capacities:
        rate.axvline(capacity, color="#7f7f7f", linestyle=":", linewidth=1.0)
        rate.annotate("%s\n%.3f g" % (label, capacity), xy=(capacity, 0.02), xycoords=("data", "axes fraction"),
                      xytext=(3, 0), textcoords="offset points", fontsize=8, color="0.3")
    rate.set_ylim(-0.02, 1.02)
    rate.set_ylabel("survival rate  [-]")

    handles, labels = ax.get_legend_handles_labels()
    more_handles, more_labels = rate.get_legend_handles_labels()
    ax.set_title(title, fontsize=10)
    # Below the axes: inside, it would cover points or the survival curve whatever the corner.
    fig.tight_layout(rect=(0.0, 0.1, 1.0, 1.0))
    fig.legend(handles + more_handles, labels + more_labels, loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.savefig(png, dpi=150)
    plt.close(fig)


def main(argv):
    if len(argv) < 3 or (len(argv) - 3) % 6 != 0:
        sys.exit("usage: study_figures.py RUNS_CSV SUMMARY_JSON [CASE VERTICAL R_LABEL FIG6_PNG FIG7_PNG TITLE]...")
    with open(argv[1], newline="") as f:
        runs = list(csv.DictReader(f))
    with open(argv[2]) as f:
        summary = json.load(f)
    records = summary["plan"]["records"]
    levels = summary["plan"]["pga_g"]
    caps = summary["capacities"]
    capacities = [(caps["ntc2008_g"], "NTC 2008"), (caps["nzsee2016_g"], "NZSEE 2016")]
    for k in range(3, len(argv), 6):
        case = summary["cases"][int(argv[k])]
        vertical, r_label, fig6, fig7, title = argv[k + 1], argv[k + 2], argv[k + 3], argv[k + 4], argv[k + 5]
        rows = [r for r in runs if r["vertical"] == vertical and r["r"] == r_label]
        collapse_map(rows, records, levels, fig6, "Collapse map, " + title)
        displacement_figure(rows, case, capacities, fig7, "Max displacement and survival, " + title)


if __name__ == "__main__":
    main(sys.argv)
