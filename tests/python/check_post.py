#!/usr/bin/python3
"""Open the deformed voxels and grid fields of a Talus results folder with real XDMF readers.

    /usr/bin/python3 tests/python/check_post.py <dir>

For the last frame of run.h5 (h5py), and the last time step of run.xmf read by VTK's XDMF
readers (vtkXdmfReader, ParaView's "XDMF Reader", and vtkXdmf3Reader where available):

* voxels: N quadrilateral cells of 4 points each (3D: hexahedra of 8), point coordinates equal to
  /frames/K/voxels/corners, cell arrays stress, stress_smoothed, checker, stripes_horizontal,
  stripes_vertical (checker equal to run.h5);
* grid: (nodes_x x nodes_y [x nodes_z]) points on the lattice of /frames/K/grid (origin and spacing), point
  arrays mass and stress, the mass equal to run.h5 node by node (x fastest).

Exits 0 when everything matches, 1 with a message otherwise (a missing reader is a failure).
"""

import os
import sys

VOXEL_ARRAYS = ["stress", "stress_smoothed", "checker", "stripes_horizontal", "stripes_vertical"]
GRID_ARRAYS = ["mass", "stress"]


def fail(msg):
    print(f"check_post: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def blocks(obj):
    """The datasets of a composite output, in order."""
    out = []
    it = obj.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        out.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return out


def arrays(data):
    return {data.GetArrayName(j): data.GetArray(j) for j in range(data.GetNumberOfArrays())}


def check_reader(name, reader_class, xmf, h5):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp

    reader = reader_class()
    reader.SetFileName(xmf)
    reader.UpdateInformation()
    steps = list(reader.GetOutputInformation(0).Get(sddp.TIME_STEPS()))
    reader.UpdateTimeStep(steps[-1])
    out = reader.GetOutputDataObject(0)
    if not out.IsA("vtkCompositeDataSet"):
        fail(f"{name}: expected particles, voxels and grid blocks, got one {out.GetClassName()}")
    found = blocks(out)
    print(f"{name}: {len(found)} blocks: " +
          ", ".join(f"{b.GetClassName()}({b.GetNumberOfPoints()} points, "
                    f"{b.GetNumberOfCells()} cells)" for b in found))
    if len(found) != 3:
        fail(f"{name}: {len(found)} blocks, expected 3 (particles, voxels, grid)")
    particles, voxels, grid = found
    n = h5["n"]
    if particles.GetNumberOfPoints() != n:
        fail(f"{name}: particle block has {particles.GetNumberOfPoints()} points, expected {n}")

    if voxels.GetNumberOfCells() != n:
        fail(f"{name}: voxel block has {voxels.GetNumberOfCells()} cells, expected {n}")
    dim = h5["dimension"]
    corners, cell_type = (8, 12) if dim == 3 else (4, 9)  # VTK_HEXAHEDRON, VTK_QUAD
    for c in range(voxels.GetNumberOfCells()):
        cell = voxels.GetCell(c)
        if cell.GetNumberOfPoints() != corners or cell.GetCellType() != cell_type:
            fail(f"{name}: voxel {c} is not a {'hexahedron' if dim == 3 else 'quadrilateral'}")
    pts = vtk_to_numpy(voxels.GetPoints().GetData())[:, :dim]
    if not np.array_equal(pts, h5["corners"]):
        fail(f"{name}: voxel points differ from voxels/corners")
    cell_arrays = arrays(voxels.GetCellData())
    print(f"{name}: voxel cell arrays {sorted(cell_arrays)}")
    for a in VOXEL_ARRAYS:
        if a not in cell_arrays:
            fail(f"{name}: voxel cell array '{a}' missing (found {sorted(cell_arrays)})")
    if not np.array_equal(vtk_to_numpy(cell_arrays["checker"]), h5["checker"]):
        fail(f"{name}: voxel 'checker' differs from run.h5")

    nodes = h5["nodes"]  # x, y (and z)
    count = int(np.prod(nodes))
    if grid.GetNumberOfPoints() != count:
        fail(f"{name}: grid block has {grid.GetNumberOfPoints()} points, expected "
             f"{' x '.join(map(str, nodes))}")
    bounds = grid.GetBounds()
    want = []
    for d, n in enumerate(nodes):
        want += [h5["origin"][d], h5["origin"][d] + (n - 1) * h5["spacing"]]
    got = bounds[:2 * dim]
    if not np.allclose(got, want, rtol=0, atol=1e-12 * max(1.0, max(map(abs, want)))):
        fail(f"{name}: grid bounds {got}, expected {want}")
    point_arrays = arrays(grid.GetPointData())
    print(f"{name}: grid point arrays {sorted(point_arrays)}, bounds {got}")
    for a in GRID_ARRAYS:
        if a not in point_arrays:
            fail(f"{name}: grid point array '{a}' missing (found {sorted(point_arrays)})")
    # Point order of a structured grid: x fastest, like grid/mass.
    if not np.array_equal(vtk_to_numpy(point_arrays["mass"]), h5["mass"]):
        fail(f"{name}: grid 'mass' differs from run.h5")
    xyz = np.array([grid.GetPoint(i)[:dim] for i in range(grid.GetNumberOfPoints())])
    # x fastest: the index of axis 0 changes first.
    index = np.indices(nodes[::-1]).reshape(dim, -1)[::-1].T
    lattice = h5["origin"] + h5["spacing"] * index
    if not np.allclose(xyz, lattice, rtol=0, atol=1e-12):
        fail(f"{name}: grid point coordinates are not the lattice of run.h5 (x fastest)")


def main():
    if len(sys.argv) != 2:
        fail("usage: check_post.py <results dir>")
    try:
        import h5py
    except ImportError as e:
        fail(f"cannot import h5py ({e}); install python3-h5py")
    d = sys.argv[1]
    with h5py.File(os.path.join(d, "run.h5"), "r") as f:
        last = sorted(f["frames"].keys())[-1]
        g = f["frames"][last]
        dim = int(f["metadata"].attrs["dimension"])
        nodes = [int(g["grid"].attrs["nodes_x"]), int(g["grid"].attrs["nodes_y"])]
        if dim == 3:
            nodes.append(int(g["grid"].attrs["nodes_z"]))
        h5 = {
            "dimension": dim,
            "n": g["position"].shape[0],
            "corners": g["voxels/corners"][()],
            "checker": g["voxels/checker"][()],
            "mass": g["grid/mass"][()].ravel(),
            "nodes": nodes,
            "origin": g["grid"].attrs["origin"],
            "spacing": float(g["grid"].attrs["spacing"]),
        }
    readers = {}
    try:
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
        readers["vtkXdmfReader"] = vtkXdmfReader
    except ImportError:
        pass
    try:
        from vtkmodules.vtkIOXdmf3 import vtkXdmf3Reader
        readers["vtkXdmf3Reader"] = vtkXdmf3Reader
    except ImportError:
        pass
    if not readers:
        fail("this VTK has no XDMF reader; install python3-paraview (Debian's python3-vtk9 is "
             "built without vtkIOXdmf2/vtkIOXdmf3)")
    # Absolute: vtkXdmf3Reader resolves run.h5 wrongly when given a bare file name.
    xmf = os.path.abspath(os.path.join(d, "run.xmf"))
    for name, cls in readers.items():
        check_reader(name, cls, xmf, h5)
    print("check_post: OK")


if __name__ == "__main__":
    main()
