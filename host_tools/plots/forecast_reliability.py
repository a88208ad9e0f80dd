# The reliability diagram of `rockwatch study --forecast` (issue 29 item 4): per bin of forecast P(collapse), the
# observed frequency of collapse within the horizon against the bin's mean forecast, with the diagonal (perfect
# calibration), the ±0.1 band the calibration goal allows, and the number of forecasts per bin; beneath, how many
# forecasts fell in each bin (log scale).
# Embedded in the rockwatch binary and run by `rockwatch study --forecast`:
#   forecast_reliability.py SUMMARY_JSON PNG TITLE
import json
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the tool runs on servers and in CI
import matplotlib.pyplot as plt


def main(argv):
    if len(argv) != 4:
        sys.exit("usage: forecast_reliability.py SUMMARY_JSON PNG TITLE")
    with open(argv[1]) as f:
        forecast = json.load(f)["forecast"]
    bins = forecast["reliability"]
    tol = forecast["calibration"]["tolerance"]
    min_n = forecast["calibration"]["min_forecasts_per_bin"]
    fig, (ax, hist) = plt.subplots(2, 1, figsize=(5.5, 7), gridspec_kw={"height_ratios": [3, 1]}, sharex=True)
    ax.plot([0, 1], [0, 1], "k--", lw=0.8, label="perfect calibration")
    ax.fill_between([0, 1], [-tol, 1 - tol], [tol, 1 + tol], color="0.9", label="goal: within %g" % tol)
    judged = [b for b in bins if b["n"] >= min_n]
    thin = [b for b in bins if b["n"] < min_n]
    ax.plot([b["mean_p"] for b in judged], [b["observed"] for b in judged], "o-", color="C0",
            label="ensemble (bins with >= %d forecasts)" % min_n)
    if thin:
        ax.plot([b["mean_p"] for b in thin], [b["observed"] for b in thin], "o", mfc="none", color="C0",
                label="bins with fewer")
    calibrated = forecast.get("calibrated") or {}
    cbins = calibrated.get("reliability") or []
    if cbins:
        cj = [b for b in cbins if b["n"] >= min_n]
        ax.plot([b["mean_p"] for b in cj], [b["observed"] for b in cj], "s-", color="C1",
                label="calibrated P, leave one record out")
        ct = [b for b in cbins if b["n"] < min_n]
        if ct:
            ax.plot([b["mean_p"] for b in ct], [b["observed"] for b in ct], "s", mfc="none", color="C1")
    for b in bins:
        ax.annotate(str(b["n"]), (b["mean_p"], b["observed"]), fontsize=7, xytext=(4, -10),
                    textcoords="offset points")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_ylabel("observed frequency of collapse within %g s" % forecast["settings"]["horizon_s"])
    skill = forecast["brier_skill"]
    base = forecast["baseline"]["brier_skill"]
    cskill = calibrated.get("brier_skill")
    ax.set_title("%s\nBrier %s, skill %s, calibrated %s (baseline %s)" % (
        argv[3], "%.4f" % forecast["brier"] if forecast["brier"] is not None else "-",
        "%.3f" % skill if skill is not None else "-", "%.3f" % cskill if cskill is not None else "-",
        "%.3f" % base if base is not None else "-"), fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    hist.bar([0.5 * (b["lo"] + b["hi"]) - (0.022 if cbins else 0) for b in bins], [b["n"] for b in bins],
             width=0.044 if cbins else 0.09, color="C0", label="raw")
    if cbins:
        hist.bar([0.5 * (b["lo"] + b["hi"]) + 0.022 for b in cbins], [b["n"] for b in cbins], width=0.044,
                 color="C1", label="calibrated")
        hist.legend(fontsize=7)
    hist.set_yscale("log")
    hist.set_xlabel("forecast P(collapse)")
    hist.set_ylabel("forecasts")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)


if __name__ == "__main__":
    main(sys.argv)
