#!/usr/bin/python3
"""Plot a factor of safety against the grid size (`talus fos --refine N`).

    /usr/bin/python3 scripts/plot_fos_refinement.py REFINEMENT.csv OUT.png CASE EXTRAPOLATED MESSAGE

REFINEMENT.csv (src/solver/fos_refinement.cpp) has one row per grid: cell_size,
factor_of_safety, lower, upper (the bracket), bracketed, upper_undecided. Each level is its
bracket with the midpoint; EXTRAPOLATED (empty: none) is the Richardson extrapolation to h = 0
with the observed order, drawn as a dashed line; MESSAGE says what the sequence shows.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 6:
        sys.exit("usage: plot_fos_refinement.py REFINEMENT.csv OUT.png CASE EXTRAPOLATED MESSAGE")
    with open(sys.argv[1]) as f:
        rows = [r for r in csv.DictReader(f)]
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for r in rows:
        h, fos = float(r["cell_size"]), float(r["factor_of_safety"])
        lo, hi = float(r["lower"]), float(r["upper"])
        colour = "tab:orange" if r["upper_undecided"] == "1" else "tab:blue"
        ax.errorbar(h, fos, yerr=[[fos - lo], [hi - fos]], fmt="o", color=colour, capsize=5)
        ax.annotate(f"{fos:.3f}", (h, fos), textcoords="offset points", xytext=(8, -3), fontsize=8)
    ax.plot([float(r["cell_size"]) for r in rows], [float(r["factor_of_safety"]) for r in rows],
            "-", color="tab:blue", alpha=0.5)
    if sys.argv[4]:
        ax.axhline(float(sys.argv[4]), color="tab:green", ls="--",
                   label=f"extrapolated to h = 0: {float(sys.argv[4]):.3f}")
        ax.legend(fontsize=8)
    ax.set_xscale("log", base=2)
    ax.invert_xaxis()
    ax.set_xlabel("cell size h [m] (finer to the right)")
    ax.set_ylabel("factor of safety (bracket)")
    ax.set_title(f"{sys.argv[3]}: factor of safety against the grid\n{sys.argv[5]}", fontsize=9)
    ax.grid(True, alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=130)


if __name__ == "__main__":
    main()
