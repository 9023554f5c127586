#!/usr/bin/python3
"""Draw frames of a Talus run.h5 as deformed voxels (or dots) coloured by a field or a pattern.

Called by `talus render`, which validates the request first; the arguments here are already
resolved to datasets and columns:

    /usr/bin/python3 scripts/render.py RUN.h5 --frames 0 5 9 -o OUT.png
        (--dataset stress --column 1 --label "stress xy [Pa]" | --pattern checker)
        [--mode voxels|points] [--sequence] [--slice z=0.5 | --view iso|x|y|z]
        [--clim LO HI] [--log] [--crop X0 Y0 X1 Y1] [--delta]

One PNG per frame: OUT.png for a single frame; with --sequence OUT_000000.png, OUT_000005.png,
... named by frame number, all with the same colour range so the sequence can be animated.
Axes are in model units (m); the title gives the case, the field and the frame's time.
A 3D run (3-column positions) is drawn as a slice (--slice: the voxels or points the plane
cuts, in the plane's axes) or as the outer faces of its voxels (or its points) seen from --view;
the geometry is scripts/render3d.py's. --clim fixes the colour range, --log makes the colour
scale logarithmic (values at or below zero take the lowest colour), --crop draws only the box
(X0, Y0)-(X1, Y1) of the picture's axes at the figure's full size, and --delta colours each
point by its change from frame 0.
"""

import argparse
import os
import sys
from dataclasses import dataclass

import h5py
import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import ListedColormap, LogNorm, Normalize  # noqa: E402
from mpl_toolkits.axes_grid1 import make_axes_locatable  # noqa: E402

import render3d  # noqa: E402

PATTERN_COLOURS = ListedColormap(["#f2f2f2", "#2b5d8a"])


@dataclass
class Picture:
    """What one frame's picture draws: polygons (quadrilaterals, slice polygons, faces) or dots
    in picture coordinates, their colour values, and how the axes are laid out."""
    values: np.ndarray
    polygons: object = None  # (n, 4, 2) array or a list of (k, 2) arrays
    points: np.ndarray = None  # (n, 2)
    shade: np.ndarray = None  # per polygon brightness factor (the 3D faces' lighting)
    spacing: float = None  # 3D dots: drawn 0.8 particle spacings wide, not at a fixed size
    labels: tuple = ("x [m]", "y [m]")  # None: an oblique view, no model axes
    invert: tuple = (False, False)
    note: str = ""  # a second title line; 3D pictures have one
    lo: np.ndarray = None
    hi: np.ndarray = None

    def __post_init__(self):
        if self.lo is None:  # a slice gives its frame's bounds; everything else is an array
            every = np.reshape(self.points if self.polygons is None else self.polygons, (-1, 2))
            self.lo, self.hi = every.min(axis=0), every.max(axis=0)


def frame_values(group, args):
    """The colour value of every particle of a frame (less frame 0's with --delta)."""
    if args.pattern:
        return group["voxels"][args.pattern][()].astype(float)
    data = group[args.dataset][()]
    if args.delta:
        data = data - args.base  # talus render checked that the frames have the same points
    if data.ndim == 1:
        return data.astype(float)
    if args.column == "norm":
        return np.linalg.norm(data, axis=1)
    return data[:, int(args.column)]


def norm(limits, args):
    """The colour scale: linear, or logarithmic with --log."""
    return LogNorm(*limits) if args.log else Normalize(*limits)


def frame_shapes(group, mode):
    """Voxel quadrilaterals (n, 4, 2) or particle positions (n, 2)."""
    if mode == "voxels":
        return group["voxels"]["corners"][()].reshape(-1, 4, 2)
    return group["position"][()]


def picture(group, args):
    """The picture of a frame: 2D as it is, 3D by slice or view."""
    values = frame_values(group, args)
    if group["position"].shape[1] == 3:
        return picture_3d(group, values, args)
    shapes = frame_shapes(group, args.mode)
    # An axisymmetric run is drawn in its meridian plane: x is the radius, y the axis.
    labels = ("r [m]", "z [m]") if args.axisymmetric else ("x [m]", "y [m]")
    if args.mode == "voxels":
        return Picture(values, polygons=shapes, labels=labels)
    return Picture(values, points=shapes, labels=labels)


def drawn_values(group, args):
    """The values a frame's picture colours (all particles' in 2D), without its geometry."""
    if group["position"].shape[1] == 2:
        return frame_values(group, args)
    return picture(group, args).values


