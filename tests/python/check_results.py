#!/usr/bin/python3
"""Check a Talus results folder (run.h5 + run.xmf) with real readers.

    /usr/bin/python3 tests/python/check_results.py <dir> --particles N --frames K \
        [--fields velocity,F,stress,mass] [--reader auto|xdmf2|xdmf3|all]

* h5py: /frames/000000/position has shape (N, 2), there are K frame groups, and every expected
  field of the first and last frame has its documented shape.
* VTK: run.xmf is opened with VTK's XDMF readers (vtkXdmfReader from vtkIOXdmf2, the reader
  ParaView lists as "XDMF Reader", and vtkXdmf3Reader from vtkIOXdmf3). For the first and last
  time step it checks the number of time steps, points and cells (Polyvertex: N points in N
  one-point cells), that every expected array is present with the component count that reader
  produces, and that positions, velocities and stresses equal the values in run.h5.

--reader auto (default) uses every XDMF reader this VTK has and fails if it has none. Exits 0
when everything matches, 1 with a message otherwise (including a missing h5py, vtk or XDMF
reader: a missing reader is a failure, not a skip).

Note: Debian 12's python3-vtk9 is built without the IOXdmf2/IOXdmf3 modules. ParaView's Python
package (python3-paraview, which replaces python3-vtk9) ships both; any VTK build with them
works through the usual PYTHONPATH / LD_LIBRARY_PATH.
"""

import argparse
import os
import sys

# Field name -> (columns in run.h5 (0 = 1-D), components in vtkXdmfReader, in vtkXdmf3Reader).
# vtkXdmfReader pads 2-component Vectors to 3 and expands Tensor6 to a full 9-component tensor;
# vtkXdmf3Reader passes both through unchanged.
FIELDS = {
    "velocity": (2, 3, 2),
    "mass": (0, 1, 1),
    "volume": (0, 1, 1),
    "F": (9, 9, 9),
    "stress": (6, 9, 6),
    "material": (0, 1, 1),
    "body": (0, 1, 1),
    "plastic_strain": (0, 1, 1),
    "pore_pressure": (0, 1, 1),
    "effective_stress": (6, 9, 6),
}


class CheckError(Exception):
    pass


