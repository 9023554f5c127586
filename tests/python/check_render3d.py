#!/usr/bin/python3
"""Checks of the 3D geometry of `talus render` (scripts/render3d.py) against answers known
without it: lattices of voxels built here, and optionally a run's box.

    /usr/bin/python3 tests/python/check_render3d.py [RUN.h5 NX NY NZ]

Built here: an nx x ny x nz box has 2 (nx ny + ny nz + nz nx) outer faces, also when smoothly
deformed and rotated, and a random set of lattice cells has as many as it has cell faces
without a neighbouring cell; a slice cuts one layer of voxels (also along voxel faces and at the
box's faces) with the box's cross-section as total area; a cube turned 45 degrees about x cut
through its centre gives a 1 x sqrt(2) rectangle; the iso view shows three sides of the box,
far to near. With RUN.h5, a run of an undeformed box of NX x NY x NZ points with voxels: frame
0 gives the exact counts and areas, the last frame the same face count and a cross-section
within 3 %, with one polygon per voxel that straddles the plane.
Exits 0 when all hold, 1 with the failed check otherwise.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import render3d  # noqa: E402

SIGNS = np.array([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
                  (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)], dtype=float)
failures = []


def check(ok, what):
    print(f"check_render3d: {'ok' if ok else 'FAIL'}: {what}")
    if not ok:
        failures.append(what)


def voxels(cells, h, mapping=None):
    """Voxels of integer lattice cells (m, 3) of side h; mapping(X) -> (x, grad) deforms them
    as the solver does: corners x_p + grad(X_p) (X_c - X_p)."""
    centres = (cells + 0.5) * h
    offsets = 0.5 * h * SIGNS
    if mapping is None:
        return centres[:, None, :] + offsets[None]
    x, grad = mapping(centres)
    return x[:, None, :] + np.einsum("nij,cj->nci", grad, offsets)


def bend(X):
    """A smooth deformation (a few % of strain varying over the body) then a rotation."""
    a = 0.04
    c, s = np.cos(0.5), np.sin(0.5)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    u = a * np.stack([X[:, 1] ** 2, 0.5 * X[:, 2] * X[:, 0], np.sin(X[:, 0])], axis=1)
    grad = np.zeros((len(X), 3, 3)) + np.eye(3)
    grad[:, 0, 1] += 2 * a * X[:, 1]
    grad[:, 1, 0] += 0.5 * a * X[:, 2]
    grad[:, 1, 2] += 0.5 * a * X[:, 0]
    grad[:, 2, 0] += a * np.cos(X[:, 0])
    return (X + u) @ R.T, R[None] @ grad


def box_cells(n):
    return np.array(np.meshgrid(*[np.arange(k) for k in n], indexing="ij")).reshape(3, -1).T


def expected_outer(cells):
    occupied = {tuple(c) for c in cells}
    return sum(tuple(c + d) not in occupied
               for c in cells for d in np.vstack([np.eye(3, dtype=int), -np.eye(3, dtype=int)]))


def check_faces():
    n = (5, 4, 3)
    outer = 2 * (n[0] * n[1] + n[1] * n[2] + n[2] * n[0])
    box = voxels(box_cells(n), 0.1)
    check(len(render3d.outer_faces(box)) == outer, f"box {n}: {outer} outer faces")
    bent = voxels(box_cells(n), 1.0, bend)
    check(len(render3d.outer_faces(bent)) == outer, f"bent, turned box {n}: {outer} outer faces")
    rng = np.random.default_rng(7)
    cells = box_cells((5, 5, 5))[rng.random(125) < 0.6]
    expected = expected_outer(cells)
    for name, corners in (("", voxels(cells, 0.1)), ("bent ", voxels(cells, 1.0, bend))):
        got = len(render3d.outer_faces(corners))
        check(got == expected, f"{name}random cells: {got} outer faces, {expected} expected")
    shown, faces, _ = render3d.visible_faces(bent, "iso")
    sides = n[0] * n[1] + n[1] * n[2] + n[2] * n[0]
    check(len(shown) == sides, f"iso view of box {n}: {len(shown)} faces shown, {sides} expected")
    depth = render3d.face_geometry(bent)[1][faces] @ render3d.view_basis("iso")[2]
    check(np.all(np.diff(depth) >= 0), "the faces are drawn far to near")
    for view, side, count in (("x", 5, n[1] * n[2]), ("y", 3, n[0] * n[2]), ("z", 1, n[0] * n[1])):
        faces = render3d.visible_faces(box, view)[1]
        check(len(faces) == count and np.all(faces % 6 == side),
              f"the {view} view shows the {count} faces of the +{view} side")


def check_slice(corners, axis, value, count, area, what, rel=1e-9):
    cut, polygons = render3d.slice_voxels(corners, axis, value)
    total = sum(render3d.polygon_area(p) for p in polygons)
    check(len(polygons) == len(cut) == count and abs(total - area) <= rel * area,
          f"{what}: {len(polygons)} polygons ({count} expected), area {total:.9g} ({area:.9g})")


def check_slices():
    n, h = (5, 4, 3), 0.1
    box = voxels(box_cells(n), h)
    section = n[0] * h * n[1] * h
    for value, where in ((0.14, "inside a layer"), (0.2, "along voxel faces"),
                         (0.0, "at the bottom face"), (0.3, "at the top face")):
        check_slice(box, 2, value, n[0] * n[1], section, f"slice z = {value} {where}")
    check_slice(box, 0, 0.25, n[1] * n[2], n[1] * n[2] * h * h, "slice x = 0.25")
    c = np.sqrt(0.5)
    cube = (SIGNS * 0.5) @ np.array([[1, 0, 0], [0, c, -c], [0, c, c]]).T
    # The plane is nudged 1e-9 off the centre (render3d.NUDGE), which narrows the cut by as much.
    check_slice(cube[None], 2, 0.0, 1, np.sqrt(2), "cube turned 45 degrees about x, cut at z = 0",
                rel=1e-8)
    points = (box_cells(n) + 0.5) * h
    for value in (0.14, 0.2):
        got = len(render3d.slice_points(points, 2, value, render3d.point_spacing(points)))
        check(got == n[0] * n[1], f"points within half a spacing of z = {value}: {got}")
    check(len(render3d.slice_voxels(box, 2, 0.5)[0]) == 0, "a plane above the box cuts nothing")


def check_run(path, n):
    import h5py
    with h5py.File(path, "r") as f:
        frames = f["frames"]
        first, last = frames["000000"], frames[sorted(frames)[-1]]
        corners0 = first["voxels"]["corners"][()].reshape(-1, 8, 3)
        corners1 = last["voxels"]["corners"][()].reshape(-1, 8, 3)
    lo, hi = corners0.reshape(-1, 3).min(axis=0), corners0.reshape(-1, 3).max(axis=0)
    size = hi - lo
    mid = 0.5 * (lo + hi)
    outer = 2 * (n[0] * n[1] + n[1] * n[2] + n[2] * n[0])
    check(len(corners0) == n[0] * n[1] * n[2], f"the run has {n[0] * n[1] * n[2]} voxels")
    for name, corners in (("frame 0", corners0), ("last frame", corners1)):
        got = len(render3d.outer_faces(corners))
        check(got == outer, f"run, {name}: {got} outer faces, {outer} expected")
    for axis in range(3):
        a, b = render3d.PLANE_AXES[axis]
        value = mid[axis] + 0.1 * size[axis] / n[axis]
        area = size[a] * size[b]
        count = n[a] * n[b]
        check_slice(corners0, axis, value, count, area, f"run, frame 0, slice {'xyz'[axis]}")
        along = corners1[:, :, axis]
        straddle = int(((along.min(axis=1) < value) & (along.max(axis=1) > value)).sum())
        check_slice(corners1, axis, value, straddle, area, f"run, last frame, slice "
                    f"{'xyz'[axis]}", rel=0.03)


def main():
    check_faces()
    check_slices()
    if len(sys.argv) == 5:
        check_run(sys.argv[1], [int(a) for a in sys.argv[2:]])
    elif len(sys.argv) != 1:
        sys.exit(__doc__)
    if failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
