#!/usr/bin/python3
"""Renders a cross-section of a tetcontact .vtu frame to PNG, like the paper's figures
(Dobritsa et al. 2019): the cells cut by a plane, coloured by body, with pixels covered by two
bodies (interpenetration) in red; the particles of fracture near the plane as darker discs.

    section_png.py FRAME.vtu OUT.png [--normal x|y|z] [--at C] [--width PX]
                   [--particles PARTICLES.vtu] [--slab W] [--window X0,X1,Y0,Y1] [--raw]

--normal  the plane's normal axis (default y: the x-z plane, the axial section of a body
          along z or x); --at  the plane's coordinate on that axis in metres (default: the
          middle of the frame's bounds); --width  image width in pixels (default 800);
--particles  also draw the particles (particles_NNNN.vtu of the same time): those whose centre
          lies within W of the plane (--slab, metres, default 0) as discs of their full radius
          (the slab projected on the plane), and those farther whose spheres the plane cuts as
          the cut's disc;
--window  the picture's extent in the plane's two in-plane axes, metres (default: the cut
          cells' extent, padded 3 %): a sequence of pictures at one scale;
--raw     the bare picture, one pixel per raster cell, no axes (what the tests decode).

The picture has axes in mm, a scale bar, the frame's time in µs (from the case.pvd beside the
frame) and a legend of the bodies (their names from the summary.json beside it). Prints one
line: polygons cut, the pixel size, pixels covered per body, overlap pixels, particles drawn.
OUT.png is replaced only through a temporary file (no half-written image). Needs Debian's
python3-vtk9, python3-numpy and python3-matplotlib (run with /usr/bin/python3). Exit code 0,
or 2 on bad input."""
import json
import os
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import summary_keys as K  # noqa: E402

import numpy as np  # noqa: E402 (after tools.common: a missing module is said plainly)

PALETTE = [(70, 110, 190), (120, 180, 90), (220, 170, 60), (150, 100, 180), (80, 170, 170)]
OVERLAP = (220, 30, 30)
EDGES = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


def fail(msg):
    print("section_png.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def read_grid(path):
    import vtk

    if not os.path.isfile(path):
        fail(path + ": no such file")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def read_frame(path):
    from vtk.util.numpy_support import vtk_to_numpy

    g = read_grid(path)
    if g is None or g.GetNumberOfCells() == 0:
        fail(path + ": not a tetrahedral .vtu frame (no cells read)")
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4)
    body = g.GetCellData().GetArray("body")
    if body is None:
        fail(path + ": no cell array 'body' (write it with output.fields)")
    return pts, conn, vtk_to_numpy(body).astype(int)


def read_particles(path):
    """Centres, radii and bodies of the particles of a particles_NNNN.vtu."""
    from vtk.util.numpy_support import vtk_to_numpy

    g = read_grid(path)
    n = g.GetNumberOfPoints()
    if n == 0:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0, dtype=int)
    radius, body = g.GetPointData().GetArray("radius"), g.GetPointData().GetArray("body")
    if radius is None or body is None:
        fail(path + ": not a particles .vtu (no 'radius' or 'body' point array)")
    return (vtk_to_numpy(g.GetPoints().GetData()).astype(float), vtk_to_numpy(radius),
            vtk_to_numpy(body).astype(int))


def particle_colour(body):
    """A particle's colour: a darker shade of its body's."""
    return tuple(int(0.55 * v) for v in PALETTE[body % len(PALETTE)])


