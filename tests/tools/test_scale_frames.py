"""tools/dev/scale_frames.py at a small size (10 × 10 × 1 plate cells): two binary PLY frames
of the same triangles, which `tetcontact profile --frames` reads."""
import json
import os
import struct
import subprocess

from conftest import run_tool


def read_ply(path):
    data = open(path, "rb").read()
    head, body = data.split(b"end_header\n", 1)
    lines = head.decode().splitlines()
    assert lines[:2] == ["ply", "format binary_little_endian 1.0"]
    nv = int([x for x in lines if x.startswith("element vertex")][0].split()[-1])
    nf = int([x for x in lines if x.startswith("element face")][0].split()[-1])
    verts = [struct.unpack_from("<3d", body, 24 * i) for i in range(nv)]
    faces = [struct.unpack_from("<B3i", body, 24 * nv + 13 * i) for i in range(nf)]
    assert len(body) == 24 * nv + 13 * nf
    return verts, faces


def test_small_frames(binary, out):
    r = run_tool("dev/scale_frames.py", binary, out, "--cells", "10", "--thickness", "1",
                 check=0)
    va, fa = read_ply(os.path.join(out, "A.ply"))
    vb, fb = read_ply(os.path.join(out, "B.ply"))
    assert fa == fb and len(va) == len(vb)
    assert all(f[0] == 3 and all(0 <= v < len(va) for v in f[1:]) for f in fa)
    assert f"{len(va)} vertices, {len(fa)} triangles" in r.stdout
    assert va != vb  # the ball moved between the frames
    p = subprocess.run([binary, "profile", "--frames", os.path.join(out, "A.ply"),
                        os.path.join(out, "B.ply"), "--json"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    methods = json.loads(p.stdout)
    assert methods and all(m["primitives"] > len(fa) for m in methods)
