"""What the tools' tests share: the program under test, a folder per test, a short run.

The program is $TETCONTACT_BINARY (tests/tools/tools.cmake passes $<TARGET_FILE:tetcontact>),
else build/tetcontact; a test that needs it fails, never skips, when it is not there. Outputs go
to $TETCONTACT_TEST_OUTPUT/<test file>/<test> (build/test-output/tools/...), else pytest's
temporary folder."""
import json
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PYTHON = "/usr/bin/python3"  # Debian's, with numpy, vtk9 and matplotlib
# The plot tools write what they draw beside each PNG (tools/common/figure_data.py): read it
# with figure().
os.environ["TETCONTACT_FIGURE_DATA"] = "1"


def figure(png):
    """What the figure OUT.png draws, as tools/common/figure_data.py writes it."""
    with open(png + ".json") as f:
        return json.load(f)


def case(name):
    """The path of a shipped case: case("cubes-edge") is data/cases/cubes-edge.yaml."""
    path = os.path.join(ROOT, "data", "cases", name + ".yaml")
    assert os.path.isfile(path), path + ": no such case"
    return path


def tool(path):
    """The path of a tool script: tool("post/check_vtu.py")."""
    full = os.path.join(ROOT, "tools", path)
    assert os.path.isfile(full), full + ": no such tool"
    return full


def run_tool(path, *args, check=None):
    """Runs a tool by path with Debian's python; returns the CompletedProcess (text). With
    check=N, asserts the exit code is N and shows stdout and stderr when it is not."""
    r = subprocess.run([PYTHON, tool(path)] + [str(a) for a in args], capture_output=True,
                       text=True, cwd=ROOT)
    if check is not None:
        assert r.returncode == check, f"{path} exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


@pytest.fixture(scope="module")
def binary():
    path = os.environ.get("TETCONTACT_BINARY") or os.path.join(ROOT, "build", "tetcontact")
    assert os.path.isfile(path) and os.access(path, os.X_OK), (
        f"{path}: no tetcontact program (set TETCONTACT_BINARY or build it)")
    return path


@pytest.fixture
def out(request, tmp_path):
    """An empty folder for this test's files."""
    base = os.environ.get("TETCONTACT_TEST_OUTPUT")
    if not base:
        return str(tmp_path)
    path = os.path.join(base, request.module.__name__, request.node.name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


@pytest.fixture(scope="module")
def module_out(request, tmp_path_factory):
    """An empty folder shared by one test file's tests (for a run they all read)."""
    base = os.environ.get("TETCONTACT_TEST_OUTPUT")
    if not base:
        return str(tmp_path_factory.mktemp(request.module.__name__))
    path = os.path.join(base, request.module.__name__, "shared")
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


# A small Whipple shield (bumper 12 mm square, wall 30 mm square, 6 mm behind, coarse cells) to
# 1.5 µs: about 3,500 tets and 2,000 particles of debris in 2 s. The case's own output.fields
# (no displacement, stress or von_mises).
SMALL_WHIPPLE = ["parameters.hb=1.0e-3", "parameters.hw=2.0e-3", "parameters.np=6",
                 "parameters.ww=30e-3", "parameters.wb=12e-3", "parameters.S=6e-3",
                 "end_time=1.5e-6", "output.interval=0.5e-6"]


def run_case(binary, case_path, outdir, *sets, extra=()):
    """Runs a case on one thread with --set KEY=VALUE for each of `sets`; asserts it finished
    (exit 0) and returns its summary.json."""
    cmd = [binary, "run", case_path, "--quiet", "--force", "--threads", "1", "--out", outdir]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd + list(extra), capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr}"
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)
