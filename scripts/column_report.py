#!/usr/bin/python3
"""The soil-column collapse report (issue 6): runs cases/soil_column_collapse.yaml with and
without material-point splitting, explicit and implicit-dynamic, and writes report.md with
plots into the output folder.

    /usr/bin/python3 scripts/column_report.py [--talus build/talus] [--out results/column_report]
                                              [--refine] [--threads N] [--reuse] [--check]

Measured per run (final frame unless said otherwise):
  * particle count over time (timeseries.csv, column `particles`);
  * largest voxel aspect ratio over time: for each point the ratio of the singular values of
    its deformed voxel's edge matrix [c1 - c0, c3 - c0] (1 for a square, the long-to-short
    axis ratio of the parallelogram's equivalent ellipse; a string-like voxel is large);
  * runout: the front (largest x of any deformed voxel corner) at the end minus at t = 0;
  * final height: the largest y of any deformed voxel corner at the end.
The voxel corners are what the points represent, so both measures use them rather than the
point centres (a centre sits half a voxel inside the material's edge).
`--refine` adds the explicit and implicit split runs at h = 0.05 m (the refinement study).
`--reuse` keeps a run whose folder already holds a completed summary.json (re-plotting only).
Wall times are the runs' own (summary.json), without the Python around them.
`--check` (ctest report.column_collapse) exits 1 unless the figures the README quotes hold
(BOUNDS below, with their reasons): every run completes, mass survives the splits, the
runouts and heights lie in their bands, explicit and implicit runouts agree within 5 %, and
splitting keeps the voxels rounder than no splitting.
"""

import argparse
import csv
import json
import os
import subprocess
import sys

from report_setup import ensure_packages

ensure_packages()
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

CASE = "cases/soil_column_collapse.yaml"

# The figures of docs/column-collapse/report.md (h = 0.1 m) and their bands. There is no
# closed-form runout for a cohesive column (the granular scaling laws of Lube et al. 2005 are
# for c = 0), so the bands come from the measurements: every run gives the same table with 1
# and 2 threads, but a change of the implicit Newton path (an earlier solver version) moved the
# implicit split run by 0.8 % in runout, 0.2 % in height and 0.9 % in points: the collapse
# passes bifurcations. Bands: 3 % for the explicit runouts, 5 % for the implicit ones, 2 % for
# heights, 10 % for point counts (3-10x that). A friction angle of 38 instead of 42 degrees
# fails seven of them (explicit runout +5 %, heights -7 to -8 %).
BOUNDS = {
    "explicit_split": {"runout": (1.228, 0.03), "height": (1.787, 0.02), "points": (2127, 0.1)},
    "explicit_no_split": {"runout": (1.296, 0.03), "height": (1.776, 0.02)},
    "implicit_split": {"runout": (1.24, 0.05), "height": (1.814, 0.02), "points": (2140, 0.1)},
    "implicit_no_split": {"runout": (1.283, 0.05), "height": (1.80, 0.02)},
    # The other shape functions in the explicit split run (issue 21), the explicit bands. The
    # splines slump further at h = 0.1 m (height 1.46 and 1.39 against uGIMP's 1.79); at
    # h = 0.05 m uGIMP comes down to theirs (1.49 against bspline2's 1.48): the splines are
    # nearer the refined state on the coarse grid.
    "explicit_split_cpgimp": {"runout": (1.227, 0.03), "height": (1.781, 0.02),
                              "points": (2106, 0.1)},
    "explicit_split_cpdi": {"runout": (1.235, 0.03), "height": (1.771, 0.02),
                            "points": (2157, 0.1)},
    "explicit_split_bspline2": {"runout": (1.324, 0.03), "height": (1.457, 0.02),
                                "points": (2177, 0.1)},
    "explicit_split_bspline3": {"runout": (1.336, 0.03), "height": (1.385, 0.02),
                                "points": (2199, 0.1)},
}
IMPLICIT = ["analysis=implicit_dynamic", "time.cfl=~", "time.dt=0.005"]
NO_SPLIT = ["bodies.column.split=~"]
PATTERN = ListedColormap(["#f2f2f2", "#2b5d8a"])


