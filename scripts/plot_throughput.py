#!/usr/bin/python3
"""Explicit throughput plot for `talus bench --case explicit_throughput`.

Usage: /usr/bin/python3 scripts/plot_throughput.py throughput.csv throughput.png

Left: particle-steps per second (median) against the number of points, one line per dimension
and thread count. Right: the speed-up from one thread to two at each size. Rows whose status is
not "ok" are left out. Uses the Agg backend (no display needed).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: plot_throughput.py throughput.csv throughput.png\n")
        return 2
    with open(argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    if not rows:
        sys.stderr.write(f"{argv[1]}: no completed rows\n")
        return 1
    series = {}
    for r in rows:
        key = (int(r["dimension"]), int(r["threads"]))
        series.setdefault(key, []).append(
            (float(r["particles"]), float(r["median_particle_steps_per_second"]) / 1e6))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5), dpi=110)
    colours = {2: "tab:blue", 3: "tab:red"}
    for (dim, threads), pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "-" if threads > 1 else "--",
                marker="o" if threads > 1 else "s", color=colours.get(dim, "k"),
                label=f"{dim}D, {threads} thread{'s' if threads > 1 else ''}")
    ax.set_xscale("log")
    ax.set_xlabel("material points")
    ax.set_ylabel("million particle-steps per second (median)")
    ax.set_title("Explicit step (GIMP, MUSL, neo-Hookean)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    for dim in sorted({d for d, _ in series}):
        one = dict(series.get((dim, 1), []))
        two = dict(series.get((dim, 2), []))
        sizes = sorted(set(one) & set(two))
        if sizes:
            bx.plot(sizes, [two[n] / one[n] for n in sizes], marker="o",
                    color=colours.get(dim, "k"), label=f"{dim}D")
    bx.axhline(2.0, color="0.5", linestyle=":", label="ideal")
    bx.set_xscale("log")
    bx.set_ylim(0.8, 2.2)
    bx.set_xlabel("material points")
    bx.set_ylabel("speed-up, 2 threads over 1")
    bx.set_title("Thread scaling")
    bx.grid(True, which="both", alpha=0.3)
    bx.legend()
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
