#!/usr/bin/python3
"""Opens a tetcontact ParaView series with VTK's own XML reader (the one ParaView uses) and
checks it: every frame of case.pvd reads, has the mesh of summary.json, linear tetrahedra
only, the arrays the run asked for (its output.fields) in every frame, each where it belongs
(node or cell) with its component count, finite values, positive volumes.
With fracture particles, particles.pvd too: each frame's particles plus its cells make the
mesh's tets, with radius, mass, velocity, energy and body, finite, radius and mass positive.

    check_vtu.py OUTDIR [--fields A,B,...]            check an existing result folder: the
                                                      arrays asked for are --fields, else
                                                      those of the first frame
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

Needs Debian's python3-vtk9 (run with /usr/bin/python3). Exit code 0 when all checks pass, 1
when one fails (each failure printed as a FAIL line), 2 when the folder is not a run's (no
summary.json, no case.pvd, an unknown field asked for)."""
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import summary_keys as K  # noqa: E402

import numpy as np  # noqa: E402 (after tools.common: a missing module is said plainly)
import vtk  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

checks = {"passed": 0, "failed": 0}

# The output.fields a case may ask for (src/io/case.cpp's known_output_fields): where each is
# written (node or cell data; body in both) and its component count.
FIELDS = {"displacement": ("point", 3), "velocity": ("point", 3), "body": ("both", 1),
          "stress": ("cell", 6), "pressure": ("cell", 1), "von_mises": ("cell", 1),
          "plastic_strain": ("cell", 1), "internal_energy": ("cell", 1),
          "viscosity": ("cell", 1), "damage": ("cell", 1), "temperature": ("cell", 1),
          "ductile_damage": ("cell", 1)}
# Arrays the program adds by itself: penetration depths, a distributed run's global numbers.
EXTRA = {"penetration_depth": ("point", 1), "global_node": ("point", 1),
         "global_tet": ("cell", 1)}
PARTICLE_ARRAYS = {"radius": 1, "mass": 1, "velocity": 3, "energy": 1, "body": 1}
RUN_FIELDS = ["displacement", "velocity", "stress", "pressure", "body", "von_mises"]


class BadFolder(Exception):
    """Not a run's folder, or an unknown field asked for: exit code 2."""


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
           "--set", f"output.fields=[{','.join(RUN_FIELDS)}]"]
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
        check(check_folder(d, RUN_FIELDS) == 0, f"{f}: the folder passes every check")
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
        # One process's frame numbers its nodes as the mesh does, or, once cells have turned
        # into particles and left nodes out, names each node's mesh number (global_node).
        ref_nodes = (ref.pop("point:global_node").astype(int) if "point:global_node" in ref
                     else np.arange(len(ref["Points"])))
        row_of = {g: k for k, g in enumerate(ref_nodes.tolist())}
        # One process's cells are the tets still cells, ascending: the k-th is the k-th of the
        # sorted global numbers.
        order = sorted(set(tets.tolist()))
        check(len(order) == len(tets), f"{b}: each cell in one piece")
        cell = {g: k for k, g in enumerate(order)}
        cells = [cell[g] for g in tets]
        check(len(order) == len(ref["types"]), f"{b}: {len(ref['types'])} cells")
        check(set(nodes.tolist()) == set(ref_nodes.tolist()), f"{b}: every node in a piece")
        check(sorted(got) == sorted(ref), f"{b}: the same arrays")
        for k in ref:
            if k not in got:
                continue
            if k == "connectivity":  # the pieces' own node numbers, as the mesh's
                check((nodes[got[k]] == ref_nodes[ref[k][cells]]).all(),
                      f"{b}: the same cells' nodes")
                continue
            point = k.startswith("point:") or k == "Points"
            rows = [row_of.get(g, -1) for g in nodes.tolist()] if point else cells
            check(got[k].dtype == ref[k].dtype and
                  got[k].tobytes() == ref[k][rows].tobytes(), f"{b}: {k} bit-identical")
    print(f"check_vtu: {dist} against {serial}: {checks['passed']} passed, "
          f"{checks['failed']} failed")
    return 1 if checks["failed"] else 0