# The shape functions beside the case's uGIMP (issue 21), each in the explicit split run.
SHAPES = ["cpgimp", "cpdi", "bspline2", "bspline3"]


def runs(refine):
    """(label, overrides) of every run of the report."""
    out = [
        ("explicit_split", []),
        ("explicit_no_split", NO_SPLIT),
        ("implicit_split", IMPLICIT),
        ("implicit_no_split", IMPLICIT + NO_SPLIT),
    ]
    out += [(f"explicit_split_{shape}", [f"solver.shape={shape}"]) for shape in SHAPES]
    if refine:
        fine = ["grid.cell_size=0.05"]
        out += [("explicit_split_h0.05", fine), ("implicit_split_h0.05", IMPLICIT + fine)]
        out += [(f"explicit_split_h0.05_{shape}", fine + [f"solver.shape={shape}"])
                for shape in SHAPES]
    return out


def run(talus, label, overrides, out, threads, reuse):
    folder = os.path.join(out, "runs", label)
    summary = os.path.join(folder, "summary.json")
    if reuse and os.path.exists(summary):
        with open(summary) as fh:
            if json.load(fh)["status"] == "completed":
                return folder, 0
    cmd = [talus, "run", CASE, "--out", folder, "--force", "--threads", str(threads)]
    for o in overrides:
        cmd += ["--set", o]
    print("running", label, file=sys.stderr, flush=True)
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        print(done.stderr, file=sys.stderr)
    return folder, done.returncode


def aspect_ratios(corners):
    """Long-to-short singular value ratio of every voxel (n, 4, 2 corners)."""
    a = corners[:, 1, :] - corners[:, 0, :]
    b = corners[:, 3, :] - corners[:, 0, :]
    edges = np.stack([a, b], axis=2)  # n x 2 x 2, columns the two edges
    s = np.linalg.svd(edges, compute_uv=False)
    return s[:, 0] / s[:, 1]


def measure(folder):
    """Per-frame time, particle count and largest aspect ratio; front and height."""
    with h5py.File(os.path.join(folder, "run.h5"), "r") as f:
        frames = sorted(f["frames"].keys())
        times, ratios = [], []
        for name in frames:
            g = f["frames"][name]
            times.append(float(g.attrs["time"]))
            ratios.append(float(aspect_ratios(g["voxels"]["corners"][()].reshape(-1, 4, 2)).max()))
        first = f["frames"][frames[0]]["voxels"]["corners"][()].reshape(-1, 4, 2)
        mass = [float(f["frames"][name]["mass"][()].sum()) for name in (frames[0], frames[-1])]
        last_group = f["frames"][frames[-1]]
        last = last_group["voxels"]["corners"][()].reshape(-1, 4, 2)
        checker = last_group["voxels"]["checker"][()]
    with open(os.path.join(folder, "timeseries.csv")) as fh:
        rows = list(csv.DictReader(fh))
    with open(os.path.join(folder, "summary.json")) as fh:
        summary = json.load(fh)
    return {
        "frame_time": times,
        "max_aspect": ratios,
        "time": [float(r["time"]) for r in rows],
        "particles": [float(r["particles"]) for r in rows],
        "mass_error": abs(mass[1] - mass[0]) / mass[0],
        "runout": float(last[:, :, 0].max() - first[:, :, 0].max()),
        "front": float(last[:, :, 0].max()),
        "height": float(last[:, :, 1].max()),
        "corners": last,
        "checker": checker,
        "summary": summary,
    }


