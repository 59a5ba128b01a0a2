#!/usr/bin/python3
"""A picture sequence of a run, like the paper's figures (Dobritsa et al. 2019): cross-sections
of chosen output frames side by side (four to a row), each cut by the same plane and framed at
one common extent, cells coloured by body, the particles of fracture near the plane as darker
discs, overlap (interpenetration) in red; axes in mm, a scale bar, the time of each frame in
µs, a legend of the bodies.

    sequence_png.py RUN_DIR OUT.png [--frames I,J,...] [--normal x|y|z] [--at C] [--width PX]
                    [--slab W] [--window X0,X1,Y0,Y1]

RUN_DIR is a run's output folder (case.pvd, frame_NNNN.vtu, particles_NNNN.vtu, summary.json
for the bodies' names). --frames: the frame numbers (default: four spread over the run, the
first and the last among them); --normal/--at: the plane (default y = 0); --width: pixels per
panel (default 400); --slab: the particles drawn are those whose centres lie within W of the
plane (metres; default 5 % of the window's larger side), each a disc of its radius: the debris
cloud projected on the plane, not only the particles the plane cuts; --window: the extent in the
plane's two in-plane axes (metres; default: what every chosen frame shows, together — its
cells' nodes and its particles in the slab — padded by 5 %). Every panel has the same extent:
what moves, moves across the picture.

Prints the window, then one line per panel (time, polygons cut, particles drawn). Writes
OUT.png through a temporary file. Needs python3-vtk9, python3-numpy and python3-matplotlib
(run with /usr/bin/python3). Exit code 0, or 2 on bad input."""
import os
import re
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.post import section_png as sp  # noqa: E402

import numpy as np  # noqa: E402 (after tools.common: a missing module is said plainly)


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


class Frame:
    """One output frame: its cells and the particles of the same time."""

    def __init__(self, run, number, time):
        self.number, self.time = number, time
        self.pts, self.conn, self.body = sp.read_frame(os.path.join(run, "frame_%04d.vtu" % number))
        ppath = os.path.join(run, "particles_%04d.vtu" % number)
        if os.path.isfile(ppath):
            self.centres, self.radii, self.pbody = sp.read_particles(ppath)
        else:
            self.centres, self.radii, self.pbody = np.zeros((0, 3)), np.zeros(0), np.zeros(0, int)

    def in_slab(self, axis, at, slab):
        """The particles whose centres lie within `slab` of the plane."""
        return np.abs(self.centres[:, axis] - at) <= slab


def content_extent(frames, axis, at, slab):
    """The in-plane (lo, hi) of what the frames show together: their cells' nodes and their
    particles (with their radii) in the slab."""
    inplane = [a for a in range(3) if a != axis]
    los, his = [], []
    for f in frames:
        used = f.pts[np.unique(f.conn)] if len(f.conn) else np.zeros((0, 3))
        if len(used):
            los.append(used[:, inplane].min(axis=0))
            his.append(used[:, inplane].max(axis=0))
        near = f.in_slab(axis, at, slab)
        if near.any():
            c, r = f.centres[near][:, inplane], f.radii[near][:, None]
            los.append((c - r).min(axis=0))
            his.append((c + r).max(axis=0))
    if not los:
        fail("the chosen frames have no cells and no particles near the plane")
    return np.min(los, axis=0), np.max(his, axis=0)


def common_window(frames, axis, at, slab, pad=0.05):
    """One window for every panel: the frames' content together, padded by `pad` of its
    larger side."""
    lo, hi = content_extent(frames, axis, at, slab)
    margin = pad * max((hi - lo).max(), 1e-300)
    return lo - margin, hi + margin


def panel(frame, axis, at, window, width, bodies, slab):
    """One frame's raster over the window: (rgb, polygons cut, particles drawn)."""
    polys, cells = sp.section(frame.pts, frame.conn, axis, at)
    if polys:
        cover, px = sp.rasterize(polys, cells, frame.body, width, [], window, bodies)
    else:
        cover, px = sp.blank(window, width, bodies)
    rgb = sp.paint(cover)
    drawn = sp.draw_discs(rgb, frame.centres, frame.radii, frame.pbody, axis, at, window[0], px,
                          slab)
    return rgb, len(polys), drawn


def figure(panels, window, inplane, names, particles):
    """The panels side by side (four to a row) at the one window, each with its time, axes in
    mm and a scale bar; one legend of the bodies. Returns the matplotlib figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h, w, _ = panels[0][1].shape
    cols = min(len(panels), 4)
    rows = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, rows * (3.2 * h / w + 0.8) + 0.5),
                             squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    extent = [window[0][0] * 1e3, window[1][0] * 1e3, window[0][1] * 1e3, window[1][1] * 1e3]
    for ax, (t, rgb) in zip(axes.flat, panels):
        ax.imshow(rgb[::-1], extent=extent, interpolation="nearest")
        sp.annotate(ax, window, inplane, t)
    fig.legend(handles=sp.legend_handles(names, particles), loc="lower center",
               ncol=min(len(names) * (2 if particles else 1) + 1, 7), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def main(argv):
    opts = {"--frames": None, "--normal": "y", "--at": "0", "--width": "400", "--slab": None,
            "--window": None}
    args = sp.parse_args(argv, opts, __doc__, fail)
    if args is None:
        return 0
    if len(args) != 2:
        fail("usage: sequence_png.py RUN_DIR OUT.png [--frames I,J,...] [--normal x|y|z] "
             "[--at C] [--width PX] [--slab W] [--window X0,X1,Y0,Y1]")
    run, out = args
    if opts["--normal"] not in ("x", "y", "z"):
        fail("--normal must be x, y or z")
    axis = "xyz".index(opts["--normal"])
    inplane = [a for a in range(3) if a != axis]
    try:
        at, width = float(opts["--at"]), int(opts["--width"])
        slab = None if opts["--slab"] is None else float(opts["--slab"])
    except ValueError:
        fail("--at and --slab must be lengths in metres and --width a whole number")
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
    frames = [Frame(run, f, times[f]) for f in picks]
    if opts["--window"] is not None:
        window = sp.parse_window(opts["--window"], fail)
    else:
        cells_only = content_extent(frames, axis, at, -1.0)  # no particle is within -1 m
        slab_guess = 0.05 * (cells_only[1] - cells_only[0]).max() if slab is None else slab
        window = common_window(frames, axis, at, slab_guess)
    if slab is None:
        slab = 0.05 * (window[1] - window[0]).max()
    print("window: %s %.3f to %.3f mm, %s %.3f to %.3f mm; particles within %.3f mm of %s = %g m"
          % ("xyz"[inplane[0]], window[0][0] * 1e3, window[1][0] * 1e3, "xyz"[inplane[1]],
             window[0][1] * 1e3, window[1][1] * 1e3, slab * 1e3, opts["--normal"], at))
    bodies = max(int(f.body.max()) + 1 if len(f.body) else 0 for f in frames)
    bodies = max([bodies] + [int(f.pbody.max()) + 1 for f in frames if len(f.pbody)])
    panels = []
    for f in frames:
        rgb, cut, drawn = panel(f, axis, at, window, width, bodies, slab)
        panels.append((f.time, rgb))
        print("frame %d: t = %.3g s, %d polygons cut, %d particles drawn" % (f.number, f.time,
                                                                            cut, drawn))
    _, names = sp.run_info(os.path.join(run, "frame_%04d.vtu" % picks[0]))
    fig = figure(panels, window, inplane, sp.body_names(names, bodies),
                 any(len(f.pbody) for f in frames))
    sp.save_figure(fig, out, dpi=150)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
