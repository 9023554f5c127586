#!/usr/bin/python3
"""Newton iteration cost plot for `talus bench --case newton_cost`.

Usage: /usr/bin/python3 scripts/plot_newton_cost.py newton_cost.csv newton_cost.png

One bar per case: the run's wall time per Newton iteration, stacked by phase (summary.json's
split), in units of the bare factorisation + solve of the run's own tangent (talus_bench), so
the cases of different sizes share one axis. The dashed line at 2 is the issue's target; the
bar labelled 'bare' is 1 by construction. Rows whose status is not "ok" are left out. Uses the
Agg backend (no display needed).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PHASES = [
    ("factorization", "factorisation"),
    ("solve", "solve"),
    ("tangent_assembly", "tangent assembly"),
    ("material", "material"),
    ("residual_assembly", "residual assembly"),
    ("analysis", "analysis (per pattern)"),
    ("step_setup", "step setup"),
    ("commit", "commit"),
    ("output", "output"),
    ("other", "other"),
]


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: plot_newton_cost.py newton_cost.csv newton_cost.png\n")
        return 2
    with open(argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    if not rows:
        sys.stderr.write(f"{argv[1]}: no completed rows\n")
        return 1
    fig, ax = plt.subplots(figsize=(8, 4.5))
    colours = plt.get_cmap("tab10").colors
    labels = []
    for i, r in enumerate(rows):
        iterations = float(r["newton_iterations"])
        bare = float(r["bare_factor_solve_ms"])
        bottom = 0.0
        for k, (key, name) in enumerate(PHASES):
            height = 1e3 * float(r["seconds_" + key]) / iterations / bare
            ax.bar(i, height, bottom=bottom, color=colours[k], label=name if i == 0 else None)
            bottom += height
        ax.text(i, bottom, f"{float(r['ms_per_iteration']):.2f} ms", ha="center", va="bottom")
        labels.append(f"{r['case']}\n{int(float(r['unknowns']))} unknowns\nbare {bare:.2f} ms")
    ax.axhline(2.0, color="black", linestyle="--", linewidth=1, label="target: 2x bare")
    ax.axhline(1.0, color="grey", linestyle=":", linewidth=1, label="bare factor + solve")
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_xlim(-0.6, len(rows) + 1.4)
    ax.set_ylabel("time per Newton iteration / bare factor + solve")
    ax.set_title("Implicit Newton iteration by phase, against its own linear solve")
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