def fail(msg):
    print(f"check_results: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def expect(cond, msg):
    if not cond:
        raise CheckError(msg)


def check_h5(path, n, k, fields):
    try:
        import h5py
        import numpy as np
    except ImportError as e:
        fail(f"cannot import h5py/numpy ({e}); install python3-h5py")
    frames = {}
    with h5py.File(path, "r") as f:
        expect("frames" in f and "metadata" in f, f"{path}: no /frames or /metadata group")
        names = sorted(f["frames"].keys())
        expect(len(names) == k, f"{path}: {len(names)} frame groups, expected {k}")
        expect(names == [f"{i:06d}" for i in range(k)], f"{path}: frame groups {names}")
        shape = f["frames/000000/position"].shape
        print(f"h5py: /frames/000000/position shape {shape}")
        expect(shape == (n, 2), f"/frames/000000/position has shape {shape}, expected {(n, 2)}")
        for i in sorted({0, k - 1}):
            g = f[f"frames/{i:06d}"]
            data = {"time": float(g.attrs["time"]), "step": int(g.attrs["step"])}
            for name in ["position"] + fields:
                expect(name in g, f"/frames/{i:06d}/{name} missing (has {sorted(g.keys())})")
                cols = 2 if name == "position" else FIELDS[name][0]
                want = (n, cols) if cols else (n,)
                expect(g[name].shape == want,
                       f"/frames/{i:06d}/{name} has shape {g[name].shape}, expected {want}")
                expect("units" in g[name].attrs, f"/frames/{i:06d}/{name} has no units attribute")
                data[name] = np.asarray(g[name][()])
            frames[i] = data
            print(f"h5py: frame {i}: time {data['time']!r}, step {data['step']}, "
                  f"datasets {sorted(g.keys())}")
    return frames


def load_vtk():
    try:
        import vtkmodules  # noqa: F401
        from vtkmodules.vtkCommonCore import vtkVersion
    except ImportError as e:
        fail(f"cannot import the vtk Python module ({e}); install python3-vtk9 or python3-paraview")
    readers = {}
    try:
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
        readers["xdmf2"] = vtkXdmfReader
    except ImportError:
        pass
    try:
        from vtkmodules.vtkIOXdmf3 import vtkXdmf3Reader
        readers["xdmf3"] = vtkXdmf3Reader
    except ImportError:
        pass
    return vtkVersion.GetVTKVersion(), os.path.dirname(vtkmodules.__file__), readers


def first_dataset(obj):
    """The dataset of a time step (the readers may wrap it in a composite)."""
    if obj is None:
        return None
    if obj.IsA("vtkDataSet"):
        return obj
    if obj.IsA("vtkCompositeDataSet"):
        it = obj.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            ds = it.GetCurrentDataObject()
            if ds is not None and ds.IsA("vtkDataSet"):
                return ds
            it.GoToNextItem()
    return None


def check_vtk(kind, reader_class, xmf, n, k, fields, frames):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp

    comp_index = 1 if kind == "xdmf2" else 2
    reader = reader_class()
    reader.SetFileName(xmf)
    reader.UpdateInformation()
    info = reader.GetOutputInformation(0)
    steps = list(info.Get(sddp.TIME_STEPS())) if info.Has(sddp.TIME_STEPS()) else []
    print(f"{reader_class.__name__}: {len(steps)} time steps {steps}")
    expect(len(steps) == k, f"{reader_class.__name__}: {len(steps)} time steps, expected {k}")
    for i in sorted({0, k - 1}):
        h5 = frames[i]
        expect(steps[i] == h5["time"],
               f"{reader_class.__name__}: time step {i} is {steps[i]!r}, run.h5 says {h5['time']!r}")
        reader.UpdateTimeStep(steps[i])
        ds = first_dataset(reader.GetOutputDataObject(0))
        expect(ds is not None, f"{reader_class.__name__}: frame {i}: no dataset in the output")
        npts, ncells = ds.GetNumberOfPoints(), ds.GetNumberOfCells()
        pd = ds.GetPointData()
        arrays = {pd.GetArrayName(j): pd.GetArray(j) for j in range(pd.GetNumberOfArrays())}
        found = ", ".join(f"{a}({arr.GetNumberOfComponents()})" for a, arr in arrays.items())
        print(f"{reader_class.__name__}: frame {i} (t = {steps[i]!r}): {ds.GetClassName()}, "
              f"{npts} points, {ncells} cells, point arrays: {found}")
        expect(npts == n, f"frame {i}: {npts} points, expected {n}")
        expect(ncells == n, f"frame {i}: {ncells} cells, expected {n} (one per particle)")
        for c in range(ncells):
            expect(ds.GetCell(c).GetNumberOfPoints() == 1,
                   f"frame {i}: cell {c} has {ds.GetCell(c).GetNumberOfPoints()} points")
        pts = vtk_to_numpy(ds.GetPoints().GetData())
        expect(np.array_equal(pts[:, :2], h5["position"]) and not pts[:, 2].any(),
               f"frame {i}: point coordinates differ from /frames/{i:06d}/position")
        for name in fields:
            expect(name in arrays, f"frame {i}: array '{name}' missing (found: {found})")
            want = FIELDS[name][comp_index]
            got = arrays[name].GetNumberOfComponents()
            expect(got == want, f"frame {i}: '{name}' has {got} components, expected {want}")
            values = vtk_to_numpy(arrays[name]).reshape(n, -1)
            ref = h5[name].reshape(n, -1)
            if name in ("stress", "effective_stress") and got == 9:
                # Tensor6 (xx, xy, xz, yy, yz, zz) expanded to the full symmetric tensor.
                t6 = [0, 1, 2, 4, 5, 8]
                ok = np.array_equal(values[:, t6], ref) and np.array_equal(
                    values[:, [3, 6, 7]], ref[:, [1, 2, 4]])
            elif name == "velocity" and got == 3:
                ok = np.array_equal(values[:, :2], ref) and not values[:, 2].any()
            else:
                ok = np.array_equal(values, ref)
            expect(ok, f"frame {i}: '{name}' values differ from /frames/{i:06d}/{name}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", help="results folder with run.h5 and run.xmf")
    ap.add_argument("--particles", type=int, required=True)
    ap.add_argument("--frames", type=int, required=True)
    ap.add_argument("--fields", default="", help="comma-separated, e.g. velocity,F,stress,mass")
    ap.add_argument("--reader", choices=["auto", "xdmf2", "xdmf3", "all"], default="auto",
                    help="auto: every XDMF reader this VTK has (at least one); all: both")
    args = ap.parse_args()

    fields = [f for f in args.fields.split(",") if f]
    for f in fields:
        if f not in FIELDS:
            fail(f"unknown field '{f}' (known: {', '.join(FIELDS)})")
    if args.frames < 1 or args.particles < 1:
        fail("--frames and --particles must be at least 1")
    h5 = os.path.join(args.dir, "run.h5")
    # Absolute: vtkXdmf3Reader resolves run.h5 wrongly when given a bare file name.
    xmf = os.path.abspath(os.path.join(args.dir, "run.xmf"))
    for p in (h5, xmf):
        if not os.path.isfile(p):
            fail(f"{p} does not exist")

    version, where, readers = load_vtk()
    print(f"vtk {version} from {where}; XDMF readers: {', '.join(readers) or 'none'}")
    if args.reader == "auto":
        wanted = list(readers)
        if not wanted:
            fail(f"this VTK ({version}, {where}) has no XDMF reader (modules vtkIOXdmf2 / "
                 "vtkIOXdmf3). Debian 12's python3-vtk9 is built without them; install "
                 "python3-paraview (it replaces python3-vtk9) or point PYTHONPATH and "
                 "LD_LIBRARY_PATH at a VTK/ParaView build that has them.")
    else:
        wanted = ["xdmf2", "xdmf3"] if args.reader == "all" else [args.reader]
        missing = [r for r in wanted if r not in readers]
        if missing:
            fail(f"this VTK ({version}, {where}) lacks the reader(s) {', '.join(missing)}")

    try:
        frames = check_h5(h5, args.particles, args.frames, fields)
        for kind in wanted:
            check_vtk(kind, readers[kind], xmf, args.particles, args.frames, fields, frames)
    except CheckError as e:
        fail(str(e))
    print(f"check_results: OK ({args.particles} particles, {args.frames} frames, "
          f"readers: {', '.join(wanted)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
