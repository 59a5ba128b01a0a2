"""tools/dev/random_ccd_queries.py: the ccd file format (TYPE and 24 coordinates), alternating
vf and ee, half on the integer grid, the same file for the same seed; `tetcontact ccd` reads it
and the CGAL oracle agrees with the exact path on every query."""
import json
import subprocess

from conftest import run_tool


def queries(path):
    return [line.split() for line in open(path).read().splitlines()]


def test_format_and_seed(tmp_path):
    a, b, c = (str(tmp_path / n) for n in ("a.txt", "b.txt", "c.txt"))
    run_tool("dev/random_ccd_queries.py", "40", a, "--seed", "7", check=0)
    run_tool("dev/random_ccd_queries.py", "40", b, "--seed", "7", check=0)
    run_tool("dev/random_ccd_queries.py", "40", c, "--seed", "8", check=0)
    assert open(a).read() == open(b).read() != open(c).read()
    q = queries(a)
    assert len(q) == 40
    assert [x[0] for x in q] == ["vf", "ee"] * 20
    assert all(len(x) == 25 for x in q)
    coords = [[float(v) for v in x[1:]] for x in q]
    for i, c in enumerate(coords):
        if i % 4 < 2:  # generic: start in [-1, 1], moved by up to 1
            assert all(-1 <= v <= 1 for v in c[:12]) and all(-2 <= v <= 2 for v in c[12:])
        else:  # the integer grid {-2, ..., 2}
            assert all(v == int(v) and -2 <= v <= 2 for v in c)


def test_the_program_reads_them(binary, tmp_path):
    path = str(tmp_path / "q.txt")
    run_tool("dev/random_ccd_queries.py", "40", path, "--seed", "7", check=0)
    r = subprocess.run([binary, "ccd", path, "--confirm", "cgal", "--json", "--quiet"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    for kind in ("vf", "ee"):
        assert res[kind]["queries"] == 20
        assert res[kind]["cgal"]["disagreements"] == 0
        assert res[kind]["cgal"]["agreements"] + res[kind]["cgal"]["undecided"] == 20
