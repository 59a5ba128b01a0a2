#!/usr/bin/python3
"""tools/plot_sweep.py on a real sweep (bars-impact, two meshes × two pass counts): a PNG is
written with every finished run plotted, a failed run is left out and counted, and a file that
is not a sweep is refused with exit code 2.

    test_plot_sweep.py BINARY SOURCE_DIR OUTDIR"""
import os
import shutil
import subprocess
import sys

binary, src, out = sys.argv[1:4]
tool = os.path.join(src, "tools/plot_sweep.py")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import check, finish  # noqa: E402


shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
subprocess.run([binary, "sweep", os.path.join(src, "data/cases/bars-impact.yaml"), "--vary",
                "bodies.0.mesh.box.cells+bodies.1.mesh.box.cells=[10,1,1],[20,2,2]", "--vary",
                "contact.passes=1,3", "--quiet", "--out", os.path.join(out, "s")], check=True,
               capture_output=True)
csv = os.path.join(out, "s", "sweep.csv")
r = subprocess.run([sys.executable, tool, csv], capture_output=True, text=True)
check(r.returncode == 0, "plot_sweep.py exits 0: " + r.stderr)
png = os.path.join(out, "s", "sweep.png")
check(os.path.isfile(png) and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n", "a PNG is written")
check("4 runs plotted, 0 left out" in r.stdout, "every run plotted: " + r.stdout)

# A failed run is left out and counted.
lines = open(csv).read().splitlines()
lines[1] = lines[1].replace(",ok,", ",failed: test,", 1)
open(os.path.join(out, "edited.csv"), "w").write("\n".join(lines) + "\n")
r = subprocess.run([sys.executable, tool, os.path.join(out, "edited.csv"), os.path.join(out, "e.png")],
                   capture_output=True, text=True)
check(r.returncode == 0 and "3 runs plotted, 1 left out" in r.stdout, "failed run left out: " + r.stdout)

open(os.path.join(out, "bad.csv"), "w").write("a,b\n1,2\n")
r = subprocess.run([sys.executable, tool, os.path.join(out, "bad.csv")], capture_output=True, text=True)
check(r.returncode == 2 and "not a sweep.csv" in r.stderr, "a non-sweep file is refused")
finish("plot_sweep")
