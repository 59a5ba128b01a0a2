#!/usr/bin/python3
"""Renders a cross-section of a tetcontact .vtu frame to PNG, like the paper's figures: the
cells cut by a plane, coloured by body, with pixels covered by two bodies (interpenetration)
in red.

    section_png.py FRAME.vtu OUT.png [--normal x|y|z] [--at C] [--width PX]
                   [--particles PARTICLES.vtu]

--normal  the plane's normal axis (default y: the x-z plane, the axial section of a body
          along z or x); --at  the plane's coordinate on that axis in metres (default: the
          middle of the frame's bounds); --width  image width in pixels (default 800);
          --particles  also draw the particles of fracture whose spheres the plane cuts, as
          discs in a darker shade of their body's colour (particles_NNNN.vtu of the same time).

Prints one line: polygons cut, the pixel size, pixels covered per body, overlap pixels. An existing OUT.png is
replaced only through a temporary file (no half-written image). Needs Debian's python3-vtk9
and python3-numpy (run with /usr/bin/python3). Exit code 0, or 2 on bad input."""
import os
import struct
import sys
import zlib

import numpy as np

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


def draw_discs(rgb, centres, radii, bodies, axis, at, lo, px):
    """Discs where the plane cuts each particle's sphere; returns how many were drawn."""
    inplane = [a for a in range(3) if a != axis]
    h, w, _ = rgb.shape
    drawn = 0
    for c, r, b in zip(centres, radii, bodies):
        d = c[axis] - at
        if abs(d) >= r:
            continue
        rc = np.sqrt(r * r - d * d)
        x, y = c[inplane]
        i0, i1 = max(0, int((x - rc - lo[0]) / px)), min(w, int((x + rc - lo[0]) / px) + 1)
        j0, j1 = max(0, int((y - rc - lo[1]) / px)), min(h, int((y + rc - lo[1]) / px) + 1)
        xs = lo[0] + (np.arange(i0, i1) + 0.5) * px
        ys = lo[1] + (np.arange(j0, j1) + 0.5) * px
        X, Y = np.meshgrid(xs, ys)
        inside = (X - x) ** 2 + (Y - y) ** 2 <= max(rc, 0.5 * px) ** 2
        colour = tuple(int(0.55 * v) for v in PALETTE[b % len(PALETTE)])
        rgb[j0:j1, i0:i1][inside] = colour
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


def main(argv):
    opts = {"--normal": "y", "--at": None, "--width": "800", "--particles": None}
    args = parse_args(argv, opts, __doc__)
    if args is None:
        return 0
    if len(args) != 2:
        fail("usage: section_png.py FRAME.vtu OUT.png [--normal x|y|z] [--at C] [--width PX]")
    if opts["--normal"] not in ("x", "y", "z"):
        fail("--normal must be x, y or z")
    axis = "xyz".index(opts["--normal"])
    try:
        width = int(opts["--width"])
        at = None if opts["--at"] is None else float(opts["--at"])
    except ValueError:
        fail("--width must be a whole number and --at a coordinate in metres")
    if width < 16:
        fail("--width must be at least 16")
    pts, conn, body = read_frame(args[0])
    if at is None:
        at = 0.5 * (pts[:, axis].min() + pts[:, axis].max())
    polys, cells = section(pts, conn, axis, at)
    if not polys:
        fail("%s: the plane %s = %g m cuts no cell" % (args[0], opts["--normal"], at))
    extent = []
    cover, pixel = rasterize(polys, cells, body, width, extent)
    count = cover.sum(axis=0)
    rgb = np.full(count.shape + (3,), 255, dtype=np.uint8)
    for b in range(cover.shape[0]):
        rgb[cover[b]] = PALETTE[b % len(PALETTE)]
    rgb[count >= 2] = OVERLAP
    discs = ""
    if opts["--particles"] is not None:
        centres, radii, bodies = read_particles(opts["--particles"])
        discs = "; %d particles cut" % draw_discs(rgb, centres, radii, bodies, axis, at,
                                                  extent[0], pixel)
    write_png(args[1], rgb)
    print("%d polygons cut at %s = %g m; pixel %g m; pixels per body %s; %d overlap pixels%s" %
          (len(polys), opts["--normal"], at, pixel, ",".join(str(int(c.sum())) for c in cover),
           int((count >= 2).sum()), discs))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
