#!/usr/bin/python3
"""Opens a tetcontact ParaView series with VTK's own XML reader (the one ParaView uses) and
checks it: every frame of case.pvd reads, has the mesh of summary.json, linear tetrahedra
only, the requested arrays with their component counts, finite values, positive volumes.
With fracture particles, particles.pvd too: each frame's particles plus its cells make the
mesh's tets, with radius, mass, velocity, energy and body, finite, radius and mass positive.

    check_vtu.py OUTDIR                               check an existing result folder
    check_vtu.py --run BINARY CASE OUTDIR [END_TIME]  run a short version of CASE first
                                                      (to END_TIME, default 2e-5 s)
    check_vtu.py --same SERIAL_DIR DISTRIBUTED_DIR    a distributed run's frames (.pvtu of
                                                      per-rank pieces) hold one process's
                                                      values bit for bit, node by node and
                                                      cell by cell (their global numbers)
    check_vtu.py --formats BINARY CASE OUTDIR [END_TIME]
                                                      run it with output.format ascii, binary
                                                      and compressed; each folder must pass the
                                                      checks and VTK must read the same values,
                                                      bit for bit, from all three

Needs Debian's python3-vtk9 (run with /usr/bin/python3). Exit code 0 when all checks pass."""
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy

checks = {"passed": 0, "failed": 0}


def check(cond, what):
    if cond:
        checks["passed"] += 1
    else:
        checks["failed"] += 1
        print("FAIL:", what)


def read(path, name):
    """The grid of one .vtu (or the pieces a .pvtu joins), checked to be readable by VTK."""
    reader = (vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu")
              else vtk.vtkXMLUnstructuredGridReader())
    reader.SetFileName(path)
    reader.Update()
    check(reader.GetErrorCode() == 0, f"{name}: VTK reads it")
    return reader.GetOutput()


def check_arrays(data, expected, name):
    """Each expected array present with its component count, values finite; returns them."""
    found = {}
    for array, comps in expected.items():
        a = data.GetArray(array)
        check(a is not None and a.GetNumberOfComponents() == comps,
              f"{name}: array {array} with {comps} components")
        if a is not None:
            found[array] = vtk_to_numpy(a)
            check(all(math.isfinite(v) for v in found[array].ravel()), f"{name}: {array} finite")
    return found


def run_short(binary, case, out, end, fmt=None):
    cmd = [binary, "run", case, "--out", out, "--force", "--quiet",
           "--set", f"end_time={end!r}", "--set", f"output.interval={end / 2!r}",
           "--set", "output.fields=[displacement,velocity,stress,pressure,body,von_mises]"]
    if fmt:
        cmd += ["--set", f"output.format={fmt}"]
    subprocess.run(cmd, check=True)


