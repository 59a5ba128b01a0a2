"""tools/post/ball_plate_report.py on a coarse ball-plate run to 4 µs: the figures it prints
against the run's summary.json, the hole measure on a made-up plate, and the pictures at the
paper's times (Dobritsa et al. 2019, Fig. 5) at one common extent with labels."""
import os
import re

import numpy as np
import pytest

from conftest import case, run_case, run_tool
from tools.post import ball_plate_report as bpr

COARSE = ["bodies.0.mesh.sphere.cells_across=6", "bodies.1.mesh.box.cells=[20,20,1]",
          "end_time=4.0e-6", "output.interval=0.05e-6", "output.history_every=10"]


@pytest.fixture(scope="module")
def run(binary, module_out):
    out = os.path.join(module_out, "run")
    return out, run_case(binary, case("ball-plate"), out, *COARSE)


def test_report_matches_the_summary(run, out):
    folder, summary = run
    r = run_tool("post/ball_plate_report.py", folder, "--pictures", out, check=0)
    ball = summary["bodies"][[b["name"] for b in summary["bodies"]].index("ball")]
    assert f"ball residual velocity {ball['velocity'][2]:.1f} m/s (z)" in r.stdout
    assert f"particles {summary['fracture']['particles']}, " in r.stdout
    for b in summary["fracture"]["from_bodies"]:
        assert f"  from {b['name']}: {b['particles']} particles" in r.stdout
    hole = float(re.search(r"hole diameter ([0-9.]+) mm", r.stdout).group(1))
    assert 0 < hole < 60  # inside the 60 mm plate
    # Six paper times, each its own picture, and the sequence.
    pngs = sorted(f for f in os.listdir(out) if f.endswith(".png"))
    assert pngs == ["ball-plate-0.00us.png", "ball-plate-0.25us.png", "ball-plate-0.40us.png",
                    "ball-plate-0.60us.png", "ball-plate-0.95us.png", "ball-plate-4.00us.png",
                    "ball-plate-sequence.png"]
    # One window for every picture, and it holds the ball's start (its top at z = 20 mm).
    windows = re.findall(r"^window: x (\S+) to (\S+) mm, z (\S+) to (\S+) mm \(every picture\)$",
                         r.stdout, re.M)
    assert len(windows) == 1
    x0, x1, z0, z1 = map(float, windows[0])
    assert z1 >= 20.0 and x0 <= -30.0 and x1 >= 30.0


def test_pictures_share_one_extent_with_labels(run):
    folder, _ = run
    from tools.post import section_png as sp
    from tools.post import sequence_png as seq
    times = seq.frame_times(folder)
    numbers = sorted(times)
    frames = [seq.Frame(folder, n, times[n]) for n in (numbers[0], numbers[len(numbers) // 4],
                                                        numbers[-1])]
    window = seq.common_window(frames, 1, 0.0, 1e-3)
    panels = [(f.time, seq.panel(f, 1, 0.0, window, 200, 2, 1e-3)[0]) for f in frames]
    assert len({p[1].shape for p in panels}) == 1  # the same pixels, the same extent
    fig = seq.figure(panels, window, [0, 2], ["ball", "plate"], True)
    axes = [ax for ax in fig.axes if ax.images]
    assert len({(ax.get_xlim(), ax.get_ylim()) for ax in axes}) == 1
    assert all(re.fullmatch(r"t = \d\.\d\d µs", ax.get_title()) for ax in axes)
    assert all(any("SizeBar" in type(a).__name__ for a in ax.artists) for ax in axes)
    # The ball moves down across the fixed picture: its lowest pixel row rises in the image.
    def lowest_ball_row(rgb):
        rows = np.nonzero((rgb == np.array(sp.PALETTE[0], dtype=np.uint8)).all(axis=2).any(axis=1))[0]
        return rows.min()
    assert lowest_ball_row(panels[0][1]) > lowest_ball_row(panels[2][1])


def test_hole_radius():
    """Plate cells centred at 3 mm and 5 mm from the axis in the layer, one below it."""
    pts = np.repeat([[3e-3, 0, -1e-3], [0, 5e-3, -1e-3], [1e-3, 0, -3e-3]], 4, axis=0)
    conn = np.arange(12).reshape(3, 4)
    assert bpr.hole_radius(pts, conn, np.array([1, 1, 1]), 1, 2e-3) == pytest.approx(3e-3)
    assert bpr.hole_radius(pts, conn, np.array([0, 1, 1]), 1, 2e-3) == pytest.approx(5e-3)
    assert bpr.hole_radius(pts, conn, np.array([0, 0, 1]), 1, 2e-3) == float("inf")


def test_bad_input(binary, out, tmp_path):
    r = run_tool("post/ball_plate_report.py", str(tmp_path), check=2)
    assert "summary.json: no such file" in r.stderr
    other = os.path.join(out, "cubes")
    run_case(binary, case("cubes-edge"), other, "end_time=1e-6")
    r = run_tool("post/ball_plate_report.py", other, check=2)
    assert "no bodies named 'ball' and 'plate' (it has left, right)" in r.stderr
    r = run_tool("post/ball_plate_report.py", other, "--thickness", check=2)
    assert "usage" in r.stderr
