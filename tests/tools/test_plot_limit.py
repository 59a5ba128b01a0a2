"""tools/post/plot_limit.py on a limit.csv in the program's format (src/app/limit.cpp's
header): the brackets drawn beside Christiansen's curve, brackets not found listed, a search
without --vary and a file that is not a limit.csv refused (exit 2)."""
import os

import pytest

from conftest import figure, run_tool
from tools.common import christiansen

HEADER = "parameters.v,key,lo,hi,criterion_lo,criterion_hi,runs,reused,wall_seconds,status\n"


def test_brackets_and_missing(out):
    csv = os.path.join(out, "limit.csv")
    with open(csv, "w") as f:
        f.write(HEADER)
        f.write("3000,parameters.d,0.002,0.0025,0,1,4,0,12.5,ok\n")
        f.write("5000,parameters.d,0.0015,0.002,0,1,4,1,14.0,ok\n")
        f.write('7000,parameters.d,0.001,0.004,0,0,3,0,9.0,"no bracket: the criterion is 0 at both ends"\n')
    r = run_tool("post/plot_limit.py", csv, "--shield", "1e-3", "2e-3", "30e-3", check=0)
    png = os.path.join(out, "limit.png")
    assert r.stdout.splitlines()[0] == "written: " + png
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert "not found: 7000 m/s: no bracket" in r.stdout
    assert sum(1 for x in r.stdout.splitlines() if x.startswith("not found")) == 1
    # What is drawn: the equation's curve (km/s, mm) and a bar per bracket found, none at 7 km/s.
    lines = figure(png)["axes"][0]["lines"]
    curve = [x for x in lines if x["label"].startswith("Christiansen")]
    assert len(curve) == 1 and len(curve[0]["x"]) > 100
    for v, d in zip(curve[0]["x"], curve[0]["y"]):
        assert d == pytest.approx(christiansen.critical_diameter(v * 1e3, 1e-3, 2e-3, 30e-3) * 1e3,
                                  rel=1e-12)
    bars = sorted((x["x"], x["y"]) for x in lines if len(x["x"]) == 2 and x["x"][0] == x["x"][1])
    assert bars == [([3.0, 3.0], [pytest.approx(2.0), pytest.approx(2.5)]),
                    ([5.0, 5.0], [pytest.approx(1.5), pytest.approx(2.0)])]


def test_refusals(out):
    csv = os.path.join(out, "one.csv")
    with open(csv, "w") as f:
        f.write(HEADER.split(",", 1)[1])
        f.write("parameters.d,0.002,0.0025,0,1,4,0,12.5,ok\n")
    r = run_tool("post/plot_limit.py", csv, "--shield", "1e-3", "2e-3", "30e-3", check=2)
    assert "the search has no --vary" in r.stderr
    bad = os.path.join(out, "bad.csv")
    open(bad, "w").write("a,b\n1,2\n")
    r = run_tool("post/plot_limit.py", bad, "--shield", "1e-3", "2e-3", "30e-3", check=2)
    assert "not a limit.csv" in r.stderr
    r = run_tool("post/plot_limit.py", bad, check=2)
    assert "--shield TB TW S is required" in r.stderr
    r = run_tool("post/plot_limit.py", bad, "--shield", "a", "b", "c", check=2)
    assert "--shield needs three numbers" in r.stderr
    r = run_tool("post/plot_limit.py", os.path.join(out, "none.csv"), "--shield", "1", "2", "3",
                 check=2)
    assert "none.csv: no such file" in r.stderr
