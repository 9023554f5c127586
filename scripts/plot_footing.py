#!/usr/bin/python3
"""Plot the strip-footing verification: footing pressure against settlement.

    /usr/bin/python3 scripts/plot_footing.py LOAD_SETTLEMENT.csv OUT.png "LABEL"

LOAD_SETTLEMENT.csv (written by src/verify/case_strip_footing.cpp) has columns settlement_m,
settlement_over_B, pressure_Pa, pressure_over_prandtl. The pressure is drawn normalised by
Prandtl's limit (2 + pi) c, with the 3 % band the verification allows around it.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: plot_footing.py LOAD_SETTLEMENT.csv OUT.png LABEL")
    settlement, pressure = [], []
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            settlement.append(100.0 * float(row["settlement_over_B"]))
            pressure.append(float(row["pressure_over_prandtl"]))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.axhspan(0.97, 1.03, color="0.9", label="±3 % of (2 + π) c")
    ax.axhline(1.0, color="black", linewidth=1, label="Prandtl: (2 + π) c")
    ax.plot(settlement, pressure, "o-", color="tab:blue", markersize=3,
            label=f"Talus, {sys.argv[3]}")
    peak = max(range(len(pressure)), key=pressure.__getitem__)
    ax.plot(settlement[peak], pressure[peak], "s", color="tab:red",
            label=f"peak {pressure[peak]:.4f}")
    ax.set_xlabel("settlement / B [%]")
    ax.set_ylabel("footing pressure / ((2 + π) c)")
    ax.set_title("Smooth strip footing on Tresca soil")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=130)


if __name__ == "__main__":
    main()