def draw_discs(rgb, centres, radii, bodies, axis, at, lo, px, slab=0.0):
    """Particles as discs: those whose centre lies within `slab` of the plane x[axis] = at at
    their full radius (projected on the plane), the others whose sphere the plane cuts as the
    cut's disc. Returns how many were drawn."""
    inplane = [a for a in range(3) if a != axis]
    h, w, _ = rgb.shape
    drawn = 0
    for c, r, b in zip(centres, radii, bodies):
        d = c[axis] - at
        if abs(d) <= slab:
            rc = r
        elif abs(d) < r:
            rc = np.sqrt(r * r - d * d)
        else:
            continue
        x, y = c[inplane]
        i0, i1 = max(0, int((x - rc - lo[0]) / px)), min(w, int((x + rc - lo[0]) / px) + 1)
        j0, j1 = max(0, int((y - rc - lo[1]) / px)), min(h, int((y + rc - lo[1]) / px) + 1)
        if i0 >= i1 or j0 >= j1:
            continue  # outside the picture
        xs = lo[0] + (np.arange(i0, i1) + 0.5) * px
        ys = lo[1] + (np.arange(j0, j1) + 0.5) * px
        X, Y = np.meshgrid(xs, ys)
        inside = (X - x) ** 2 + (Y - y) ** 2 <= max(rc, 0.5 * px) ** 2
        rgb[j0:j1, i0:i1][inside] = particle_colour(b)
        drawn += 1
    return drawn


def section(pts, conn, axis, at):
    """Convex polygons (in-plane 2-D coordinates) of the tets cut by the plane x[axis] = at."""
    inplane = [a for a in range(3) if a != axis]
    d = pts[:, axis] - at
    polys, cells = [], []
    dc = d[conn]
    cut = (dc.min(axis=1) <= 0) & (dc.max(axis=1) >= 0) & (np.abs(dc).max(axis=1) > 0)
    for c in np.nonzero(cut)[0]:
        q = [pts[v][inplane] for v in conn[c] if d[v] == 0]  # corners on the plane
        for i, j in EDGES:
            a, b = conn[c, i], conn[c, j]
            if d[a] * d[b] < 0:  # the edge crosses the plane
                q.append((pts[a] + d[a] / (d[a] - d[b]) * (pts[b] - pts[a]))[inplane])
        if len(q) < 3:
            continue
        q = np.array(q)
        ctr = q.mean(axis=0)
        q = q[np.argsort(np.arctan2(q[:, 1] - ctr[1], q[:, 0] - ctr[0]))]
        polys.append(q)
        cells.append(c)
    return polys, cells


