#!/usr/bin/python3
"""A picture sequence of a run, like the paper's figures: cross-sections of chosen output
frames side by side (four to a row) at one scale, each cut by the same plane, cells coloured by body, the
particles of fracture as darker discs, overlap (interpenetration) in red, the time above each.

    sequence_png.py RUN_DIR OUT.png [--frames I,J,...] [--normal x|y|z] [--at C] [--width PX]

RUN_DIR is a run's output folder (case.pvd, frame_NNNN.vtu, particles_NNNN.vtu). --frames: the
frame numbers (default: four spread over the run, the first and the last among them);
--normal/--at: the plane (default y = 0); --width: pixels per panel (default 400). The window
is the in-plane extent of the first frame's mesh (every body intact), padded by 5 %: what
leaves it is not drawn. Prints one line per panel (time, polygons cut, particles drawn).
Writes OUT.png through a temporary file. Needs python3-vtk9, python3-numpy and
python3-matplotlib (run with /usr/bin/python3). Exit code 0, or 2 on bad input."""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import section_png as sp  # noqa: E402


def fail(msg):
    print("sequence_png.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def frame_times(run):
    """{frame number: time} from the run's case.pvd."""
    pvd = os.path.join(run, "case.pvd")
    if not os.path.isfile(pvd):
        fail(pvd + ": no such file (not a run's output folder?)")
    times = {}
    for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="frame_(\d+)\.vtu"', open(pvd).read()):
        times[int(f)] = float(t)
    if not times:
        fail(pvd + ": lists no frame_NNNN.vtu")
    return times


def main(argv):
    opts = {"--frames": None, "--normal": "y", "--at": "0", "--width": "400"}
    args = sp.parse_args(argv, opts, __doc__, fail)
    if args is None:
        return 0
    if len(args) != 2:
        fail("usage: sequence_png.py RUN_DIR OUT.png [--frames I,J,...] [--normal x|y|z] "
             "[--at C] [--width PX]")
    run, out = args
    if opts["--normal"] not in ("x", "y", "z"):
        fail("--normal must be x, y or z")
    axis = "xyz".index(opts["--normal"])
    try:
        at, width = float(opts["--at"]), int(opts["--width"])
    except ValueError:
        fail("--at must be a coordinate in metres and --width a whole number")
    times = frame_times(run)
    numbers = sorted(times)
    if opts["--frames"] is None:
        picks = sorted({numbers[round(k * (len(numbers) - 1) / 3)] for k in range(4)})
    else:
        try:
            picks = [int(f) for f in opts["--frames"].split(",")]
        except ValueError:
            fail("--frames must be frame numbers separated by commas")
        for f in picks:
            if f not in times:
                fail("no frame %d in %s/case.pvd (it has %d to %d)" % (f, run, numbers[0],
                                                                        numbers[-1]))
    inplane = [a for a in range(3) if a != axis]
    pts0, _, body0 = sp.read_frame(os.path.join(run, "frame_%04d.vtu" % numbers[0]))
    lo, hi = pts0[:, inplane].min(axis=0), pts0[:, inplane].max(axis=0)
    pad = 0.05 * (hi - lo).max()
    window = (lo - pad, hi + pad)
    nb = int(body0.max()) + 1
    panels = []
    for f in picks:
        pts, conn, body = sp.read_frame(os.path.join(run, "frame_%04d.vtu" % f))
        polys, cells = sp.section(pts, conn, axis, at)
        extent = []
        if polys:
            cover, px = sp.rasterize(polys, cells, body, width, extent, window, nb)
        else:
            px = (window[1][0] - window[0][0]) / width
            cover = np.zeros((nb, max(1, int(round((window[1][1] - window[0][1]) / px))), width),
                             dtype=bool)
        count = cover.sum(axis=0)
        rgb = np.full(count.shape + (3,), 255, dtype=np.uint8)
        for b in range(cover.shape[0]):
            rgb[cover[b]] = sp.PALETTE[b % len(sp.PALETTE)]
        rgb[count >= 2] = sp.OVERLAP
        drawn = 0
        ppath = os.path.join(run, "particles_%04d.vtu" % f)
        if os.path.isfile(ppath):
            c, r, b = sp.read_particles(ppath)
            drawn = sp.draw_discs(rgb, c, r, b, axis, at, window[0], px)
        panels.append((times[f], rgb))
        print("frame %d: t = %.3g s, %d polygons cut, %d particles drawn" % (f, times[f],
                                                                           len(polys), drawn))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h, w, _ = panels[0][1].shape
    cols = min(len(panels), 4)
    rows = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, rows * (3.2 * h / w + 0.6)),
                             squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, (t, rgb) in zip(axes.flat, panels):
        ax.imshow(rgb[::-1], extent=[window[0][0] * 1e3, window[1][0] * 1e3,
                                     window[0][1] * 1e3, window[1][1] * 1e3])
        ax.set_title("t = %.1f µs" % (t * 1e6), fontsize=9)
        ax.set_xlabel("xyz"[inplane[0]] + " (mm)", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in axes[:, 0]:
        ax.set_ylabel("xyz"[inplane[1]] + " (mm)", fontsize=8)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=150)
    os.replace(tmp, out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
