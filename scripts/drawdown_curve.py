#!/usr/bin/python3
"""The factor of safety of a slope against the drawdown of the water in front of and inside it.

    /usr/bin/python3 scripts/drawdown_curve.py TALUS CASE OUT_DIR [--ratios 0,0.1,...,1]
                                                [--set KEY=VALUE ...]

CASE is a case with a `water` section and a `strength_reduction` section (cases/
slope_drawdown.yaml); H is the height of the crest (the search's probe) above the grid's
origin. For each drawdown ratio L/H the level is set to
y_crest - L and `TALUS fos` searches the factor in the incremental mode (one run per level)
into OUT_DIR/ratio_<L/H>/. Writes OUT_DIR/drawdown.csv (ratio, level, factor, lower, upper)
and OUT_DIR/drawdown.png: the factor against L/H with Griffiths & Lane's (1999, example 5)
values for their slope. Extra --set options go to every search (a coarser grid for a check).
"""

import argparse
import csv
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import yaml  # noqa: E402

GRIFFITHS_LANE = [(0.0, 1.85), (0.7, 1.30), (1.0, 1.40)]  # example 5, read from their figure


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("talus")
    parser.add_argument("case")
    parser.add_argument("out_dir")
    parser.add_argument("--ratios", default=",".join(f"{k / 10:g}" for k in range(11)))
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    args = parser.parse_args()
    with open(args.case) as f:
        case = yaml.safe_load(f)
    probe = case["strength_reduction"]["probe"]
    crest = next(p["point"] for p in case["probes"] if p["name"] == probe)
    base = case["grid"]["origin"][1]
    height = crest[1] - base
    ratios = [float(r) for r in args.ratios.split(",")]
    os.makedirs(args.out_dir, exist_ok=True)
    rows = []
    for ratio in ratios:
        level = crest[1] - ratio * height
        out = os.path.join(args.out_dir, f"ratio_{ratio:g}")
        command = [args.talus, "fos", args.case, "--out", out, "--force",
                   "--set", f"water.level={level!r}",
                   "--set", "strength_reduction.mode=incremental"]
        for o in args.overrides:
            command += ["--set", o]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"drawdown_curve: L/H = {ratio:g}: talus fos failed ({done.returncode}):\n"
                     + done.stderr)
        with open(os.path.join(out, "fos.json")) as f:
            fos = json.load(f)
        if not fos["bracketed"]:
            sys.exit(f"drawdown_curve: L/H = {ratio:g}: no bracket: {fos['message']}")
        lower, upper = fos["bracket"]
        rows.append((ratio, level, fos["factor_of_safety"], lower, upper))
        print(f"L/H = {ratio:4.2f}  level {level:7.3f} m  factor {fos['factor_of_safety']:.4f}",
              flush=True)
    with open(os.path.join(args.out_dir, "drawdown.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["ratio", "level", "factor", "lower", "upper"])
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(6, 4))
    x = [r[0] for r in rows]
    ax.fill_between(x, [r[3] for r in rows], [r[4] for r in rows], color="C0", alpha=0.25,
                    label="bracket")
    ax.plot(x, [r[2] for r in rows], "o-", color="C0", label=f"Talus ({case['name']})")
    ax.plot(*zip(*GRIFFITHS_LANE), "s", color="C3", mfc="none", ms=8,
            label="Griffiths & Lane (1999), ex. 5")
    ax.set_xlabel("drawdown ratio L / H")
    ax.set_ylabel("factor of safety")
    ax.set_title("Slow drawdown: factor of safety against the water level")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.savefig(os.path.join(args.out_dir, "drawdown.png"), dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    main()
