#!/usr/bin/python3
"""tools/section_png.py (and sequence_png.py) on the paper's cubes case: the t = 0 section areas against the exact
ones, the PNG decoded back (its red pixels are the reported overlap), and the on/off contrast
(edge-edge contact on: no overlap at 20 us; off: the cubes overlap).

    test_section_png.py BINARY SOURCE_DIR OUTDIR"""
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

binary, src, out = sys.argv[1:4]
case = os.path.join(src, "data/cases/cubes-edge.yaml")
tool = os.path.join(src, "tools/section_png.py")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import check, finish  # noqa: E402


def render(frame, png):
    r = subprocess.run([sys.executable, tool, frame, png, "--normal", "z", "--at", "0",
                        "--width", "600"], capture_output=True, text=True)
    check(r.returncode == 0, "render %s: %s" % (frame, r.stderr))
    m = re.search(r"pixel ([0-9.e+-]+) m; pixels per body (\d+),(\d+); (\d+) overlap", r.stdout)
    check(m is not None, "output line: " + r.stdout)
    return float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))


def red_pixels(png):
    data = open(png, "rb").read()
    check(data[:8] == b"\x89PNG\r\n\x1a\n", "PNG signature")
    w, h = struct.unpack(">II", data[16:24])
    at, idat = 8, b""
    while at < len(data):
        n = struct.unpack(">I", data[at:at + 4])[0]
        if data[at + 4:at + 8] == b"IDAT":
            idat += data[at + 8:at + 8 + n]
        at += 12 + n
    raw = zlib.decompress(idat)
    check(len(raw) == h * (1 + 3 * w), "image size")
    red = 0
    for j in range(h):
        row = raw[j * (1 + 3 * w) + 1:(j + 1) * (1 + 3 * w)]
        red += sum(1 for i in range(w) if row[3 * i:3 * i + 3] == b"\xdc\x1e\x1e")
    return red


shutil.rmtree(out, ignore_errors=True)
for mode in ("on", "off"):
    r = subprocess.run([binary, "run", case, "--out", os.path.join(out, mode), "--quiet",
                        "--set", "contact.edge_edge=" + ("true" if mode == "on" else "false")],
                       capture_output=True, text=True)
    check(r.returncode == 0, "run %s: %s" % (mode, r.stderr))

# t = 0: the left cube (turned about z) cuts z = 0 in a 2 cm square, area 4e-4 m^2; the right
# one (turned about y) in a 2 cm x 2*sqrt(2) cm rectangle, 5.657e-4 m^2. Pixel areas within 1 %.
px, left, right, overlap = render(os.path.join(out, "on/frame_0000.vtu"), os.path.join(out, "t0.png"))
check(abs(left * px * px / 4e-4 - 1) < 0.01, "left section area %g" % (left * px * px))
check(abs(right * px * px / (2 * 2 ** 0.5 * 1e-4 * 2) - 1) < 0.01,
      "right section area %g" % (right * px * px))
check(overlap == 0, "no overlap at t = 0 (%d)" % overlap)

_, _, _, on = render(os.path.join(out, "on/frame_0020.vtu"), os.path.join(out, "on.png"))
_, _, _, off = render(os.path.join(out, "off/frame_0020.vtu"), os.path.join(out, "off.png"))
check(on == 0, "edge-edge on: no overlap at 20 us (%d pixels)" % on)
check(off > 1000, "edge-edge off: the cubes overlap at 20 us (%d pixels)" % off)
check(red_pixels(os.path.join(out, "off.png")) == off, "red pixels = reported overlap")

# Bad input: a clear error, exit code 2.
r = subprocess.run([sys.executable, tool, os.path.join(out, "missing.vtu"), os.path.join(out, "x.png")],
                   capture_output=True, text=True)
check(r.returncode == 2 and "missing.vtu: no such file" in r.stderr, "missing frame: " + r.stderr)

# The picture sequence (tools/sequence_png.py): three frames of the edge-on run side by side
# at one scale, times from case.pvd; a frame the run lacks is refused (exit 2).
seq = os.path.join(src, "tools/sequence_png.py")
r = subprocess.run([sys.executable, seq, os.path.join(out, "on"), os.path.join(out, "seq.png"),
                    "--frames", "0,10,20", "--normal", "z"], capture_output=True, text=True)
check(r.returncode == 0, "sequence: " + r.stderr)
lines = re.findall(r"frame (\d+): t = ([0-9.e+-]+) s, (\d+) polygons cut", r.stdout)
check([int(f) for f, _, _ in lines] == [0, 10, 20], "sequence frames: " + r.stdout)
check(abs(float(lines[-1][1]) - 20e-6) < 1e-6 if lines else False, "last frame at 20 us")  # first step at or after
check(all(int(n) > 0 for _, _, n in lines), "every panel cuts cells")
check(open(os.path.join(out, "seq.png"), "rb").read()[:8] == b"\x89PNG\r\n\x1a\n", "PNG")
r = subprocess.run([sys.executable, seq, os.path.join(out, "on"), os.path.join(out, "x.png"),
                    "--frames", "99"], capture_output=True, text=True)
check(r.returncode == 2 and "no frame 99" in r.stderr, "missing frame in a sequence: " + r.stderr)
finish("section_png", " (overlap on %d, off %d pixels)" % (on, off))
