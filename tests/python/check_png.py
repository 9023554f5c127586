#!/usr/bin/python3
"""Look inside a picture `talus render` drew, so that a test checks what it shows, not only
that a file exists.

    /usr/bin/python3 tests/python/check_png.py pattern OUT.png   # checker pattern on the voxels
    /usr/bin/python3 tests/python/check_png.py field OUT.png     # a field in the viridis map
    /usr/bin/python3 tests/python/check_png.py drawn OUT.png     # points in the viridis map
    /usr/bin/python3 tests/python/check_png.py shaded OUT.png    # lit 3D faces, coloured
    /usr/bin/python3 tests/python/check_png.py lowest OUT.png    # one colour: the map's lowest
    /usr/bin/python3 tests/python/check_png.py one OUT.png       # one colour of the map
    /usr/bin/python3 tests/python/check_png.py differ A.png B.png

Only the axes are looked at (the box inside the dark spines, the widest of the boxes the
figure has, so a colour bar does not count). pattern: both colours of scripts/render.py's
pattern map cover at least 3 % of the axes each, in a ratio within [0.8, 1.25] (a checker is
half dark, half light; an empty plot, a plot of one colour or of the wrong field fails). field:
at least 20 distinct colours of matplotlib's viridis map cover at least 2 % of the axes (the
points or voxels are drawn and coloured by a varying field). drawn: viridis colours cover at
least 0.5 % of the axes (dots of a uniform field are drawn). shaded: at least 20 distinct
coloured (not grey: channels spread by 40 or more of 255) colours cover at least 2 % of the
axes (3D faces are the map's colours darkened by their lighting, so not the map's own). lowest:
viridis's lowest colour covers at least 2 % of the axes and the rest of the map (its colours
past the first 8 of 256) less than a tenth of that (a field below --clim, a change that is
zero); one: the same for the map's most common colour and the map's colours more than 8 of
256 away from it (a uniform field in the middle of its range). differ:
the two pictures are not the same image (frames of a moving body).
Exits 0 when the picture holds, 1 with a message otherwise.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import colormaps  # noqa: E402

PATTERN = [(0xF2, 0xF2, 0xF2), (0x2B, 0x5D, 0x8A)]  # scripts/render.py PATTERN_COLOURS


def rgb(path):
    """The picture's pixels as integers 0-255, rows x columns x 3."""
    image = mpimg.imread(path)
    if image.dtype != np.uint8:
        image = np.round(image * 255).astype(np.int32)
    return image[:, :, :3]


def widest_gap(lines):
    """(first, last) pixel inside the widest gap between consecutive spine lines."""
    runs = np.split(lines, np.where(np.diff(lines) > 1)[0] + 1)
    edges = [(r[-1] + 1, n[0] - 1) for r, n in zip(runs, runs[1:])]
    return max(edges, key=lambda e: e[1] - e[0])


def axes_pixels(path):
    """The pixels inside the axes' spines, as an n x 3 array."""
    image = rgb(path)
    # The spines: dark neutral grey (matplotlib draws them anti-aliased, about 42 of 255).
    black = (image.max(axis=2) < 100) & (image.max(axis=2) - image.min(axis=2) <= 2)
    columns = np.where(black.sum(axis=0) > 0.3 * image.shape[0])[0]
    rows = np.where(black.sum(axis=1) > 0.3 * image.shape[1])[0]
    if len(columns) < 2 or len(rows) < 2:
        fail(f"{path}: no axes box found")
    (c0, c1), (r0, r1) = widest_gap(columns), widest_gap(rows)
    return image[r0:r1 + 1, c0:c1 + 1].reshape(-1, 3)


def fail(message):
    print(f"check_png: FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def check_pattern(path):
    pixels = axes_pixels(path)
    counts = [int(np.all(pixels == np.array(c), axis=1).sum()) for c in PATTERN]
    fractions = [c / len(pixels) for c in counts]
    if min(fractions) < 0.03:
        fail(f"{path}: pattern colours cover {fractions[0]:.3f} and {fractions[1]:.3f}")
    ratio = counts[1] / counts[0]
    if not 0.8 <= ratio <= 1.25:
        fail(f"{path}: dark / light pattern pixels = {ratio:.3f}, not about 1")
    print(f"check_png: {path}: pattern {fractions[0]:.3f} / {fractions[1]:.3f}, ratio {ratio:.3f}")


def check_field(path, min_colours=20, min_cover=0.02):
    pixels = axes_pixels(path)
    table = np.round(colormaps["viridis"](np.linspace(0, 1, 256))[:, :3] * 255).astype(np.int32)
    colours, counts = np.unique(pixels, axis=0, return_counts=True)
    in_map = [n for c, n in zip(colours, counts) if np.abs(table - c).sum(axis=1).min() <= 3]
    covered = sum(in_map) / len(pixels)
    if len(in_map) < min_colours or covered < min_cover:
        fail(f"{path}: {len(in_map)} viridis colours covering {covered:.3f} of the axes")
    print(f"check_png: {path}: {len(in_map)} viridis colours over {covered:.3f}")


def check_shaded(path):
    pixels = axes_pixels(path)
    coloured = pixels[pixels.max(axis=1) - pixels.min(axis=1) >= 40]
    distinct = len(np.unique(coloured, axis=0))
    covered = len(coloured) / len(pixels)
    if distinct < 20 or covered < 0.02:
        fail(f"{path}: {distinct} coloured colours covering {covered:.3f} of the axes")
    print(f"check_png: {path}: {distinct} coloured colours over {covered:.3f}")


def check_one(path, lowest_only):
    pixels = axes_pixels(path)
    table = np.round(colormaps["viridis"](np.linspace(0, 1, 256))[:, :3] * 255).astype(np.int32)
    colours, counts = np.unique(pixels, axis=0, return_counts=True)
    nearest = np.abs(colours[:, None, :] - table[None, :, :]).sum(axis=2)
    in_map = nearest.min(axis=1) <= 3
    index = nearest.argmin(axis=1)
    if lowest_only or not in_map.any():
        dominant = 0
    else:
        dominant = index[in_map][np.argmax(counts[in_map])]
    one = counts[in_map & (index == dominant)].sum() / len(pixels)
    rest = counts[in_map & (np.abs(index - dominant) > 8)].sum() / len(pixels)
    if one < 0.02 or rest >= 0.1 * one:
        fail(f"{path}: colour {dominant} of the map covers {one:.3f}, the rest of it {rest:.3f}")
    print(f"check_png: {path}: colour {dominant} of the map over {one:.3f}, the rest {rest:.4f}")


def check_differ(a, b):
    pa, pb = rgb(a).reshape(-1, 3), rgb(b).reshape(-1, 3)
    if pa.shape == pb.shape and np.array_equal(pa, pb):
        fail(f"{a} and {b} are the same picture")
    print(f"check_png: {a} and {b} differ")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "pattern":
        check_pattern(sys.argv[2])
    elif len(sys.argv) == 3 and sys.argv[1] == "field":
        check_field(sys.argv[2])
    elif len(sys.argv) == 3 and sys.argv[1] == "drawn":
        check_field(sys.argv[2], min_colours=1, min_cover=0.005)
    elif len(sys.argv) == 3 and sys.argv[1] == "shaded":
        check_shaded(sys.argv[2])
    elif len(sys.argv) == 3 and sys.argv[1] in ("lowest", "one"):
        check_one(sys.argv[2], sys.argv[1] == "lowest")
    elif len(sys.argv) == 4 and sys.argv[1] == "differ":
        check_differ(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
