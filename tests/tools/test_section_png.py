"""tools/post/section_png.py on the paper's cubes case (Dobritsa et al. 2019, Figs. 2–3): the
t = 0 section areas against the exact ones, the bare picture (--raw) decoded back (its red
pixels are the reported overlap), the on/off contrast (edge–edge contact on: no overlap at
20 µs; off: the cubes overlap), the annotated picture's labels, and bad input refused."""
import os
import re
import struct
import zlib

import numpy as np
import pytest

from conftest import case, run_case, run_tool
from tools.post import section_png as sp


@pytest.fixture(scope="module")
def cubes(binary, module_out):
    runs = {}
    for mode in ("on", "off"):
        runs[mode] = os.path.join(module_out, mode)
        run_case(binary, case("cubes-edge"), runs[mode],
                 "contact.edge_edge=" + ("true" if mode == "on" else "false"),
                 "contact.verify=" + ("true" if mode == "on" else "false"))
    return runs


def render(frame, png, *extra):
    r = run_tool("post/section_png.py", frame, png, "--normal", "z", "--at", "0", "--width", "600",
                 *extra, check=0)
    m = re.search(r"pixel ([0-9.e+-]+) m; pixels per body (\d+),(\d+); (\d+) overlap", r.stdout)
    assert m is not None, r.stdout
    return float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))


def decode(png):
    """The RGB rows of a PNG as section_png --raw writes it (8-bit RGB, filter 0)."""
    data = open(png, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    w, h = struct.unpack(">II", data[16:24])
    at, idat = 8, b""
    while at < len(data):
        n = struct.unpack(">I", data[at:at + 4])[0]
        if data[at + 4:at + 8] == b"IDAT":
            idat += data[at + 8:at + 8 + n]
        at += 12 + n
    raw = zlib.decompress(idat)
    assert len(raw) == h * (1 + 3 * w)
    return [raw[j * (1 + 3 * w) + 1:(j + 1) * (1 + 3 * w)] for j in range(h)], w


def red_pixels(png):
    rows, w = decode(png)
    red = bytes(sp.OVERLAP)
    return sum(1 for row in rows for i in range(w) if row[3 * i:3 * i + 3] == red)


def test_section_areas_at_t0(cubes, out):
    # The left cube (turned about z) cuts z = 0 in a 2 cm square, 4e-4 m²; the right one (turned
    # about y) in a 2 cm × 2√2 cm rectangle, 5.657e-4 m². Pixel areas within 1 %.
    px, left, right, overlap = render(os.path.join(cubes["on"], "frame_0000.vtu"),
                                      os.path.join(out, "t0.png"), "--raw")
    assert left * px * px == pytest.approx(4e-4, rel=0.01)
    assert right * px * px == pytest.approx(2 * 2 ** 0.5 * 1e-4 * 2, rel=0.01)
    assert overlap == 0


def test_overlap_with_edge_edge_contact_on_and_off(cubes, out):
    _, _, _, on = render(os.path.join(cubes["on"], "frame_0020.vtu"), os.path.join(out, "on.png"),
                         "--raw")
    _, _, _, off = render(os.path.join(cubes["off"], "frame_0020.vtu"),
                          os.path.join(out, "off.png"), "--raw")
    assert on == 0, "edge-edge on: no overlap at 20 us"
    assert off > 1000, "edge-edge off: the cubes overlap at 20 us"
    assert red_pixels(os.path.join(out, "off.png")) == off


def test_annotated_picture(cubes, out):
    """The default picture: axes in mm, the frame's time in µs, a legend with the bodies'
    names from summary.json, a scale bar."""
    import matplotlib
    matplotlib.use("Agg")
    frame = os.path.join(cubes["on"], "frame_0010.vtu")
    time, names = sp.run_info(frame)
    assert time == pytest.approx(10e-6, rel=0.1)
    assert names == ["left", "right"]
    png = os.path.join(out, "annotated.png")
    render(frame, png)
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    # The same picture drawn in the test, to read its labels.
    pts, conn, body = sp.read_frame(frame)
    polys, cells = sp.section(pts, conn, 2, 0.0)
    extent = []
    cover, px = sp.rasterize(polys, cells, body, 200, extent)
    window = (extent[0], extent[0] + px * np.array([200, cover.shape[1]]))
    fig = sp.picture(sp.paint(cover), window, [0, 1], os.path.join(out, "again.png"), time,
                     names)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)"
    assert re.fullmatch(r"t = 1\d\.\d\d µs", ax.get_title())
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[:2] == ["left", "right"] and "overlap (two bodies)" in labels
    bars = [a for a in ax.artists if "SizeBar" in type(a).__name__]
    assert len(bars) == 1 and bars[0].txt_label.get_text().endswith(" mm")
    assert ax.get_xlim() == pytest.approx((window[0][0] * 1e3, window[1][0] * 1e3))


def test_bad_input(out):
    r = run_tool("post/section_png.py", os.path.join(out, "missing.vtu"),
                 os.path.join(out, "x.png"), check=2)
    assert "missing.vtu: no such file" in r.stderr
    r = run_tool("post/section_png.py", "a.vtu", "b.png", "--window", "1,0,0,1", check=2)
    assert "--window must have X1 > X0" in r.stderr
