#!/usr/bin/python3
"""The figures of the paper's ball through a plate (Dobritsa et al. 2019, Fig. 5) from a
finished run of ball-plate.yaml: the ball's residual velocity (summary.json), the hole in the
plate (the last frame: plate cells centred in the plate's original layer, −h ≤ z ≤ 0, the
nearest one to the impact axis x = y = 0 gives the hole's radius), and the particles from each
body with their mass.

    ball_plate_report.py OUTDIR [--thickness H] [--pictures DIR] [--slab W]

--thickness  the plate's thickness (default 2e-3 m); --pictures  also render the y = 0 section
at the paper's times (0, 0.25, 0.4, 0.6, 0.95 and 4.0 µs: the frame nearest each, each once)
with the particles within --slab of the plane (default 1e-3 m), all framed at one common extent
(what the chosen frames show together), with axes in mm, a scale bar, the time and a legend: as
DIR/ball-plate-<t>us.png, and side by side as DIR/ball-plate-sequence.png
(tools/post/section_png.py and sequence_png.py draw them).

Needs Debian's python3-vtk9, python3-numpy and python3-matplotlib (run with /usr/bin/python3).
Exit code 0, or 2 on bad input."""
import json
import os
import re
import sys
import xml.etree.ElementTree as ET

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import summary_keys as K  # noqa: E402

import numpy as np  # noqa: E402 (after tools.common: a missing module is said plainly)

PAPER_TIMES = [0.0, 0.25e-6, 0.4e-6, 0.6e-6, 0.95e-6, 4.0e-6]  # s, the paper's Fig. 5 frames


def fail(msg):
    print("ball_plate_report.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def hole_radius(pts, conn, body, plate, thickness):
    """The distance from the axis x = y = 0 to the nearest centre of a `plate` cell in the
    plate's original layer (−thickness ≤ z ≤ 0); inf when none is left."""
    centres = pts[conn].mean(axis=1)
    layer = (body == plate) & (centres[:, 2] >= -thickness) & (centres[:, 2] <= 0)
    return float(np.hypot(centres[layer, 0], centres[layer, 1]).min()) if layer.any() else float("inf")


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    out, opts = argv[0], {"--thickness": "2e-3", "--pictures": None, "--slab": "1e-3"}
    rest = argv[1:]
    while rest:
        if rest[0] not in opts or len(rest) < 2:
            fail("usage: ball_plate_report.py OUTDIR [--thickness H] [--pictures DIR] [--slab W]")
        opts[rest[0]] = rest[1]
        rest = rest[2:]
    try:
        thickness, slab = float(opts["--thickness"]), float(opts["--slab"])
    except ValueError:
        fail("--thickness and --slab must be lengths in metres")
    for f in ("summary.json", "case.pvd"):
        if not os.path.isfile(os.path.join(out, f)):
            fail(os.path.join(out, f) + ": no such file (run the case first)")
    path = os.path.join(out, "summary.json")
    with open(path) as f:
        summary = json.load(f)
    frames = ET.parse(os.path.join(out, "case.pvd")).getroot().find("Collection").findall("DataSet")
    if not frames:
        fail(os.path.join(out, "case.pvd") + ": lists no frame")
    try:
        names = [b[K.NAME] for b in K.get(summary, K.BODIES, path)]
        if "plate" not in names or "ball" not in names:
            fail("the run has no bodies named 'ball' and 'plate' (it has %s)" % ", ".join(names))

        from tools.post import section_png as sp

        pts, conn, body = sp.read_frame(os.path.join(out, frames[-1].get("file")))
        radius = hole_radius(pts, conn, body, names.index("plate"), thickness)
        ball = K.get(summary, K.BODIES)[names.index("ball")]
        print("time %.3g s, status %s, %d steps, wall %.1f s" %
              (K.get(summary, K.TIME), K.get(summary, K.STATUS), K.get(summary, K.STEPS),
               K.get(summary, K.WALL_SECONDS)))
        print("ball residual velocity %.1f m/s (z), mass %.4g kg" % (ball[K.VELOCITY][2],
                                                                    ball[K.MASS]))
        print("hole diameter %.2f mm (nearest plate cell of the original layer to the axis)" %
              (2e3 * radius))
        print("particles %d, mass %.4g kg" % (K.get(summary, K.FRACTURE_PARTICLES),
                                             K.get(summary, K.FRACTURE_MASS_TO_PARTICLES)))
        for b in summary["fracture"].get(K.FRACTURE_FROM_BODIES[1], []):
            print("  from %s: %d particles, %.4g kg" % (b[K.NAME], b[K.PARTICLES], b[K.MASS]))
        inside = (K.get(summary, K.PARTICLES_INSIDE_AT_END)
                  if K.has(summary, K.PARTICLES_INSIDE_AT_END) else None)
        print("mass error %.2g, momentum error %.2g, energy balance max %.2g, particles inside "
              "at end %s" % (K.get(summary, K.MASS_ERROR), K.get(summary, K.MOMENTUM_ERROR),
                             K.get(summary, K.ENERGY_BALANCE_ERROR_MAX), inside))
    except K.MissingKey as e:
        fail(str(e))
    if opts["--pictures"] is not None:
        pictures(out, frames, opts["--pictures"], slab)
    return 0


def pictures(out, frames, folder, slab):
    """The y = 0 sections at the paper's times, one window for all."""
    from tools.post import section_png as sp
    from tools.post import sequence_png as seq

    os.makedirs(folder, exist_ok=True)
    times = [float(d.get("timestep")) for d in frames]
    paper = {}  # frame index → the first paper time it stands for
    for t in PAPER_TIMES:
        paper.setdefault(min(range(len(times)), key=lambda i: abs(times[i] - t)), t)
    picks = sorted(paper)
    numbers = [int(re.fullmatch(r"frame_(\d+)\.vtu", frames[k].get("file")).group(1)) for k in picks]
    chosen = [seq.Frame(out, n, times[k]) for n, k in zip(numbers, picks)]
    axis, at, inplane = 1, 0.0, [0, 2]
    window = seq.common_window(chosen, axis, at, slab)
    print("window: x %.3f to %.3f mm, z %.3f to %.3f mm (every picture)" %
          (window[0][0] * 1e3, window[1][0] * 1e3, window[0][1] * 1e3, window[1][1] * 1e3))
    bodies = max(int(f.body.max()) + 1 for f in chosen)
    _, names = sp.run_info(os.path.join(out, frames[0].get("file")))
    names = sp.body_names(names, bodies)
    panels = []
    for k, f in zip(picks, chosen):
        rgb, cut, drawn = seq.panel(f, axis, at, window, 600, bodies, slab)
        png = os.path.join(folder, "ball-plate-%.2fus.png" % (paper[k] * 1e6))
        sp.picture(rgb, window, inplane, png, f.time, names, True)
        panels.append((f.time, rgb))
        print("%s (t = %.3g s): %d polygons cut, %d particles drawn" % (png, f.time, cut, drawn))
    fig = seq.figure(panels, window, inplane, names, True)
    png = os.path.join(folder, "ball-plate-sequence.png")
    sp.save_figure(fig, png, dpi=150)
    print("written: " + png)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
