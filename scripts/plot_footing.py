#!/usr/bin/python3
"""Plot a footing verification: footing pressure against settlement, one or more curves.

    /usr/bin/python3 scripts/plot_footing.py [--band LO HI] OUT.png "TITLE" "REFERENCE" CSV LABEL
                                             [CSV LABEL ...]

Each CSV (written by src/verify/footing_curve.cpp) has columns settlement_m, settlement_over_B,
pressure_Pa, pressure_over_reference. The pressure is drawn normalised by its curve's limit
pressure (REFERENCE names it), with the band the verification accepts for its peak: 3 % either
side unless --band gives it (as fractions of the limit pressure).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_curve(path):
    settlement, pressure = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            settlement.append(100.0 * float(row["settlement_over_B"]))
            pressure.append(float(row["pressure_over_reference"]))
    return settlement, pressure


def main():
    args = sys.argv[1:]
    band, band_label = (0.97, 1.03), "±3 % of the limit pressure"
    if args[:1] == ["--band"] and len(args) >= 3:
        band = (float(args[1]), float(args[2]))
        band_label = f"accepted peak: {band[0]:g} to {band[1]:g}"
        args = args[3:]
    if len(args) < 5 or len(args) % 2 != 1:
        sys.exit('usage: plot_footing.py [--band LO HI] OUT.png "TITLE" "REFERENCE" CSV LABEL '
                 '[CSV LABEL ...]')
    out, title, reference = args[0:3]
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.axhspan(band[0], band[1], color="0.9", label=band_label)
    ax.axhline(1.0, color="black", linewidth=1, label=reference)
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:purple"]
    for k in range(3, len(args), 2):
        settlement, pressure = read_curve(args[k])
        colour = colours[(k // 2 - 1) % len(colours)]
        ax.plot(settlement, pressure, "o-", color=colour, markersize=3,
                label=f"Talus, {args[k + 1]}")
        peak = max(range(len(pressure)), key=pressure.__getitem__)
        ax.plot(settlement[peak], pressure[peak], "s", color="tab:red")
        ax.annotate(f"{pressure[peak]:.4f}", (settlement[peak], pressure[peak]),
                    textcoords="offset points", xytext=(4, -12), fontsize=8, color=colour)
    ax.set_xlabel("settlement / B [%]")
    ax.set_ylabel("footing pressure / limit pressure")
    ax.set_title(title)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=130)


if __name__ == "__main__":
    main()
