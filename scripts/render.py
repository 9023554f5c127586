#!/usr/bin/python3
"""Draw frames of a Talus run.h5 as deformed voxels (or dots) coloured by a field or a pattern.

Called by `talus render`, which validates the request first; the arguments here are already
resolved to datasets and columns:

    /usr/bin/python3 scripts/render.py RUN.h5 --frames 0 5 9 -o OUT.png
        (--dataset stress --column 1 --label "stress xy [Pa]" | --pattern checker)
        [--mode voxels|points] [--sequence]

One PNG per frame: OUT.png for a single frame; with --sequence OUT_000000.png, OUT_000005.png,
... named by frame number, all with the same colour range so the sequence can be animated.
Axes are in model units (m); the title gives the case, the field and the frame's time.
"""

import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

PATTERN_COLOURS = ListedColormap(["#f2f2f2", "#2b5d8a"])


def frame_values(group, args):
    """The colour value of every particle of a frame."""
    if args.pattern:
        return group["voxels"][args.pattern][()].astype(float)
    data = group[args.dataset][()]
    if data.ndim == 1:
        return data.astype(float)
    if args.column == "norm":
        return np.linalg.norm(data, axis=1)
    return data[:, int(args.column)]


def frame_shapes(group, mode):
    """Voxel quadrilaterals (n, 4, 2) or particle positions (n, 2)."""
    if mode == "voxels":
        return group["voxels"]["corners"][()].reshape(-1, 4, 2)
    return group["position"][()]


def output_name(base, frame, sequence):
    if not sequence:
        return base
    stem, ext = os.path.splitext(base)
    return f"{stem}_{frame:06d}{ext}"


def draw(f, frame, values, limits, args, case):
    group = f["frames"][f"{frame:06d}"]
    shapes = frame_shapes(group, args.mode)
    points = shapes.reshape(-1, 2)
    lo, hi = points.min(axis=0), points.max(axis=0)
    # The figure follows the body's aspect ratio; a slender body gets its colour bar below.
    aspect = (hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-300)
    wide = aspect < 0.5
    fig, ax = plt.subplots(figsize=(9, min(9, max(3.5, 9 * aspect + (2.2 if wide else 0.8)))),
                           dpi=args.dpi)
    cmap = PATTERN_COLOURS if args.pattern else "viridis"
    if args.mode == "voxels":
        art = PolyCollection(shapes, array=values, cmap=cmap, edgecolors="face", linewidths=0.2)
        art.set_clim(*limits)
        ax.add_collection(art)
    else:
        art = ax.scatter(shapes[:, 0], shapes[:, 1], c=values, cmap=cmap, s=4, linewidths=0,
                         vmin=limits[0], vmax=limits[1])
    pad = 0.03 * max(hi - lo)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    time = float(group.attrs["time"])
    what = f"{args.pattern} pattern" if args.pattern else args.label
    ax.set_title(f"{case}: {what}, t = {time:.6g} s (frame {frame})")
    if not args.pattern:  # a pattern is two dummy colours, nothing to read off a bar
        fig.colorbar(art, ax=ax, label=args.label, orientation="horizontal" if wide else "vertical",
                     fraction=0.08 if wide else 0.046, pad=0.25 if wide else 0.04)
    fig.tight_layout()
    name = output_name(args.output, frame, args.sequence)
    fig.savefig(name)
    plt.close(fig)
    print(name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("h5")
    ap.add_argument("--frames", type=int, nargs="+", required=True)
    ap.add_argument("--dataset")
    ap.add_argument("--column", default="")
    ap.add_argument("--label", default="")
    ap.add_argument("--pattern")
    ap.add_argument("--mode", choices=["voxels", "points"], default="voxels")
    ap.add_argument("--sequence", action="store_true")
    ap.add_argument("--dpi", type=int, default=150)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    if bool(args.dataset) == bool(args.pattern):
        sys.exit("render.py: give exactly one of --dataset and --pattern")

    with h5py.File(args.h5, "r") as f:
        case = f["metadata"].attrs["case_name"]
        if args.dataset:
            units = f["frames"][f"{args.frames[0]:06d}"][args.dataset].attrs.get("units", "1")
            if units != "1":
                args.label += f" [{units}]"
        values = {k: frame_values(f["frames"][f"{k:06d}"], args) for k in args.frames}
        if args.pattern:
            limits = (0.0, 1.0)
        else:
            # One colour range for all frames: a sequence reads as one animation.
            lo = min(float(v.min()) for v in values.values() if v.size)
            hi = max(float(v.max()) for v in values.values() if v.size)
            if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1e-300):
                lo, hi = lo - 0.5 * max(abs(lo), 1.0), hi + 0.5 * max(abs(hi), 1.0)
            limits = (lo, hi)
        for k in args.frames:
            draw(f, k, values[k], limits, args, case)


if __name__ == "__main__":
    main()
