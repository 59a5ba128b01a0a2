"""tools/dev/compare_runs.py: the same program twice gives identical results (exit 0); a
changed setting for the new run is found (exit 1, the first different file named); a failing
run is exit 2."""
import os

from conftest import case, run_tool

SHORT = ["--set", "end_time=3e-6", "--set", "output.interval=1e-6", "--set", "solver.threads=1"]


def test_identical(binary, out):
    r = run_tool("dev/compare_runs.py", binary, binary, case("cubes-edge"), *SHORT, "--work",
                 out, check=0)
    assert r.stdout.strip().endswith("identical (4 frames and history.csv)")
    assert os.path.isfile(os.path.join(out, "old", "history.csv"))


def test_different(binary, out):
    r = run_tool("dev/compare_runs.py", binary, binary, case("cubes-edge"), *SHORT,
                 "--new-set", "contact.passes=1", "--work", out, check=1)
    assert "DIFFERENT at frame_0001.vtu" in r.stdout


def test_failing_run(binary, out):
    r = run_tool("dev/compare_runs.py", binary, binary, case("cubes-edge"), "--set",
                 "no_such_key=1", "--work", out, check=2)
    assert "exit 2" in r.stderr
