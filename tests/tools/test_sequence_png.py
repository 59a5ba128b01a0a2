"""tools/post/sequence_png.py: every panel framed at one common extent that holds what all the
chosen frames show (a body moving between frames moves across the picture, the picture does
not follow it); the particles within the slab around the plane drawn, projected, not only those
the plane cuts (pixel counts); times, axes in mm and the bodies' legend; on fake frames written
here with VTK, and on a small Whipple shield's debris cloud."""
import json
import os

import numpy as np
import pytest

from conftest import SMALL_WHIPPLE, case, run_case, run_tool
from tools.post import section_png as sp
from tools.post import sequence_png as seq

MM = 1e-3


def write_vtu(path, points, tets=None, cell_body=None, point_arrays=None):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    grid = vtk.vtkUnstructuredGrid()
    p = vtk.vtkPoints()
    p.SetData(numpy_to_vtk(np.asarray(points, dtype=float), deep=True))
    grid.SetPoints(p)
    if tets is not None:
        for t in tets:
            ids = vtk.vtkIdList()
            for v in t:
                ids.InsertNextId(int(v))
            grid.InsertNextCell(vtk.VTK_TETRA, ids)
        a = numpy_to_vtk(np.asarray(cell_body, dtype=np.int32), deep=True)
        a.SetName("body")
        grid.GetCellData().AddArray(a)
    else:
        for i in range(len(points)):
            ids = vtk.vtkIdList()
            ids.InsertNextId(i)
            grid.InsertNextCell(vtk.VTK_VERTEX, ids)
    for name, values in (point_arrays or {}).items():
        a = numpy_to_vtk(np.asarray(values), deep=True)
        a.SetName(name)
        grid.GetPointData().AddArray(a)
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(grid)
    assert w.Write() == 1


def cube(lo, size):
    """A cube's 8 corners and its 6 tets (Kuhn split)."""
    import itertools
    corners = np.array([[lo[0] + i * size, lo[1] + j * size, lo[2] + k * size]
                        for k, j, i in itertools.product(range(2), range(2), range(2))])
    index = {(i, j, k): n for n, (k, j, i) in enumerate(itertools.product(range(2), range(2), range(2)))}
    tets = []
    for perm in itertools.permutations(range(3)):
        o = [0, 0, 0]
        t = [index[(0, 0, 0)]]
        for ax in perm:
            o[ax] = 1
            t.append(index[tuple(o)])
        tets.append(t)
    return corners, tets


@pytest.fixture
def fake_run(tmp_path):
    """Three frames: a 'block' (body 0) resting, a 'ball' (body 1, a 2 mm cube) falling from
    z = 10 mm to z = -20 mm; the last frame with two particles of the ball: one cut by the
    plane y = 0, one 1.5 mm off it (radius 0.5 mm: the plane does not cut it)."""
    run = str(tmp_path)
    block_pts, block_tets = cube([-5 * MM, -5 * MM, -10 * MM], 10 * MM)
    collection = []
    for n, (t, z) in enumerate([(0.0, 10 * MM), (1e-6, -5 * MM), (2e-6, -20 * MM)]):
        ball_pts, ball_tets = cube([-1 * MM, -1 * MM, z], 2 * MM)
        pts = np.vstack([block_pts, ball_pts])
        tets = block_tets + [[v + 8 for v in t_] for t_ in ball_tets]
        write_vtu(os.path.join(run, "frame_%04d.vtu" % n), pts, tets, [0] * 6 + [1] * 6)
        centres = np.zeros((0, 3)) if n < 2 else np.array([[3 * MM, 0.0, -25 * MM],
                                                            [-3 * MM, 1.5 * MM, -25 * MM]])
        write_vtu(os.path.join(run, "particles_%04d.vtu" % n), centres,
                  point_arrays={"radius": np.full(len(centres), 0.5 * MM),
                                "body": np.ones(len(centres), dtype=np.int32)})
        collection.append(f'<DataSet timestep="{t!r}" part="0" file="frame_{n:04d}.vtu"/>')
    with open(os.path.join(run, "case.pvd"), "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
                + "\n".join(collection) + "\n</Collection>\n</VTKFile>\n")
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"bodies": [{"name": "block"}, {"name": "ball"}]}, f)
    return run