def main(argv):
    if argv[:1] in (["-h"], ["--help"]):
        print(__doc__)
        return 0
    try:
        if argv[:1] == ["--same"] and len(argv) == 3:
            return same(*argv[1:3])
        if argv[:1] == ["--formats"] and len(argv) in (4, 5):
            return formats(argv[1:])
        if argv[:1] == ["--run"] and len(argv) in (4, 5):
            binary, case, out = argv[1:4]
            run_short(binary, case, out, float(argv[4]) if len(argv) > 4 else 2.0e-5)
            return check_folder(out, RUN_FIELDS)
        if len(argv) == 3 and argv[1] == "--fields":
            return check_folder(argv[0], [f for f in argv[2].split(",") if f])
        if len(argv) == 1 and not argv[0].startswith("-"):
            return check_folder(argv[0])
        print(__doc__, file=sys.stderr)
        return 2
    except (BadFolder, OSError, ValueError, ET.ParseError, K.MissingKey) as e:
        print(f"check_vtu.py: error: {e}", file=sys.stderr)
        return 2
    except subprocess.CalledProcessError as e:
        print(f"check_vtu.py: error: the run failed: {' '.join(e.cmd)}: exit {e.returncode}",
              file=sys.stderr)
        return 2


def frame_list(out, pvd):
    """(time, file) of each frame a .pvd lists."""
    path = os.path.join(out, pvd)
    if not os.path.isfile(path):
        raise BadFolder(f"{path}: no such file (not a run's output folder?)")
    series = ET.parse(path).getroot().find("Collection")
    if series is None:
        raise BadFolder(f"{path}: no Collection of frames")
    return [(float(d.get("timestep")), d.get("file")) for d in series.findall("DataSet")]


