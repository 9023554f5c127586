#!/usr/bin/python3
"""Plot a staged case's factor of safety against time.

    /usr/bin/python3 scripts/plot_fos_history.py FOS_HISTORY.csv OUT.png CASE

FOS_HISTORY.csv (written by `talus fos` for a case with `stages`,
src/solver/strength_reduction.cpp) has one row per stage searched after: the stage, the
history's time at its end (s), the bracket [lower, upper], the factor (its midpoint) and
whether the bracket is within the tolerance. Each bracket is drawn as a bar around its factor;
one that is not bracketed as a hollow marker. Time is in days on a logarithmic axis when the
stages span more than two decades (a consolidation), linear otherwise.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DAY = 86400.0


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: plot_fos_history.py FOS_HISTORY.csv OUT.png CASE")
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sys.argv[1]}: no stage was searched")
    time = [float(r["time"]) for r in rows]
    lower = [float(r["lower"]) for r in rows]
    upper = [float(r["upper"]) for r in rows]
    factor = [float(r["factor_of_safety"]) for r in rows]
    bracketed = [r["bracketed"] == "1" for r in rows]
    days = max(time) >= DAY
    scale = DAY if days else 1.0
    t = [x / scale for x in time]

    fig, ax = plt.subplots(figsize=(7, 4.2))
    ax.plot(t, factor, "-", color="0.6", lw=1, zorder=1)
    for ti, lo, up, fs, ok, r in zip(t, lower, upper, factor, bracketed, rows):
        ax.errorbar([ti], [fs], yerr=[[fs - lo], [up - fs]], fmt="o",
                    mfc="C0" if ok else "white", mec="C0", ecolor="C0", capsize=3, zorder=2)
        ax.annotate(r["stage"], (ti, up), textcoords="offset points", xytext=(0, 5),
                    ha="center", fontsize=8)
    ax.axhline(1.0, color="C3", lw=0.8, ls="--")
    ax.margins(y=0.15)
    if min(t) > 0 and max(t) / min(t) > 100:
        ax.set_xscale("log")
    ax.set_xlabel("time (days)" if days else "time (s)")
    ax.set_ylabel("factor of safety")
    ax.set_title(f"{sys.argv[3]}: factor of safety after each stage")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