def dark_pixels(rgb, body=1):
    return int((rgb == np.array(sp.particle_colour(body), dtype=np.uint8)).all(axis=2).sum())


def test_common_extent_holds_every_frame(fake_run):
    frames = [seq.Frame(fake_run, n, t) for n, t in enumerate([0.0, 1e-6, 2e-6])]
    window = seq.common_window(frames, 1, 0.0, 2 * MM)
    lo, hi = window
    # x: the block's ±5 mm; z: from the particles' bottom (−25.5 mm) to the ball's first top
    # (12 mm); padded by 5 % of the larger side (37.5 mm).
    pad = 0.05 * 37.5 * MM
    assert lo == pytest.approx([-5 * MM - pad, -25.5 * MM - pad])
    assert hi == pytest.approx([5 * MM + pad, 12 * MM + pad])
    # The first frame's own content would not hold the last frame's ball.
    first = seq.common_window(frames[:1], 1, 0.0, 2 * MM)
    assert first[0][1] > -20 * MM


def test_panels_share_the_window_and_draw_the_slab(fake_run, out):
    png = os.path.join(out, "seq.png")
    r = run_tool("post/sequence_png.py", fake_run, png, "--frames", "0,1,2", "--slab", "2e-3",
                 "--width", "300", check=0)
    lines = [x for x in r.stdout.splitlines() if x.startswith("frame ")]
    assert len(lines) == 3
    assert lines[2].endswith("2 particles drawn")  # the one off the plane too
    assert r.stdout.startswith("window: x -6.875 to 6.875 mm, z -27.375 to 13.875 mm")
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    # The same panels in the test: the same extent on every axes, times, labels, legend.
    frames = [seq.Frame(fake_run, n, t) for n, t in enumerate([0.0, 1e-6, 2e-6])]
    window = seq.common_window(frames, 1, 0.0, 2 * MM)
    panels = [(f.time, seq.panel(f, 1, 0.0, window, 300, 2, 2 * MM)[0]) for f in frames]
    fig = seq.figure(panels, window, [0, 2], ["block", "ball"], True)
    axes = [ax for ax in fig.axes if ax.images]
    assert len(axes) == 3
    assert len({ax.get_xlim() for ax in axes}) == 1 and len({ax.get_ylim() for ax in axes}) == 1
    assert [ax.get_title() for ax in axes] == ["t = 0.00 µs", "t = 1.00 µs", "t = 2.00 µs"]
    assert all(ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "z (mm)" for ax in axes)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels[:2] == ["block", "ball"] and "ball particles" in labels


def test_particles_off_the_plane_drawn_within_the_slab(fake_run):
    frame = seq.Frame(fake_run, 2, 2e-6)
    window = seq.common_window([frame], 1, 0.0, 2 * MM)
    rgb_cut, _, cut = seq.panel(frame, 1, 0.0, window, 400, 2, 0.0)
    rgb_slab, _, slab = seq.panel(frame, 1, 0.0, window, 400, 2, 2 * MM)
    assert (cut, slab) == (1, 2)
    px = (window[1][0] - window[0][0]) / 400
    disc = np.pi * (0.5 * MM / px) ** 2  # one particle's disc, in pixels
    assert dark_pixels(rgb_cut) == pytest.approx(disc, rel=0.1)
    assert dark_pixels(rgb_slab) == pytest.approx(2 * disc, rel=0.1)
    # Outside a thinner slab (1 mm) the off-plane particle is not drawn.
    assert seq.panel(frame, 1, 0.0, window, 400, 2, 1 * MM)[2] == 1


def test_whipple_debris_cloud(binary, out):
    """The small Whipple shield: far more particles drawn with the slab than the plane cuts."""
    run = os.path.join(out, "run")
    run_case(binary, case("whipple"), run, *SMALL_WHIPPLE)
    drawn = {}
    for slab in ("0", "1e-3"):
        r = run_tool("post/sequence_png.py", run, os.path.join(out, f"seq-{slab}.png"),
                     "--frames", "3", "--slab", slab, check=0)
        drawn[slab] = int(r.stdout.split("polygons cut, ")[1].split(" particles")[0])
    assert drawn["1e-3"] > 3 * drawn["0"] > 0
    r = run_tool("post/sequence_png.py", run, os.path.join(out, "x.png"), "--frames", "99",
                 check=2)
    assert "no frame 99" in r.stderr
