"""tools/post/plot_sweep.py on a real sweep (bars-impact, two meshes × two pass counts): a PNG
with every finished run plotted, a failed run left out and counted, a file that is not a sweep
refused with exit code 2."""
import os
import subprocess

import pytest

import csv

from conftest import case, figure, run_tool


@pytest.fixture(scope="module")
def sweep(binary, module_out):
    r = subprocess.run([binary, "sweep", case("bars-impact"), "--vary",
                        "bodies.0.mesh.box.cells+bodies.1.mesh.box.cells=[10,1,1],[20,2,2]",
                        "--vary", "contact.passes=1,3", "--threads", "1", "--quiet", "--out",
                        os.path.join(module_out, "s")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return os.path.join(module_out, "s", "sweep.csv")


def test_every_run_plotted(sweep):
    r = run_tool("post/plot_sweep.py", sweep, check=0)
    png = os.path.splitext(sweep)[0] + ".png"
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert f"{png}: 4 runs plotted, 0 left out" in r.stdout
    # What is drawn: each run's wall time against its |error| and its energy balance, a line
    # per pass count, as sweep.csv has them.
    rows = list(csv.DictReader(open(sweep)))
    drawn_error, drawn_balance = (
        sorted(p for x in a["lines"] for p in zip(x["x"], x["y"])) for a in figure(png)["axes"])
    assert drawn_error == sorted((float(r["wall_seconds"]), max(abs(float(r["error"])), 1e-16))
                                 for r in rows)
    assert drawn_balance == sorted(
        (float(r["wall_seconds"]), max(float(r["energy_balance_max"]), 1e-16)) for r in rows)


def test_failed_run_left_out(sweep, out):
    lines = open(sweep).read().splitlines()
    assert ",ok," in lines[1]
    lines[1] = lines[1].replace(",ok,", ",failed: test,", 1)
    edited = os.path.join(out, "edited.csv")
    open(edited, "w").write("\n".join(lines) + "\n")
    r = run_tool("post/plot_sweep.py", edited, os.path.join(out, "e.png"), "--title", "T",
                 check=0)
    assert "3 runs plotted, 1 left out" in r.stdout
    assert os.path.isfile(os.path.join(out, "e.png"))


def test_bad_input(out):
    bad = os.path.join(out, "bad.csv")
    open(bad, "w").write("a,b\n1,2\n")
    r = run_tool("post/plot_sweep.py", bad, check=2)
    assert "not a sweep.csv" in r.stderr
    r = run_tool("post/plot_sweep.py", os.path.join(out, "none.csv"), check=2)
    assert "none.csv: no such file" in r.stderr
    r = run_tool("post/plot_sweep.py", bad, "--title", check=2)
    assert "--title needs a text" in r.stderr
