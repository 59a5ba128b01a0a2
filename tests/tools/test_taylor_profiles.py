"""tools/post/taylor_profiles.py: the shipped index names for each digitised outline a test whose
final length and D0 the outline matches; the computed outline of a run is its original lateral
surface at the end, exact on a rod whose radius grows by a known law (the mean |Δr| / R0 of an
outline drawn from that law is 0, of one 0.1 mm wider 0.1 mm / R0); a wrong line in the index and
a folder without the run are refused (exit 2)."""
import math
import os

import numpy as np
import vtk

from conftest import ROOT, run_tool
from tools.post import taylor_profiles as tp

VALIDATION = os.path.join(ROOT, "data", "validation")
R0, L0, LF = 3.0e-3, 20.0e-3, 15.0e-3  # m


def widened(z):
    """The rod's radius at height z (m) of the deformed rod: 3 mm at the top, 4.5 at the anvil."""
    return R0 * (1.5 - 0.5 * z / LF)


def write_frame(path, points):
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(*p)
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(pts)
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    assert writer.Write() == 1


def fake_campaign(folder, line):
    """A campaign folder with one run of `line`: a quarter rod's nodes (rings at r = R0 and
    R0 / 2 and the axis, 11 heights), shortened to LF and widened by `widened`, then lifted
    0.2 mm off the anvil (the rebound)."""
    run = os.path.join(folder, "runs", "row-1_0")
    os.makedirs(run)
    start, end = [], []
    for k in range(11):
        z0 = L0 * k / 10
        z1 = LF * k / 10
        for r0 in (R0, R0 / 2, 0.0):
            for a in np.linspace(0, math.pi / 2, 5 if r0 > 0 else 1):
                start.append((r0 * math.cos(a), r0 * math.sin(a), z0))
                r1 = r0 * widened(z1) / R0
                end.append((r1 * math.cos(a), r1 * math.sin(a), z1 + 0.2e-3))
    write_frame(os.path.join(run, "frame_0000.vtu"), start)
    write_frame(os.path.join(run, "frame_0001.vtu"), end)
    with open(os.path.join(run, "case.pvd"), "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection"><Collection>\n'
                '<DataSet timestep="0" file="frame_0000.vtu"/>\n'
                '<DataSet timestep="1" file="frame_0001.vtu"/>\n</Collection></VTKFile>\n')
    with open(os.path.join(folder, "predictions.csv"), "w") as f:
        f.write(f"row,line,folder\n1,{line},row-1_0\n")


def test_every_shipped_outline_matches_its_test():
    profiles = tp.checked_profiles(os.path.join(VALIDATION, "taylor-profiles.csv"),
                                   os.path.join(VALIDATION, "taylor-tests.csv"),
                                   os.path.join(VALIDATION, "taylor-profiles"))
    assert len(profiles) == 14
    assert len({test["#line"] for _, test, _ in profiles}) == 14
    names = sorted(os.listdir(os.path.join(VALIDATION, "taylor-profiles")))
    assert sorted(name for name, _, _ in profiles) == names


def test_the_computed_outline_is_the_original_surface(out):
    fake_campaign(out, 7)
    outline, foot = tp.computed_outline(os.path.join(out, "runs", "row-1_0"))
    assert len(outline) == 11
    for k, (r, z) in enumerate(outline):  # mm, from the rod's lowest node
        assert abs(z - 1e3 * LF * k / 10) < 1e-9
        assert abs(r - 1e3 * widened(LF * k / 10)) < 1e-9
    assert abs(foot - 1e3 * widened(0.0)) < 1e-9
    # A digitised outline of the same law: no difference; 0.1 mm wider: 0.1 mm / R0 everywhere.
    drawn = [(1e3 * widened(z), 1e3 * z) for z in np.linspace(0, LF, 7)]
    mean, largest = tp.compare(drawn, outline, 1e3 * R0)
    assert mean < 1e-9 and largest < 1e-9
    wider = [(r + 0.1, z) for r, z in drawn]
    mean, largest = tp.compare(wider, outline, 1e3 * R0)
    assert abs(mean - 0.1 / (1e3 * R0)) < 1e-9 and abs(largest - 0.1 / (1e3 * R0)) < 1e-9


def test_refusals(out):
    index = os.path.join(out, "index.csv")
    os.makedirs(os.path.join(out, "taylor-profiles"))
    name = "taylorCuWilkinsGuinan.dat"
    with open(os.path.join(VALIDATION, "taylor-profiles", name)) as f:
        text = f.read()
    with open(os.path.join(out, "taylor-profiles", name), "w") as f:
        f.write(text)
    table = os.path.join(VALIDATION, "taylor-tests.csv")
    with open(index, "w") as f:
        f.write("file,line\n" + name + ",134\n")  # the 204 m/s rod, 15.7 mm: not this outline
    r = run_tool("post/taylor_profiles.py", out, "--index", index, "--table", table, check=2)
    assert "taylorCuWilkinsGuinan.dat: its top 15.03 mm is not the final length 15.7 mm" in r.stderr
    with open(index, "w") as f:
        f.write("file,line\n" + name + ",135\n")
    r = run_tool("post/taylor_profiles.py", out, "--index", index, "--table", table, check=2)
    assert "predictions.csv: no such file (not a campaign folder)" in r.stderr
    fake_campaign(os.path.join(out, "campaign"), 7)
    r = run_tool("post/taylor_profiles.py", os.path.join(out, "campaign"), "--index", index,
                 "--table", table, check=2)
    assert "no run of line 135 (the test of taylorCuWilkinsGuinan.dat)" in r.stderr
    fake_campaign(os.path.join(out, "ok"), 135)
    png = os.path.join(out, "profiles.png")
    r = run_tool("post/taylor_profiles.py", os.path.join(out, "ok"), "--index", index,
                 "--table", table, "--out", png, check=0)
    assert r.stdout.splitlines()[1].startswith("taylorCuWilkinsGuinan.dat,135,Cu OFHC,210,294,ok,")
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