def picture_3d(group, values, args):
    points = group["position"][()]
    corners = group["voxels"]["corners"][()].reshape(-1, 8, 3) if args.mode == "voxels" else None
    if args.slice:
        axis, value = render3d.AXES.index(args.slice[0]), float(args.slice[2:])
        h, v = render3d.PLANE_AXES[axis]
        every = (points if corners is None else corners).reshape(-1, 3)
        frame = {"lo": every[:, [h, v]].min(axis=0), "hi": every[:, [h, v]].max(axis=0),
                 "labels": (f"{render3d.AXES[h]} [m]", f"{render3d.AXES[v]} [m]")}
        where = f"slice {args.slice[0]} = {value:g}"
        if corners is None:
            spacing = render3d.point_spacing(points)
            cut = render3d.slice_points(points, axis, value, spacing)
            return Picture(values[cut], points=points[cut][:, [h, v]], spacing=spacing,
                           note=f"{where}: {len(cut)} points within half a spacing", **frame)
        cut, polygons = render3d.slice_voxels(corners, axis, value)
        return Picture(values[cut], polygons=polygons, note=f"{where}: {len(cut)} voxels cut",
                       **frame)
    right, up, towards = render3d.view_basis(args.view)
    if corners is None:
        order = np.argsort(points @ towards, kind="stable")  # far to near
        shapes, values, shade = points[order] @ np.stack([right, up], axis=1), values[order], None
        spacing, note = render3d.point_spacing(points), f"points, {args.view} view"
    else:
        shapes, faces, normals = render3d.visible_faces(corners, args.view)
        # Light from above, a little left of the viewer; a face turned to the viewer (and the
        # top in the iso view) keeps its colour map colour, the others are darker.
        light = -0.15 * right + 0.7 * up + 0.7 * towards
        shade = np.clip(0.55 + 0.45 * (normals @ light) / (towards @ light), 0.2, 1.0)
        values, spacing = values[faces // 6], None
        note = f"outer faces, {args.view} view"
    labels, invert = None, (False, False)
    if args.view != "iso":
        # A view along an axis keeps the model's axes: picture x and y are +-1 times one
        # coordinate, drawn reversed where the view shows it so.
        a, b = int(np.argmax(np.abs(right))), int(np.argmax(np.abs(up)))
        shapes = shapes * np.array([right[a], up[b]])
        labels = (f"{render3d.AXES[a]} [m]", f"{render3d.AXES[b]} [m]")
        invert = (right[a] < 0, up[b] < 0)
    return Picture(values, labels=labels, invert=invert, note=note, shade=shade, spacing=spacing,
                   **{"points" if corners is None else "polygons": shapes})


def output_name(base, frame, sequence):
    if not sequence:
        return base
    stem, ext = os.path.splitext(base)
    return f"{stem}_{frame:06d}{ext}"


def axis_triad(ax, view):
    """Arrows of the model axes in a corner of an oblique view, which has no model axes."""
    right, up, _ = render3d.view_basis(view)
    for k, name in enumerate(render3d.AXES):
        tip = 0.09 + 0.06 * np.array([right[k], up[k]])
        ax.annotate("", xy=tip, xytext=(0.09, 0.09), xycoords="axes fraction",
                    arrowprops={"arrowstyle": "->", "color": "#555555", "lw": 1.0})
        ax.annotate(name, xy=0.09 + 0.075 * np.array([right[k], up[k]]),
                    xycoords="axes fraction", ha="center", va="center", fontsize=8)


def draw(group, frame, pic, limits, args, case):
    lo, hi = pic.lo, pic.hi
    if args.crop:
        lo, hi = np.array(args.crop[:2]), np.array(args.crop[2:])
    # The figure follows the body's aspect ratio, 9 inches along its longer side; a slender body
    # gets its colour bar below. What is left around the axes is cut when the figure is saved.
    aspect = (hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-300)
    wide = aspect < 0.5
    size = ((9, min(9, max(3.5, 9 * aspect + (2.2 if wide else 0.8)))) if aspect <= 1
            else (min(9, max(4.5, 9 / aspect + 2.0)), 9))
    fig, ax = plt.subplots(figsize=size, dpi=args.dpi)
    cmap = PATTERN_COLOURS if args.pattern else "viridis"
    if args.log:  # a log scale masks values at or below zero; they take the lowest colour
        pic.values = np.maximum(pic.values, limits[0])
    if pic.polygons is not None and pic.shade is None:
        art = PolyCollection(pic.polygons, array=pic.values, cmap=cmap, edgecolors="face",
                             linewidths=0.2, norm=norm(limits, args))
        ax.add_collection(art)
    elif pic.polygons is not None:
        # Lit faces: the colour map's colour darkened by the face's turn away from the light.
        art = ScalarMappable(norm(limits, args), plt.get_cmap(cmap))
        colours = art.to_rgba(pic.values)
        colours[:, :3] *= pic.shade[:, None]
        ax.add_collection(PolyCollection(pic.polygons, facecolors=colours, edgecolors=colours,
                                         linewidths=0.2))
    else:
        art = ax.scatter(pic.points[:, 0], pic.points[:, 1], c=pic.values, cmap=cmap, s=4,
                         linewidths=0, norm=norm(limits, args))
    pad = 0 if args.crop else 0.03 * max(hi - lo) + (0.5 * pic.spacing if pic.spacing else 0.0)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    if pic.invert[0]:
        ax.invert_xaxis()
    if pic.invert[1]:
        ax.invert_yaxis()
    ax.set_aspect("equal")
    if pic.labels is None:
        ax.set_xticks([])
        ax.set_yticks([])
        axis_triad(ax, args.view)
    else:
        ax.set_xlabel(pic.labels[0])
        ax.set_ylabel(pic.labels[1])
    time = float(group.attrs["time"])
    what = f"{args.pattern} pattern" if args.pattern else args.label
    # Two short lines rather than one long one: a narrow figure would clip it.
    title = f"{case}: {what}\nt = {time:.6g} s (frame {frame})"
    ax.set_title(f"{title}, {pic.note}" if pic.note else title, fontsize=11)
    if not args.pattern:  # a pattern is two dummy colours, nothing to read off a bar
        # The bar as long as the axes' side it stands beside, not the figure's.
        cax = make_axes_locatable(ax).append_axes("bottom" if wide else "right",
                                                  size="6%" if wide else "4%",
                                                  pad=0.6 if wide else 0.15)
        bar = fig.colorbar(art, cax=cax, label=args.label,
                           orientation="horizontal" if wide else "vertical")
        if pic.note:  # 3D: a power of ten beyond 1e-3 .. 1e4 keeps a horizontal bar's ticks apart
            bar.formatter.set_powerlimits((-3, 4))
    fig.tight_layout()
    if pic.spacing:
        ax.apply_aspect()
        points_per_unit = ax.get_window_extent().width / np.ptp(ax.get_xlim()) * 72 / args.dpi
        art.set_sizes([(0.8 * pic.spacing * points_per_unit) ** 2])
    name = output_name(args.output, frame, args.sequence)
    fig.savefig(name, bbox_inches="tight", pad_inches=0.1)
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
    ap.add_argument("--slice", help="AXIS=VALUE, a 3D run's slice plane")
    ap.add_argument("--view", choices=sorted(render3d.VIEWS), default="iso")
    ap.add_argument("--sequence", action="store_true")
    ap.add_argument("--dpi", type=int, default=150)
    ap.add_argument("--axisymmetric", action="store_true",
                    help="an axisymmetric run: the axes are r and z")
    ap.add_argument("--clim", type=float, nargs=2, help="the colour range LO HI")
    ap.add_argument("--log", action="store_true", help="a logarithmic colour scale")
    ap.add_argument("--crop", type=float, nargs=4, help="X0 Y0 X1 Y1 of the picture's axes")
    ap.add_argument("--delta", action="store_true", help="the change from frame 0")
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
        if args.delta:
            args.base = f["frames"]["000000"][args.dataset][()]
            args.label = "change of " + args.label + " since frame 0"
        # The values drawn (a slice's, the outer faces'), kept over the frames for one colour
        # range; the geometry is built again when drawn so only one frame's is held at a time.
        values = {k: drawn_values(f["frames"][f"{k:06d}"], args) for k in args.frames}
        if args.pattern:
            limits = (0.0, 1.0)
        elif args.clim:
            limits = tuple(args.clim)
        else:
            # One colour range for all frames: a sequence reads as one animation.
            drawn = [v for v in values.values() if v.size] or [np.zeros(1)]
            lo = min(float(v.min()) for v in drawn)
            hi = max(float(v.max()) for v in drawn)
            if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1e-300):
                lo, hi = lo - 0.5 * max(abs(lo), 1.0), hi + 0.5 * max(abs(hi), 1.0)
            if args.log:  # the smallest positive value drawn: a log scale cannot start at 0
                positive = [float(v[v > 0].min()) for v in drawn if (v > 0).any()]
                if not positive:
                    sys.exit("render.py: --log needs positive values; the field has none here")
                lo = min(positive)
                hi = max(hi, lo * 10)
            limits = (lo, hi)
        for k in args.frames:
            group = f["frames"][f"{k:06d}"]
            draw(group, k, picture(group, args), limits, args, case)


if __name__ == "__main__":
    main()