def rasterize(polys, cells, body, width, extent, window=None, bodies=None):
    """Pixels covered by each body: over the polygons' extent (padded), or over a fixed
    window (lo, hi) of in-plane coordinates (a sequence of frames at one scale)."""
    if window is None:
        allp = np.vstack(polys)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        span = np.maximum(hi - lo, 1e-300)
        pad = 0.03 * span.max()
        lo, hi = lo - pad, hi + pad
    else:
        lo, hi = np.asarray(window[0], dtype=float), np.asarray(window[1], dtype=float)
    span = hi - lo
    px = span[0] / width
    height = max(1, int(round(span[1] / px)))
    nb = int(body.max()) + 1 if bodies is None else bodies
    cover = np.zeros((nb, height, width), dtype=bool)
    extent[:] = [lo]
    for q, c in zip(polys, cells):
        for k in range(1, len(q) - 1):  # fan triangulation of the convex polygon
            tri = np.array([q[0], q[k], q[k + 1]])
            i0 = max(0, int((tri[:, 0].min() - lo[0]) / px))
            i1 = min(width, int((tri[:, 0].max() - lo[0]) / px) + 1)
            j0 = max(0, int((tri[:, 1].min() - lo[1]) / px))
            j1 = min(height, int((tri[:, 1].max() - lo[1]) / px) + 1)
            if i0 >= i1 or j0 >= j1:
                continue
            xs = lo[0] + (np.arange(i0, i1) + 0.5) * px
            ys = lo[1] + (np.arange(j0, j1) + 0.5) * px
            X, Y = np.meshgrid(xs, ys)
            (ax, ay), (bx, by), (cx, cy) = tri
            e0 = (bx - ax) * (Y - ay) - (by - ay) * (X - ax)
            e1 = (cx - bx) * (Y - by) - (cy - by) * (X - bx)
            e2 = (ax - cx) * (Y - cy) - (ay - cy) * (X - cx)
            inside = ((e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | ((e0 <= 0) & (e1 <= 0) & (e2 <= 0))
            cover[body[c], j0:j1, i0:i1] |= inside
    return cover, px


def write_png(path, rgb):
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[h - 1 - j].tobytes() for j in range(h))  # y up

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


def paint(cover):
    """The picture of a rasterized section: white, each body's colour, overlap red."""
    count = cover.sum(axis=0)
    rgb = np.full(count.shape + (3,), 255, dtype=np.uint8)
    for b in range(cover.shape[0]):
        rgb[cover[b]] = PALETTE[b % len(PALETTE)]
    rgb[count >= 2] = OVERLAP
    return rgb


def blank(window, width, bodies):
    """An empty raster over a window (no cell cut): (cover, pixel size)."""
    px = (window[1][0] - window[0][0]) / width
    height = max(1, int(round((window[1][1] - window[0][1]) / px)))
    return np.zeros((bodies, height, width), dtype=bool), px


def run_info(frame):
    """(time in s or None, body names) of a frame from the case.pvd and summary.json beside
    it; names 'body 0', 'body 1', ... when there is no summary."""
    folder, name = os.path.split(os.path.abspath(frame))
    time = None
    pvd = os.path.join(folder, "case.pvd")
    if os.path.isfile(pvd):
        for d in ET.parse(pvd).getroot().iter("DataSet"):
            if d.get("file") == name:
                time = float(d.get("timestep"))
    names = []
    summary = os.path.join(folder, "summary.json")
    if os.path.isfile(summary):
        with open(summary) as f:
            names = [b[K.NAME] for b in K.get(json.load(f), K.BODIES, summary)]
    return time, names


def body_names(names, count):
    return [names[b] if b < len(names) else f"body {b}" for b in range(count)]


def annotate(ax, window, inplane, time=None, scale=True):
    """Axes in mm over the window, the time in µs as the title, a scale bar."""
    ax.set_xlim(window[0][0] * 1e3, window[1][0] * 1e3)
    ax.set_ylim(window[0][1] * 1e3, window[1][1] * 1e3)
    ax.set_xlabel("xyz"[inplane[0]] + " (mm)", fontsize=8)
    ax.set_ylabel("xyz"[inplane[1]] + " (mm)", fontsize=8)
    ax.tick_params(labelsize=7)
    if time is not None:
        ax.set_title("t = %.2f µs" % (time * 1e6), fontsize=9)
    if scale:
        from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

        span = (window[1][0] - window[0][0]) * 1e3
        bar = 10 ** np.floor(np.log10(span / 4))  # a round length, a quarter of the width or less
        bar = max(b for b in (bar, 2 * bar, 5 * bar) if b <= span / 4)
        ax.add_artist(AnchoredSizeBar(ax.transData, bar, "%g mm" % bar, "lower right",
                                      pad=0.4, frameon=True, size_vertical=span / 200,
                                      fontproperties={"size": 7}))


def legend_handles(names, particles, overlap=True):
    """Legend entries: each body's colour, its particles' shade when drawn, the overlap red."""
    from matplotlib.patches import Patch

    handles = [Patch(color=np.array(PALETTE[b % len(PALETTE)]) / 255, label=n)
               for b, n in enumerate(names)]
    if particles:
        handles += [Patch(color=np.array(particle_colour(b)) / 255, label=n + " particles")
                    for b, n in enumerate(names)]
    if overlap:
        handles.append(Patch(color=np.array(OVERLAP) / 255, label="overlap (two bodies)"))
    return handles


def save_figure(fig, out, dpi=100):
    """Writes a matplotlib figure through a temporary file."""
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=dpi)
    os.replace(tmp, out)


