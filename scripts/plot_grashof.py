#!/usr/bin/python3
"""Plot the Grashof verification: shear stress through the depth at the cantilever's mid-span.

    /usr/bin/python3 scripts/plot_grashof.py PROFILES.csv OUT.png "RESOLUTION"

PROFILES.csv (written by src/verify/case_grashof.cpp) has columns kind, y, tau_xy with kind
analytical (Grashof's parabola), raw (particle stress), grid (grid-node stress) or smoothed
(smoothed particle stress). Stress on the horizontal axis, depth on the vertical, as the
profile sits in the beam.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "analytical": dict(color="black", linestyle="-", label="Grashof: 3P/(2D) (1 - 4y²/D²)"),
    "raw": dict(color="tab:red", marker="x", linestyle=":", label="(a) raw particle stress"),
    "grid": dict(color="tab:blue", marker="o", linestyle="--", label="(b) grid-node stress"),
    "smoothed": dict(color="tab:green", marker="s", linestyle="-.", markersize=4,
                     label="(c) smoothed particle stress"),
}


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: plot_grashof.py PROFILES.csv OUT.png RESOLUTION")
    data = {}
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            ys, taus = data.setdefault(row["kind"], ([], []))
            ys.append(float(row["y"]))
            taus.append(float(row["tau_xy"]))
    fig, ax = plt.subplots(figsize=(6.5, 5))
    for kind in ("analytical", "raw", "grid", "smoothed"):
        if kind in data:
            ys, taus = data[kind]
            ax.plot(taus, ys, **STYLE[kind])
    ax.set_xlabel("shear stress tau_xy [Pa]")
    ax.set_ylabel("y from the neutral axis [m]")
    ax.set_title(f"Cantilever L = 8, D = 1, P = -1 N: shear at mid-span, {sys.argv[3]}")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=130)


if __name__ == "__main__":
    main()