def all_arrays(path):
    """Every point, cell and point-coordinate array of a .vtu as VTK reads it."""
    grid = read(path, os.path.basename(path))
    out = {"Points": vtk_to_numpy(grid.GetPoints().GetData()).copy(),
           "types": vtk_to_numpy(grid.GetCellTypesArray()).copy(),
           "connectivity": vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)}
    for kind, data in (("point", grid.GetPointData()), ("cell", grid.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            out[f"{kind}:{data.GetArrayName(i)}"] = vtk_to_numpy(data.GetArray(i)).copy()
    return out


def formats(argv):
    """The same run written as ascii, binary and compressed: VTK reads the same bits."""
    binary, case, out = argv[:3]
    end = float(argv[3]) if len(argv) > 3 else 2.0e-5
    dirs = {f: os.path.join(out, f) for f in ("ascii", "binary", "compressed")}
    for f, d in dirs.items():
        run_short(binary, case, d, end, f)
        check(check_folder(d) == 0, f"{f}: the folder passes every check")
    frames = sorted(n for n in os.listdir(dirs["ascii"]) if n.endswith(".vtu"))
    check(len(frames) >= 2, "frames written")
    for name in frames:
        ref = all_arrays(os.path.join(dirs["ascii"], name))
        for f in ("binary", "compressed"):
            got = all_arrays(os.path.join(dirs[f], name))
            check(sorted(got) == sorted(ref), f"{f}/{name}: the same arrays")
            for k in ref:
                if k in got:
                    check(got[k].dtype == ref[k].dtype and got[k].shape == ref[k].shape and
                          got[k].tobytes() == ref[k].tobytes(), f"{f}/{name}: {k} bit-identical")
    size = {f: sum(os.path.getsize(os.path.join(d, n)) for n in frames) for f, d in dirs.items()}
    print("check_vtu: frame bytes", size)
    check(size["binary"] < size["ascii"], "binary frames smaller than ascii")
    check(size["compressed"] < size["binary"], "compressed frames smaller than binary")
    print(f"check_vtu: {checks['passed']} passed, {checks['failed']} failed")
    return 1 if checks["failed"] else 0


def same(serial, dist):
    """A distributed run's frames (.pvtu of per-rank pieces) against one process's (.vtu): VTK
    reads the same values, bit for bit, every node and cell by its global number; the particle
    frames, history and summary are the caller's."""
    def series(out):
        root = ET.parse(os.path.join(out, "case.pvd")).getroot().find("Collection")
        return [(d.get("timestep"), d.get("file")) for d in root.findall("DataSet")]
    one, many = series(serial), series(dist)
    check([t for t, _ in one] == [t for t, _ in many], "the same frame times")
    for (t, a), (_, b) in zip(one, many):
        ref = all_arrays(os.path.join(serial, a))
        got = all_arrays(os.path.join(dist, b))
        if not b.endswith(".pvtu"):  # one rank: the whole frame, as one process writes it
            check(sorted(got) == sorted(ref) and
                  all(got[k].tobytes() == ref[k].tobytes() for k in ref), f"{b}: bit-identical")
            continue
        nodes = got.pop("point:global_node").astype(int)
        tets = got.pop("cell:global_tet").astype(int)
        # One process's cells are the tets still cells, ascending: the k-th is the k-th of the
        # sorted global numbers.
        order = sorted(set(tets.tolist()))
        check(len(order) == len(tets), f"{b}: each cell in one piece")
        cell = {g: k for k, g in enumerate(order)}
        cells = [cell[g] for g in tets]
        check(len(order) == len(ref["types"]), f"{b}: {len(ref['types'])} cells")
        check(len(set(nodes.tolist())) == len(ref["Points"]), f"{b}: every node in a piece")
        check(sorted(got) == sorted(ref), f"{b}: the same arrays")
        for k in ref:
            if k not in got:
                continue
            if k == "connectivity":  # the pieces' own node numbers, as the mesh's
                check((nodes[got[k]] == ref[k][cells]).all(), f"{b}: the same cells' nodes")
                continue
            rows = nodes if k.startswith("point:") or k == "Points" else cells
            check(got[k].dtype == ref[k].dtype and
                  got[k].tobytes() == ref[k][rows].tobytes(), f"{b}: {k} bit-identical")
    print(f"check_vtu: {dist} against {serial}: {checks['passed']} passed, "
          f"{checks['failed']} failed")
    return 1 if checks["failed"] else 0


def main(argv):
    if argv[:1] == ["--same"]:
        return same(*argv[1:3])
    if argv[:1] == ["--formats"]:
        return formats(argv[1:])
    if argv[:1] == ["--run"]:
        binary, case, out = argv[1:4]
        run_short(binary, case, out, float(argv[4]) if len(argv) > 4 else 2.0e-5)
    else:
        (out,) = argv
    return check_folder(out)


def check_folder(out):
    failed_before = checks["failed"]
    summary = json.load(open(os.path.join(out, "summary.json")))
    nodes, tets = summary["mesh"]["nodes"], summary["mesh"]["tets"]
    series = ET.parse(os.path.join(out, "case.pvd")).getroot().find("Collection")
    frames = [(float(d.get("timestep")), d.get("file")) for d in series.findall("DataSet")]
    check(len(frames) >= 2, "at least two frames in case.pvd")
    check(all(a[0] < b[0] for a, b in zip(frames, frames[1:])), "frame times increase")
    expected_point = {"displacement": 3, "velocity": 3, "body": 1}
    expected_cell = {"stress": 6, "pressure": 1, "von_mises": 1, "body": 1}
    particles = {}  # time → particle count, from particles.pvd
    if os.path.exists(os.path.join(out, "particles.pvd")):
        pseries = ET.parse(os.path.join(out, "particles.pvd")).getroot().find("Collection")
        pframes = [(float(d.get("timestep")), d.get("file")) for d in pseries.findall("DataSet")]
        check([t for t, _ in pframes] == [t for t, _ in frames], "particle frames at the frame times")
        for t, name in pframes:
            grid = read(os.path.join(out, name), name)
            n = grid.GetNumberOfPoints()
            particles[t] = n
            check(grid.GetNumberOfCells() == n, f"{name}: one vertex per particle")
            found = check_arrays(grid.GetPointData(),
                                 {"radius": 1, "mass": 1, "velocity": 3, "energy": 1, "body": 1}, name)
            for array in ("radius", "mass"):
                if n and array in found:
                    check(found[array].min() > 0, f"{name}: {array} positive")
        check(particles.get(frames[-1][0], 0) == summary["fracture"]["particles"],
              "the last particle frame holds summary.fracture.particles")
    for t, name in frames:
        grid = read(os.path.join(out, name), name)
        pieces = grid.GetPointData().GetArray("global_node")
        if name.endswith(".pvtu"):  # pieces: each shared node in every piece that uses it
            check(pieces is not None and len(set(vtk_to_numpy(pieces).tolist())) == nodes,
                  f"{name}: the pieces hold the {nodes} nodes")
        else:
            check(grid.GetNumberOfPoints() == nodes, f"{name}: {nodes} points")
        cells = tets - particles.get(t, 0)  # cells turned into particles leave the mesh
        check(grid.GetNumberOfCells() == cells, f"{name}: {cells} cells")
        types = vtk_to_numpy(grid.GetCellTypesArray())
        check((types == vtk.VTK_TETRA).all(), f"{name}: only linear tetrahedra")
        check_arrays(grid.GetPointData(), expected_point, name)
        check_arrays(grid.GetCellData(), expected_cell, name)
        quality = vtk.vtkMeshQuality()
        quality.SetInputData(grid)
        quality.SetTetQualityMeasureToVolume()
        quality.Update()
        vol = vtk_to_numpy(quality.GetOutput().GetCellData().GetArray("Quality"))
        check(vol.min() > 0, f"{name}: every tet has positive volume in VTK's convention")
        if t == 0.0:
            disp = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
            check(abs(disp).max() == 0.0, f"{name}: zero displacement at t = 0")
    print(f"check_vtu: {out}: {checks['passed']} passed, {checks['failed']} failed")
    return 1 if checks["failed"] > failed_before else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
