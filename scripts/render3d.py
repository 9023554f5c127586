"""Geometry of `talus render` for 3D runs: plane slices through the deformed voxels (or points),
the voxel faces on a body's outer surface and the projection of an oblique view. Plain numpy, no
drawing: scripts/render.py draws with it, tests/python/check_render3d.py tests it.

Voxels are hexahedra, an (n, 8, 3) array in the corner order of src/post/voxels.cpp: corners
0-3 on the initial -z side, counter-clockwise seen from +z from the (-, -) corner ((-, -),
(+, -), (+, +), (-, +) in x, y), corners 4-7 the same on the +z side (VTK's hexahedron order).
A voxel is its particle's lattice box mapped by F, so it is a parallelepiped: convex, and a
plane cuts it in one convex polygon.
"""

import itertools

import numpy as np

AXES = "xyz"
# A slice's picture axes (horizontal, vertical): y stays vertical when it is in the plane.
PLANE_AXES = {0: (2, 1), 1: (0, 2), 2: (0, 1)}
# Directions towards the viewer. y is up in Talus (gravity [0, -g, 0]); iso looks at the front
# (+z), right (+x) and top (+y) faces.
VIEWS = {"iso": (1.0, 1.0, 1.0), "x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
EDGES = np.array([(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
                  (0, 4), (1, 5), (2, 6), (3, 7)])
# The six faces -z, +z, -y, +y, -x, +x, each counter-clockwise seen from outside.
FACES = np.array([(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (3, 7, 6, 2), (0, 4, 7, 3),
                  (1, 2, 6, 5)])
# A plane exactly along voxel faces is moved this far (relative to the voxel size) towards the
# body's middle, so it cuts one layer, not two nor none, whatever the rounding of the corners.
NUDGE = 1e-9


def voxel_size(corners):
    """Edge of the cube of each voxel's volume (the particle spacing of an undeformed lattice)."""
    edges = corners[:, [1, 3, 4]] - corners[:, [0]]
    return np.abs(np.linalg.det(edges)) ** (1.0 / 3.0)


def nudged(value, size, lo, hi):
    """The plane's coordinate moved by NUDGE voxel sizes towards the middle of [lo, hi]."""
    return value + (NUDGE * size if value < 0.5 * (lo + hi) else -NUDGE * size)


def slice_voxels(corners, axis, value):
    """Where the plane coordinate[axis] = value cuts the hexahedra (n, 8, 3): the indices of
    the voxels cut and one convex polygon each, in the plane's PLANE_AXES, counter-clockwise.
    Voxels the plane does not cross are left out."""
    if len(corners) == 0:
        return np.zeros(0, dtype=int), []
    along = corners[:, :, axis]
    plane = nudged(value, float(np.median(voxel_size(corners))), along.min(), along.max())
    d = along - plane
    cut = np.where((d.min(axis=1) < 0) & (d.max(axis=1) > 0))[0]
    c, d = corners[cut], d[cut]
    d0, d1 = d[:, EDGES[:, 0]], d[:, EDGES[:, 1]]
    crossing = d0 * d1 < 0
    t = np.where(crossing, d0 / np.where(crossing, d0 - d1, 1.0), 0.0)
    on_edges = c[:, EDGES[:, 0]] + t[:, :, None] * (c[:, EDGES[:, 1]] - c[:, EDGES[:, 0]])
    # Candidates: the 12 edge crossings and the corners that lie on the plane.
    points = np.concatenate([on_edges, c], axis=1)[:, :, list(PLANE_AXES[axis])]
    valid = np.concatenate([crossing, d == 0], axis=1)
    count = valid.sum(axis=1)
    centre = (points * valid[:, :, None]).sum(axis=1) / count[:, None]
    angle = np.arctan2(points[:, :, 1] - centre[:, None, 1], points[:, :, 0] - centre[:, None, 0])
    order = np.argsort(np.where(valid, angle, np.inf), axis=1)
    polygons = [points[i, order[i, :count[i]]] for i in range(len(cut))]
    return cut, polygons


def point_spacing(points, samples=200):
    """The median distance to the nearest other point, over up to `samples` points spread
    through the array: the particle spacing of a lattice, robust to a few split points."""
    if len(points) < 2:
        return 0.0
    pick = points[np.linspace(0, len(points) - 1, min(samples, len(points))).astype(int)]
    nearest = np.full(len(pick), np.inf)
    for start in range(0, len(points), 2048):
        d2 = ((pick[:, None, :] - points[None, start:start + 2048, :]) ** 2).sum(axis=2)
        d2[d2 == 0] = np.inf  # the point itself
        nearest = np.minimum(nearest, d2.min(axis=1))
    return float(np.sqrt(np.median(nearest)))


def slice_points(points, axis, value, h):
    """Indices of the points within half the particle spacing h (point_spacing) of the plane:
    |coordinate - value| < h / 2, the points whose voxel the plane cuts in an undeformed
    lattice; a plane halfway between two layers takes the one towards the middle of the points,
    like slice_voxels."""
    along = points[:, axis]
    plane = nudged(value, h, along.min(), along.max())
    return np.where(np.abs(along - plane) < 0.5 * h)[0]


def polygon_area(polygon):
    """Area of a simple polygon (k, 2) by the shoelace formula."""
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def face_geometry(corners):
    """The 6 n faces: quadrilaterals (6n, 4, 3), centres (6n, 3) and unit outward normals. The
    normal's sign is taken from the voxel's centre, so it points out whatever the corner order."""
    quads = corners[:, FACES].reshape(-1, 4, 3)
    centres = quads.mean(axis=1)
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    outward = centres - np.repeat(corners.mean(axis=1), 6, axis=0)
    normals *= np.sign((normals * outward).sum(axis=1))[:, None]
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    return quads, centres, normals


def outer_faces(corners, tolerance=0.25):
    """Indices (into the 6 n faces of face_geometry) of the faces on the outer surface.

    A face is interior when a face of another voxel faces it: its centre lies within
    `tolerance` voxel sizes (the smaller voxel's) and its normal is opposite (cosine < -0.5).
    Matching centres with a tolerance, not equal corners, is what works on deformed voxels:
    neighbours have different F, so their shared faces never coincide exactly (they overlap or
    gap by about h |grad F| h), while in a lattice the nearest centre of a face that is not the
    neighbour's is h / sqrt(2) away. The search hashes the centres into cubes of twice the largest
    tolerance: a centre within the tolerance of a face's lies in one of the 2 x 2 x 2 cubes
    nearest to that face's centre."""
    _, centres, normals = face_geometry(corners)
    tol = np.repeat(tolerance * voxel_size(corners), 6)
    if len(tol) == 0:
        return np.zeros(0, dtype=int)
    scaled = centres / max(2.0 * float(tol.max()), 1e-300)
    ijk = np.floor(scaled).astype(np.int64)
    step = np.where(scaled - ijk >= 0.5, 1, -1)  # towards the nearer neighbouring cube, per axis
    ijk -= ijk.min(axis=0) - 1  # a margin of one cube for the neighbours' keys
    span = ijk.max(axis=0) + 2
    order = np.argsort((ijk[:, 0] * span[1] + ijk[:, 1]) * span[2] + ijk[:, 2])
    sorted_keys = ((ijk[order, 0] * span[1] + ijk[order, 1]) * span[2] + ijk[order, 2])
    interior = np.zeros(len(tol), dtype=bool)
    for corner in itertools.product((0, 1), repeat=3):
        near = ijk + step * np.array(corner)
        near = (near[:, 0] * span[1] + near[:, 1]) * span[2] + near[:, 2]
        lo = np.searchsorted(sorted_keys, near, "left")
        count = np.searchsorted(sorted_keys, near, "right") - lo
        face = np.repeat(np.arange(len(tol)), count)
        other = order[np.repeat(lo - np.cumsum(count) + count, count) + np.arange(len(face))]
        match = ((face // 6 != other // 6)
                 & ((normals[face] * normals[other]).sum(axis=1) < -0.5)
                 & (np.linalg.norm(centres[face] - centres[other], axis=1)
                    < np.minimum(tol[face], tol[other])))
        interior[face[match]] = True
    return np.where(~interior)[0]


def view_basis(view):
    """Unit vectors (right, up, towards the viewer) of an orthographic view. The picture's up
    is y's projection, or -z when looking down y (a plan with x to the right)."""
    towards = np.array(VIEWS[view]) / np.linalg.norm(VIEWS[view])
    up = np.array([0.0, 0.0, -1.0]) if view == "y" else np.array([0.0, 1.0, 0.0])
    right = np.cross(up, towards)
    right /= np.linalg.norm(right)
    return right, np.cross(towards, right), towards


def visible_faces(corners, view):
    """The outer faces turned to the viewer, far to near (the painter's order): projected
    quadrilaterals (m, 4, 2), the faces' indices (voxel 6 + face) and unit outward normals."""
    right, up, towards = view_basis(view)
    quads, _, normals = face_geometry(corners)
    faces = outer_faces(corners)
    faces = faces[normals[faces] @ towards > 1e-9]  # back faces are hidden behind front ones
    depth = quads[faces].mean(axis=1) @ towards
    faces = faces[np.argsort(depth, kind="stable")]
    projected = np.stack([quads[faces] @ right, quads[faces] @ up], axis=-1)
    return projected, faces, normals[faces]