def picture(rgb, window, inplane, out, time=None, names=(), particles=False):
    """The annotated picture of one section: the raster in mm, axes, scale, time, legend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h, w, _ = rgb.shape
    fig = plt.figure(figsize=(w / 100 + 2.6, h / 100 + 1.0))
    ax = fig.add_axes([0.9 / (w / 100 + 2.6), 0.6 / (h / 100 + 1.0),
                       (w / 100) / (w / 100 + 2.6), (h / 100) / (h / 100 + 1.0)])
    ax.imshow(rgb[::-1], interpolation="nearest", aspect="equal",
              extent=[window[0][0] * 1e3, window[1][0] * 1e3, window[0][1] * 1e3,
                      window[1][1] * 1e3])
    annotate(ax, window, inplane, time)
    ax.legend(handles=legend_handles(list(names), particles), fontsize=7, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), frameon=False)
    save_figure(fig, out)
    return fig


def parse_args(argv, opts, doc, fail=fail):
    """Positional arguments and `--key value` options over the defaults in `opts`; None when
    help was asked for (the doc is printed)."""
    args = []
    i = 0
    while i < len(argv):
        if argv[i] in ("-h", "--help"):
            print(doc)
            return None
        if argv[i] in opts:
            if i + 1 >= len(argv):
                fail(argv[i] + " needs a value")
            opts[argv[i]] = argv[i + 1]
            i += 2
        else:
            args.append(argv[i])
            i += 1
    return args


def parse_window(text, fail=fail):
    """--window X0,X1,Y0,Y1 (m): ((X0, Y0), (X1, Y1))."""
    try:
        x0, x1, y0, y1 = (float(v) for v in text.split(","))
    except ValueError:
        fail("--window must be X0,X1,Y0,Y1 in metres")
    if not (x1 > x0 and y1 > y0):
        fail("--window must have X1 > X0 and Y1 > Y0")
    return (np.array([x0, y0]), np.array([x1, y1]))


def main(argv):
    opts = {"--normal": "y", "--at": None, "--width": "800", "--particles": None,
            "--slab": "0", "--window": None}
    raw = "--raw" in argv
    argv = [a for a in argv if a != "--raw"]
    args = parse_args(argv, opts, __doc__)
    if args is None:
        return 0
    if len(args) != 2:
        fail("usage: section_png.py FRAME.vtu OUT.png [--normal x|y|z] [--at C] [--width PX] "
             "[--particles P.vtu] [--slab W] [--window X0,X1,Y0,Y1] [--raw]")
    if opts["--normal"] not in ("x", "y", "z"):
        fail("--normal must be x, y or z")
    axis = "xyz".index(opts["--normal"])
    inplane = [a for a in range(3) if a != axis]
    try:
        width = int(opts["--width"])
        at = None if opts["--at"] is None else float(opts["--at"])
        slab = float(opts["--slab"])
    except ValueError:
        fail("--width must be a whole number, --at and --slab lengths in metres")
    if width < 16:
        fail("--width must be at least 16")
    window = None if opts["--window"] is None else parse_window(opts["--window"])
    pts, conn, body = read_frame(args[0])
    if at is None:
        at = 0.5 * (pts[:, axis].min() + pts[:, axis].max())
    polys, cells = section(pts, conn, axis, at)
    if not polys and window is None:
        fail("%s: the plane %s = %g m cuts no cell" % (args[0], opts["--normal"], at))
    extent = []
    nb = int(body.max()) + 1
    if polys:
        cover, pixel = rasterize(polys, cells, body, width, extent, window, nb)
        window = window or (extent[0], extent[0] + np.array([width, cover.shape[1]]) * pixel)
    else:
        cover, pixel = blank(window, width, nb)
    rgb = paint(cover)
    count = cover.sum(axis=0)
    discs = ""
    if opts["--particles"] is not None:
        centres, radii, bodies = read_particles(opts["--particles"])
        discs = "; %d particles drawn" % draw_discs(rgb, centres, radii, bodies, axis, at,
                                                    window[0], pixel, slab)
    if raw:
        write_png(args[1], rgb)
    else:
        time, names = run_info(args[0])
        picture(rgb, window, inplane, args[1], time, body_names(names, nb),
                opts["--particles"] is not None)
    print("%d polygons cut at %s = %g m; pixel %g m; pixels per body %s; %d overlap pixels%s" %
          (len(polys), opts["--normal"], at, pixel, ",".join(str(int(c.sum())) for c in cover),
           int((count >= 2).sum()), discs))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
