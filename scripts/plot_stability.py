#!/usr/bin/python3
"""Plot the histories of a stability verification case, one subplot per panel.

    /usr/bin/python3 scripts/plot_stability.py [--x-label TEXT] HISTORIES.csv OUT.png "TITLE"
                                               [LOG_PANEL ...]

HISTORIES.csv (written by src/verify/histories.cpp) has columns panel, series, x, y: every
series of a panel is drawn as one line against x (the simulated time, or the pseudo-time of a
load ramp). Panels named after the title are drawn with a logarithmic vertical axis of |y|
(zeros left out). --x-label names the horizontal axis (default "t [s]"; a profile is drawn
against depth).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    argv = sys.argv[1:]
    x_label = "t [s]"
    if len(argv) >= 2 and argv[0] == "--x-label":
        x_label, argv = argv[1], argv[2:]
    if len(argv) < 3:
        sys.exit("usage: plot_stability.py [--x-label TEXT] HISTORIES.csv OUT.png TITLE "
                 "[LOG_PANEL ...]")
    log_panels = set(argv[3:])
    panels = {}
    with open(argv[0]) as f:
        for row in csv.DictReader(f):
            series = panels.setdefault(row["panel"], {})
            xs, ys = series.setdefault(row["series"], ([], []))
            xs.append(float(row["x"]))
            ys.append(float(row["y"]))
    if not panels:
        sys.exit("no histories to plot")
    fig, axes = plt.subplots(len(panels), 1, figsize=(7.5, 3.2 * len(panels)), squeeze=False)
    for ax, (panel, series) in zip(axes[:, 0], panels.items()):
        for label, (xs, ys) in series.items():
            if panel in log_panels:
                # Exact zeros (e.g. an error at t = 0) have no place on a log axis.
                kept = [(x, abs(y)) for x, y in zip(xs, ys) if y != 0]
                ax.semilogy([x for x, _ in kept], [y for _, y in kept], label=label)
            else:
                ax.plot(xs, ys, label=label)
        ax.set_title(panel, fontsize=10)
        ax.set_xlabel(x_label)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best", ncol=2)
    fig.suptitle(argv[2], fontsize=11)
    fig.tight_layout()
    fig.savefig(argv[1], dpi=110)


if __name__ == "__main__":
    main()