def draw_side_by_side(results, labels, path):
    """The final deformed voxels of each run, three to a row."""
    columns = min(len(labels), 3)
    rows = (len(labels) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(6 * columns, 4 * rows), sharey=True,
                             squeeze=False)
    for ax in axes.flat[len(labels):]:
        ax.axis("off")
    for ax, label in zip(axes.flat, labels):
        m = results[label]
        polys = PolyCollection(m["corners"], array=m["checker"].astype(float), cmap=PATTERN,
                               edgecolors="none")
        polys.set_clim(0, 1)
        ax.add_collection(polys)
        ax.set_xlim(0, 3)
        ax.set_ylim(0, 2.2)
        ax.set_aspect("equal")
        n = len(m["corners"])
        ax.set_title(f"{label}: {n} points, runout {m['runout']:.3f} m, "
                     f"height {m['height']:.3f} m", fontsize=9)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_series(results, key_x, key_y, ylabel, path, logy=False):
    """One line per run, a colour each; the refined (h = 0.05 m) runs dashed."""
    fig, ax = plt.subplots(figsize=(9, 4.5))
    colours = plt.get_cmap("tab20")
    for index, (label, m) in enumerate(results.items()):
        ax.plot(m[key_x], m[key_y], "--" if "h0.05" in label else "-", color=colours(index % 20),
                label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    if logy:
        ax.set_yscale("log")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def difference(a, b):
    return abs(a - b) / max(abs(b), 1e-12)


def check(results, failed):
    """The violations of what the README quotes (BOUNDS, agreement, splitting's effect)."""
    problems = [f"{label} did not complete (exit {code})" for label, code in failed.items()]
    for label, bands in BOUNDS.items():
        if label not in results:
            continue
        m = results[label]
        values = {"runout": m["runout"], "height": m["height"], "points": m["particles"][-1]}
        for key, (value, band) in bands.items():
            if not abs(values[key] - value) <= band * value:
                problems.append(f"{label}: {key} {values[key]:.4g} outside {value:g} +- "
                                f"{100 * band:g} %")
        # Halving is exact in binary: only the summation order rounds.
        if not m["mass_error"] <= 1e-12:
            problems.append(f"{label}: mass changed by {m['mass_error']:.3g} (relative)")
    for suffix in ["split", "no_split"]:
        e, i = f"explicit_{suffix}", f"implicit_{suffix}"
        if e in results and i in results:
            d = difference(results[i]["runout"], results[e]["runout"])
            if not d <= 0.05:
                problems.append(f"{suffix}: explicit and implicit runouts differ by {100 * d:.1f} %")
    # The talk's point: splitting keeps the voxels from turning into strings (measured 14 and
    # 12.5 against 24 and 25).
    for solver in ["explicit", "implicit"]:
        split, plain = f"{solver}_split", f"{solver}_no_split"
        if split in results and plain in results:
            ratio = results[split]["max_aspect"][-1] / results[plain]["max_aspect"][-1]
            if not ratio <= 0.7:
                problems.append(f"{solver}: largest aspect ratio with splitting is {ratio:.2f}x "
                                "the one without (at most 0.7)")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--talus", default="build/talus")
    parser.add_argument("--out", default="results/column_report")
    parser.add_argument("--refine", action="store_true")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--reuse", action="store_true")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 unless the README's figures hold (BOUNDS)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    results, failed = {}, {}
    for label, overrides in runs(args.refine):
        folder, code = run(args.talus, label, overrides, args.out, args.threads, args.reuse)
        if not os.path.exists(os.path.join(folder, "summary.json")):
            failed[label] = code
            continue
        results[label] = measure(folder)
        if code != 0:
            failed[label] = code

    plot_series(results, "time", "particles", "material points",
                os.path.join(args.out, "particles.png"))
    plot_series(results, "frame_time", "max_aspect", "largest voxel aspect ratio",
                os.path.join(args.out, "aspect_ratio.png"), logy=True)
    pairs = [("explicit_no_split", "explicit_split"), ("implicit_no_split", "implicit_split")]
    for no_split, split in pairs:
        if no_split in results and split in results:
            draw_side_by_side(results, [no_split, split],
                              os.path.join(args.out, f"{split.split('_')[0]}_side_by_side.png"))
    shape_runs = [label for label in ["explicit_split"] + [f"explicit_split_{s}" for s in SHAPES]
                  if label in results]
    draw_side_by_side(results, shape_runs, os.path.join(args.out, "shapes_side_by_side.png"))

    lines = ["# Soil-column collapse: splitting and solver comparison", "",
             f"Case `{CASE}` (Mohr-Coulomb E = 20 MPa, nu = 0.42, rho0 = 1e3 kg/m3, c = 1 kPa, "
             "phi = 42 deg, psi = 0, K0 geostatic; column 1 m x 2 m on a rough base against a "
             "smooth wall; t = 1.5 s). Split runs use alpha = 2, beta = 1/2, gamma = 1, "
             "max_generations = 3. Implicit runs: Newmark dynamics, dt = 0.005 s (cut back "
             "when Newton fails).", "",
             "Runout: the front (largest x of a deformed voxel corner) at the end minus at "
             "t = 0. Height: the largest y of a deformed voxel corner at the end. Aspect "
             "ratio: long-to-short singular value ratio of a voxel's edge matrix.", "",
             "| run | status | points t=0 | points end | splits | largest aspect ratio "
             "(end) | runout [m] | final height [m] | wall time [s] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for label, _ in runs(args.refine):
        if label not in results:
            lines.append(f"| {label} | failed (exit {failed[label]}) | | | | | | | |")
            continue
        m = results[label]
        s = m["summary"]
        status = s["status"] if label not in failed else f"{s['status']} (exit {failed[label]})"
        lines.append(
            f"| {label} | {status} | {int(m['particles'][0])} | {int(m['particles'][-1])} | "
            f"{int(s.get('splits', 0))} | {m['max_aspect'][-1]:.1f} | {m['runout']:.3f} | "
            f"{m['height']:.3f} | {s['wall_seconds']:.1f} |")
    lines += ["", "## Explicit against implicit dynamic", ""]
    for suffix in ["split", "no_split", "split_h0.05"]:
        e, i = f"explicit_{suffix}", f"implicit_{suffix}"
        if e in results and i in results:
            d = difference(results[i]["runout"], results[e]["runout"])
            verdict = "within 5 %" if d <= 0.05 else "NOT within 5 %"
            lines.append(f"* {suffix.replace('_', ' ')}: explicit runout "
                         f"{results[e]['runout']:.3f} m, implicit {results[i]['runout']:.3f} m, "
                         f"difference {100 * d:.1f} % ({verdict}).")
    lines += ["", "## Shape functions", "",
              "The explicit split run with each shape (`solver.shape`; the case's own is "
              "uGIMP), and with `--refine` at h = 0.05 m. Front: the largest x of a deformed "
              "voxel corner at the end.", "",
              "| shape | h [m] | points end | runout [m] | front [m] | final height [m] | "
              "wall time [s] |", "|---|---|---|---|---|---|---|"]
    for shape in ["gimp"] + SHAPES:
        for h, prefix in [(0.1, "explicit_split"), (0.05, "explicit_split_h0.05")]:
            label = prefix if shape == "gimp" else f"{prefix}_{shape}"
            if label not in results:
                continue
            m = results[label]
            lines.append(f"| {shape} | {h:g} | {int(m['particles'][-1])} | {m['runout']:.3f} | "
                         f"{m['front']:.3f} | {m['height']:.3f} | "
                         f"{m['summary']['wall_seconds']:.1f} |")
    lines += ["", "## Pictures", "",
              "* `particles.png`: material points over time.",
              "* `aspect_ratio.png`: largest voxel aspect ratio per frame.",
              "* `explicit_side_by_side.png`, `implicit_side_by_side.png`: final deformed "
              "voxels with the checker pattern of the initial lattice, without (left) and with "
              "(right) splitting.",
              "* `shapes_side_by_side.png`: the explicit split run's final voxels with each "
              "shape function.", ""]
    with open(os.path.join(args.out, "report.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))
    if args.check:
        problems = check(results, failed)
        if problems:
            print("check failed:\n  " + "\n  ".join(problems), file=sys.stderr)
            return 1
        print("check: the README's figures hold")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
