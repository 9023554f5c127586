#!/usr/bin/python3
"""Plot a strength-reduction search: crest displacement and current stiffness against F.

    /usr/bin/python3 scripts/plot_fos.py FOS.csv OUT.png CASE LOWER UPPER BRACKETED MIN_STIFFNESS MODE

FOS.csv (written by `talus fos`, src/solver/strength_reduction.cpp) has one row per trial
(MODE `trials`) or per converged step of the one incremental run (MODE `incremental`), with the
columns factor, failed (0/1), criterion, load_reached, current_stiffness and crest_displacement.
Top: the crest displacement at the last converged step; bottom: the current stiffness there
(Bergan's parameter, 1 while the slope responds elastically, 0 at a mechanism) with the
criterion's MIN_STIFFNESS. Trials that stood are dots, failed ones crosses labelled with what
ended them and the load they reached; the incremental run is one curve, its knee (the first
failed step) marked. The shaded band is the final bracket [LOWER, UPPER] when BRACKETED is 1.
"""

import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import LogFormatterSciNotation  # noqa: E402

LABELS = {"stiffness": "stiffness", "limit_point": "limit point", "displacement": "crest limit",
          "newton_budget": "undecided (Newton)", "numerical": "numerical",
          "initial_stress": "initial stress", "interrupted": "interrupted"}


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def main():
    if len(sys.argv) != 9:
        sys.exit("usage: plot_fos.py FOS.csv OUT.png CASE LOWER UPPER BRACKETED MIN_STIFFNESS MODE")
    with open(sys.argv[1]) as f:
        rows = [{"factor": float(r["factor"]), "failed": r["failed"] == "1",
                 "criterion": r["criterion"], "load": float(r["load_reached"]),
                 "stiffness": number(r["current_stiffness"]),
                 "crest": float(r["crest_displacement"])} for r in csv.DictReader(f)]
    lower, upper, bracketed = float(sys.argv[4]), float(sys.argv[5]), sys.argv[6] == "1"
    min_stiffness, incremental = float(sys.argv[7]), sys.argv[8] == "incremental"
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True,
                                      gridspec_kw={"height_ratios": [1.2, 1]})
    stood = sorted((r for r in rows if not r["failed"]), key=lambda r: r["factor"])
    failed = [r for r in rows if r["failed"]]
    style = "-" if incremental else "o-"
    label = "converged steps" if incremental else "stood (full load)"
    for ax, key in ((top, "crest"), (bottom, "stiffness")):
        ax.plot([r["factor"] for r in stood], [r[key] for r in stood], style, color="tab:blue",
                markersize=4, label=label)
        for r in failed:
            ax.plot(r["factor"], r[key], "x", color="tab:red", markersize=9, mew=2)
            if ax is bottom:
                continue  # labelled once, above: near min_stiffness the labels would overlap
            text = LABELS.get(r["criterion"], r["criterion"])
            if not incremental:
                text += f", {100 * r['load']:.0f} %"
            ax.annotate(text, (r["factor"], r[key]), textcoords="offset points", xytext=(4, 4),
                        fontsize=7, color="tab:red")
        if bracketed:
            ax.axvspan(lower, upper, color="tab:green", alpha=0.25)
        ax.grid(True, alpha=0.3)
    if failed:
        top.plot([], [], "x", color="tab:red", mew=2,
                 label="knee: first failed step" if incremental else
                 "failed (last converged step)")
    if bracketed:
        top.plot([], [], "s", color="tab:green", alpha=0.4,
                 label=f"FoS = {0.5 * (lower + upper):.3f} [{lower:.3f}, {upper:.3f}]")
    # A log scale: the displacements span decades (elastic millimetres against a mechanism's
    # metres). Intermediate ticks labelled too, or a range within a decade shows no number.
    if all(r["crest"] > 0 for r in rows):
        top.set_yscale("log")
        top.yaxis.set_minor_formatter(LogFormatterSciNotation(labelOnlyBase=False,
                                                              minor_thresholds=(2, 0.5)))
    top.set_ylabel("crest displacement [m]")
    top.set_title(f"{sys.argv[3]}: strength reduction ({'incremental' if incremental else 'trials'})")
    top.legend(fontsize=8, loc="upper left")
    bottom.axhline(min_stiffness, color="tab:red", lw=1, ls="--",
                   label=f"min_stiffness {min_stiffness:g}")
    bottom.set_ylim(-0.02, 1.05)
    bottom.set_ylabel("current stiffness [-]")
    bottom.set_xlabel("strength reduction factor F (c / F, tan φ / F)")
    bottom.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=130)


if __name__ == "__main__":
    main()
