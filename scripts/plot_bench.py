#!/usr/bin/python3
"""Work-precision plot for `talus bench`: log-log error against median wall seconds.

Usage: /usr/bin/python3 scripts/plot_bench.py bench.csv bench.png

One line with markers per (shape, backend), a colour each and a marker per shape, points ordered by resolution and labelled with the
number of cells. Rows whose status is not "ok" (or without a positive error and time) are left
out and listed in the legend title. Uses the Agg backend (no display needed).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: plot_bench.py bench.csv bench.png\n")
        return 2
    with open(argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.stderr.write(f"{argv[1]}: no rows\n")
        return 1
    case = rows[0]["case"]
    series = {}
    failed = []
    for r in rows:
        err, sec = number(r["error"]), number(r["median_seconds"])
        if r["status"] != "ok" or not (err > 0) or not (sec > 0):
            failed.append(f'{r["shape"]}/{r["backend"]}/{r["cells"]}')
            continue
        series.setdefault((r["shape"], r["backend"]), []).append((int(r["cells"]), sec, err))

    fig, ax = plt.subplots(figsize=(11, 6.5), dpi=110)
    markers = {"linear": "s", "gimp": "o", "cpgimp": "^", "cpdi": "v", "bspline2": "D",
               "bspline3": "P"}
    styles = {"linear": "--", "gimp": "-"}
    cmap = plt.get_cmap("tab20")
    for index, ((shape, backend), pts) in enumerate(sorted(series.items())):
        pts.sort()
        colour = cmap(index % 20)
        ax.plot([p[1] for p in pts], [p[2] for p in pts], styles.get(shape, "-"),
                marker=markers.get(shape, "^"), color=colour, label=f"{shape}, {backend}",
                markersize=6, linewidth=1.2, alpha=0.85)
    # Label each resolution once per shape (all backends share the cells).
    labelled = set()
    for (shape, _), pts in sorted(series.items()):
        for cells, sec, err in pts:
            if (shape, cells) in labelled:
                continue
            labelled.add((shape, cells))
            ax.annotate(f"{cells}", (sec, err), textcoords="offset points", xytext=(5, 4),
                        fontsize=8, color="0.3")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median wall time of run_case [s]")
    if case == "cantilever":
        ax.set_ylabel("relative tip deflection error vs Timoshenko-Goodier [-]")
        res = "cells through the depth"
    elif case == "vibrating_bar":
        ax.set_ylabel("RMS centre-of-mass velocity error / amplitude [-]")
        res = "cells along the bar"
    elif case == "column_large_compression":
        ax.set_ylabel("relative L2 error of the raw sigma_yy, rho g H / E = 4 [-]")
        res = "cells over the height"
    else:
        ax.set_ylabel("error [-]")
        res = "cells"
    ax.set_title(f"Work-precision: {case} (labels: {res}; lower left is better)")
    ax.grid(True, which="both", alpha=0.3)
    title = None
    if failed:
        title = "failed (not plotted): " + ", ".join(failed[:6]) + (" ..." if len(failed) > 6 else "")
    if series:
        ax.legend(fontsize=8, title=title, title_fontsize=7, loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
