#!/usr/bin/python3
"""Plot a strength-reduction search: crest displacement against the trial factor F.

    /usr/bin/python3 scripts/plot_fos.py FOS.csv OUT.png CASE LOWER UPPER BRACKETED

FOS.csv (written by `talus fos`, src/solver/strength_reduction.cpp) has one row per trial with
the columns factor, failed (0/1), crest_displacement (m, at the last converged load step) and
load_reached (fraction of the load). Trials that stood are dots, failed ones crosses (their
displacement is that of the last converged step, labelled with the load fraction reached); the
shaded band is the final bracket [LOWER, UPPER] when BRACKETED is 1.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 7:
        sys.exit("usage: plot_fos.py FOS.csv OUT.png CASE LOWER UPPER BRACKETED")
    stood, failed = [], []
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            point = (float(row["factor"]), float(row["crest_displacement"]),
                     float(row["load_reached"]))
            (failed if row["failed"] == "1" else stood).append(point)
    lower, upper, bracketed = float(sys.argv[4]), float(sys.argv[5]), sys.argv[6] == "1"
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    stood.sort()
    if stood:
        ax.plot([p[0] for p in stood], [p[1] for p in stood], "o-", color="tab:blue",
                label="stood (full load)")
    if failed:
        ax.plot([p[0] for p in failed], [p[1] for p in failed], "x", color="tab:red",
                markersize=9, mew=2, label="failed (last converged step)")
        for factor, moved, load in failed:
            ax.annotate(f"{100 * load:.0f} %", (factor, moved), textcoords="offset points",
                        xytext=(4, 4), fontsize=7, color="tab:red")
    if bracketed:
        ax.axvspan(lower, upper, color="tab:green", alpha=0.25,
                   label=f"FoS = {0.5 * (lower + upper):.3f} [{lower:.3f}, {upper:.3f}]")
    ax.set_yscale("symlog", linthresh=1e-3)
    ax.set_xlabel("strength reduction factor F (c / F, tan φ / F)")
    ax.set_ylabel("crest displacement [m]")
    ax.set_title(f"{sys.argv[3]}: strength reduction")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=130)


if __name__ == "__main__":
    main()
