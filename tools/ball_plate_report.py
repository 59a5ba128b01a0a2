#!/usr/bin/python3
"""The figures issue 6 asks of ball-plate.yaml, from a finished run's folder: the ball's residual
velocity (summary.json), the hole in the plate (the last frame: plate cells centred in the plate's
original layer, −h ≤ z ≤ 0, the nearest one to the impact axis x = y = 0 gives the hole's
radius), and the particles from each body with their mass.

    ball_plate_report.py OUTDIR [--thickness H] [--pictures DIR]

--thickness  the plate's thickness (default 2e-3 m); --pictures  also render the y = 0 section
at the paper's times (0, 0.25, 0.4, 0.6, 0.95 and 4.0 µs: the frame nearest each) with the
particles, as DIR/ball-plate-<t>us.png (tools/section_png.py).

Needs Debian's python3-vtk9 and python3-numpy (run with /usr/bin/python3). Exit code 0, or 2 on
bad input."""
import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np


def fail(msg):
    print("ball_plate_report.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    out, opts = argv[0], {"--thickness": "2e-3", "--pictures": None}
    rest = argv[1:]
    while rest:
        if rest[0] not in opts or len(rest) < 2:
            fail("usage: ball_plate_report.py OUTDIR [--thickness H] [--pictures DIR]")
        opts[rest[0]] = rest[1]
        rest = rest[2:]
    thickness = float(opts["--thickness"])
    for f in ("summary.json", "case.pvd"):
        if not os.path.isfile(os.path.join(out, f)):
            fail(os.path.join(out, f) + ": no such file (run the case first)")
    summary = json.load(open(os.path.join(out, "summary.json")))
    frames = ET.parse(os.path.join(out, "case.pvd")).getroot().find("Collection").findall("DataSet")
    last = os.path.join(out, frames[-1].get("file"))

    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(last)
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4)
    body = vtk_to_numpy(g.GetCellData().GetArray("body")).astype(int)
    names = [b["name"] for b in summary["bodies"]]
    if "plate" not in names or "ball" not in names:
        fail("the run has no bodies named 'ball' and 'plate'")
    centres = pts[conn].mean(axis=1)
    layer = (body == names.index("plate")) & (centres[:, 2] >= -thickness) & (centres[:, 2] <= 0)
    radius = np.hypot(centres[layer, 0], centres[layer, 1]).min() if layer.any() else float("inf")

    ball = summary["bodies"][names.index("ball")]
    fr = summary["fracture"]
    print("time %.3g s, status %s, %d steps, wall %.1f s" %
          (summary["time"], summary["status"], summary["steps"], summary["wall_seconds"]))
    print("ball residual velocity %.1f m/s (z), mass %.4g kg" % (ball["velocity"][2], ball["mass"]))
    print("hole diameter %.2f mm (nearest plate cell of the original layer to the axis)" %
          (2e3 * radius))
    print("particles %d, mass %.4g kg" % (fr["particles"], fr["mass_to_particles"]))
    for b in fr.get("from_bodies", []):
        print("  from %s: %d particles, %.4g kg" % (b["name"], b["particles"], b["mass"]))
    print("mass error %.2g, momentum error %.2g, energy balance max %.2g, particles inside at end %s" %
          (summary["mass"]["relative_error"], summary["momentum"]["relative_error"],
           summary["energy"]["balance_error_max"],
           summary["penetration"].get("particles_inside_at_end")))
    if opts["--pictures"] is not None:
        pictures(out, frames, opts["--pictures"])
    return 0


def pictures(out, frames, folder):
    import subprocess

    os.makedirs(folder, exist_ok=True)
    tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "section_png.py")
    times = [float(d.get("timestep")) for d in frames]
    for t in (0.0, 0.25e-6, 0.4e-6, 0.6e-6, 0.95e-6, 4.0e-6):
        k = min(range(len(times)), key=lambda i: abs(times[i] - t))
        frame = frames[k].get("file")
        particles = os.path.join(out, frame.replace("frame_", "particles_"))
        png = os.path.join(folder, "ball-plate-%.2fus.png" % (t * 1e6))
        cmd = [sys.executable, tool, os.path.join(out, frame), png, "--at", "0", "--width", "600"]
        if os.path.isfile(particles):
            cmd += ["--particles", particles]
        line = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip()
        print("%s (t = %.3g s): %s" % (png, times[k], line))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
