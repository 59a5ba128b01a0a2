#!/usr/bin/python3
"""Make a pair of surface frames at scale from a run of our own, for `tetcontact profile
--frames` (the broadphase at scale: at least 200k edges and 10 million candidate pairs).

    scale_frames.py BINARY OUTDIR [--cells N] [--thickness K] [--gap DT]

Runs ball-plate with a plate of N x N x K cells (default 200 x 200 x 2) and a ball of 24
cells across, fracture off (the surface must stay the same between the frames), to 2 DT, a
frame every DT (default 0.2 µs); extracts the boundary surface of frames 1 and 2 with VTK and
writes OUTDIR/A.ply and OUTDIR/B.ply (binary, double vertices, the same triangles in both).
Then: tetcontact profile --frames OUTDIR/A.ply OUTDIR/B.ply --broadphase grid [--threads 2].
Needs Debian's python3-vtk9 (run with /usr/bin/python3)."""
import argparse
import os
import struct
import subprocess
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

import tools.common  # noqa: E402,F401 (first: a missing module is said plainly)

import vtk  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def surface(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    grid = r.GetOutput()
    if grid.GetNumberOfCells() == 0:
        sys.exit(f"{path}: no cells read")
    f = vtk.vtkDataSetSurfaceFilter()
    f.SetInputData(grid)
    f.PassThroughPointIdsOn()
    f.Update()
    s = f.GetOutput()
    ids = vtk_to_numpy(s.GetPointData().GetArray("vtkOriginalPointIds"))
    polys = vtk_to_numpy(s.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    # Triangles on the mesh's own node numbers: the same in every frame of the same mesh.
    return vtk_to_numpy(grid.GetPoints().GetData()), ids[polys]


def write_ply(path, points, triangles):
    used = sorted(set(triangles.ravel().tolist()))
    index = {n: i for i, n in enumerate(used)}
    with open(path + ".tmp", "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(used)}\n"
                 "property double x\nproperty double y\nproperty double z\n"
                 f"element face {len(triangles)}\nproperty list uchar int vertex_indices\n"
                 "end_header\n").encode())
        f.write(b"".join(struct.pack("<3d", *points[n]) for n in used))
        f.write(b"".join(struct.pack("<B3i", 3, *(index[int(v)] for v in t)) for t in triangles))
    os.replace(path + ".tmp", path)
    return len(used)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("out")
    ap.add_argument("--cells", type=int, default=200)
    ap.add_argument("--thickness", type=int, default=2)
    ap.add_argument("--gap", type=float, default=0.2e-6)
    a = ap.parse_args()
    run = os.path.join(a.out, "run")
    subprocess.run([a.binary, "run", os.path.join(ROOT, "data/cases/ball-plate.yaml"), "--quiet",
                    "--force", "--out", run, "--set", "fracture.enabled=false",
                    "--set", f"bodies.1.mesh.box.cells=[{a.cells},{a.cells},{a.thickness}]",
                    "--set", "bodies.0.mesh.sphere.cells_across=24",
                    "--set", f"end_time={2 * a.gap!r}", "--set", f"output.interval={a.gap!r}",
                    "--set", "output.fields=[body]"], check=True)
    pa, ta = surface(os.path.join(run, "frame_0001.vtu"))
    pb, tb = surface(os.path.join(run, "frame_0002.vtu"))
    if not (ta == tb).all():
        sys.exit("the two frames' surfaces differ")
    n = write_ply(os.path.join(a.out, "A.ply"), pa, ta)
    write_ply(os.path.join(a.out, "B.ply"), pb, tb)
    print(f"scale_frames: {n} vertices, {len(ta)} triangles, about {3 * len(ta) // 2} edges "
          f"-> {a.out}/A.ply, {a.out}/B.ply")


if __name__ == "__main__":
    main()