def arrays_of(grid):
    """{name: (where, components)} of a grid's node and cell arrays (body: 'both')."""
    found = {}
    for where, data in (("point", grid.GetPointData()), ("cell", grid.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            name = data.GetArrayName(i)
            comps = data.GetArray(i).GetNumberOfComponents()
            found[name] = ("both", comps) if name in found else (where, comps)
    return found


def check_fields(grid, fields, name):
    """Each field asked for in its place with its component count, finite; nothing asked for
    missing; the program's own extra arrays allowed."""
    found = arrays_of(grid)
    for field in fields:
        where, comps = FIELDS[field]
        for w in (("point", "cell") if where == "both" else (where,)):
            data = grid.GetPointData() if w == "point" else grid.GetCellData()
            check_arrays(data, {field: comps}, f"{name} ({w} data)")
    for array in sorted(set(found) - set(fields) - set(EXTRA)):
        check(False, f"{name}: array {array} written, not asked for ({', '.join(fields)})")


def check_folder(out, fields=None):
    """Checks a run's folder; `fields` the output.fields it asked for, else the first frame's
    arrays. 0 when every check passes, 1 otherwise; BadFolder when it is not a run's."""
    failed_before = checks["failed"]
    path = os.path.join(out, "summary.json")
    if not os.path.isfile(path):
        raise BadFolder(f"{path}: no such file (not a run's output folder?)")
    with open(path) as f:
        summary = json.load(f)
    nodes, tets = K.get(summary, K.MESH_NODES, path), K.get(summary, K.MESH_TETS, path)
    frames = frame_list(out, "case.pvd")
    check(len(frames) >= 2, "at least two frames in case.pvd")
    check(all(a[0] < b[0] for a, b in zip(frames, frames[1:])), "frame times increase")
    if fields is None and frames:
        first = read(os.path.join(out, frames[0][1]), frames[0][1])
        fields = [a for a in arrays_of(first) if a in FIELDS]
        print(f"check_vtu: {out}: the arrays of the first frame: {', '.join(fields) or 'none'}")
    if K.get(summary, K.FRACTURE_ENABLED, path) and "damage" not in fields:
        fields = fields + ["damage"]  # the program adds it whenever fracture is on
    unknown = [f for f in fields or [] if f not in FIELDS]
    if unknown:
        raise BadFolder(f"unknown output field {', '.join(unknown)} (known: {', '.join(FIELDS)})")
    particles = {}  # time → particle count, from particles.pvd
    if os.path.exists(os.path.join(out, "particles.pvd")):
        pframes = frame_list(out, "particles.pvd")
        check([t for t, _ in pframes] == [t for t, _ in frames], "particle frames at the frame times")
        for t, name in pframes:
            if not os.path.isfile(os.path.join(out, name)):
                check(False, f"{name}: the file particles.pvd lists is there")
                continue
            grid = read(os.path.join(out, name), name)
            n = grid.GetNumberOfPoints()
            particles[t] = n
            check(grid.GetNumberOfCells() == n, f"{name}: one vertex per particle")
            found = check_arrays(grid.GetPointData(), PARTICLE_ARRAYS, name)
            for array in ("radius", "mass"):
                if n and array in found:
                    check(found[array].min() > 0, f"{name}: {array} positive")
        check(particles.get(frames[-1][0], 0) == K.get(summary, K.FRACTURE_PARTICLES, path),
              "the last particle frame holds summary.fracture.particles")
    for t, name in frames:
        if not os.path.isfile(os.path.join(out, name)):
            check(False, f"{name}: the file case.pvd lists is there")
            continue
        grid = read(os.path.join(out, name), name)
        if grid is None or grid.GetPoints() is None:
            check(False, f"{name}: VTK reads points from it")
            continue
        pieces = grid.GetPointData().GetArray("global_node")
        converted = particles.get(t, 0) > 0  # cells turned into particles may leave nodes out
        if name.endswith(".pvtu"):  # pieces: each shared node in every piece that uses it
            held = len(set(vtk_to_numpy(pieces).tolist())) if pieces is not None else -1
            check(held == nodes or (converted and 0 < held < nodes),
                  f"{name}: the pieces hold the {nodes} nodes (fewer once cells convert)")
        else:
            points = grid.GetNumberOfPoints()
            check(points == nodes or (converted and 0 < points < nodes and pieces is not None),
                  f"{name}: {nodes} points (fewer, with their mesh numbers, once cells convert)")
            names = grid.GetFieldData().GetAbstractArray("body_names")
            check(names is not None and
                  [names.GetValue(i) for i in range(names.GetNumberOfValues())] ==
                  [b[K.NAME] for b in K.get(summary, K.BODIES, path)],
                  f"{name}: field data body_names lists the bodies in order")
        if grid.GetNumberOfCells():  # no loose points: a node left by converted cells is not written
            used = np.unique(vtk_to_numpy(grid.GetCells().GetConnectivityArray()))
            check(len(used) == grid.GetNumberOfPoints(), f"{name}: every point belongs to a cell")
        cells = tets - particles.get(t, 0)  # cells turned into particles leave the mesh
        check(grid.GetNumberOfCells() == cells, f"{name}: {cells} cells")
        types = vtk_to_numpy(grid.GetCellTypesArray())
        check((types == vtk.VTK_TETRA).all(), f"{name}: only linear tetrahedra")
        check_fields(grid, fields, name)
        if grid.GetNumberOfCells():
            quality = vtk.vtkMeshQuality()
            quality.SetInputData(grid)
            quality.SetTetQualityMeasureToVolume()
            quality.Update()
            vol = vtk_to_numpy(quality.GetOutput().GetCellData().GetArray("Quality"))
            check(vol.min() > 0, f"{name}: every tet has positive volume in VTK's convention")
        disp = grid.GetPointData().GetArray("displacement")
        if t == 0.0 and disp is not None:
            check(abs(vtk_to_numpy(disp)).max() == 0.0, f"{name}: zero displacement at t = 0")
    print(f"check_vtu: {out}: {checks['passed']} passed, {checks['failed']} failed")
    return 1 if checks["failed"] > failed_before else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
