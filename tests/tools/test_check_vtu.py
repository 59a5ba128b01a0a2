"""tools/post/check_vtu.py: it checks the arrays a run asked for (its output.fields, or the
first frame's), not a fixed list: a Whipple run (no displacement, stress or von_mises) passes,
a missing array or frame is a FAIL line, a folder that is not a run's a clear error (exit 2),
never a traceback. (The ctests vtk_reader_opens_output, vtk_reader_opens_particles and
vtk_reader_reads_all_formats run its --run and --formats modes on shipped cases.)"""
import os

import pytest

from conftest import SMALL_WHIPPLE, case, run_case, run_tool
from tools.post import check_vtu


@pytest.fixture(scope="module")
def whipple(binary, module_out):
    out = os.path.join(module_out, "whipple")
    summary = run_case(binary, case("whipple"), out, *SMALL_WHIPPLE)
    assert summary["fracture"]["particles"] > 0
    return out


def no_traceback(r):
    assert "Traceback" not in r.stderr + r.stdout


def test_whipple_run_passes_with_its_own_arrays(whipple):
    r = run_tool("post/check_vtu.py", whipple, check=0)
    no_traceback(r)
    line = [x for x in r.stdout.splitlines() if "the arrays of the first frame" in x]
    assert line, r.stdout
    fields = line[0].split(": ")[-1].split(", ")
    # whipple.yaml's output.fields, and nothing it did not ask for.
    assert sorted(fields) == sorted(["velocity", "pressure", "plastic_strain", "temperature",
                                     "damage", "ductile_damage", "body"])
    assert " 0 failed" in r.stdout


def test_asked_for_arrays_that_are_missing_fail_clearly(whipple):
    r = run_tool("post/check_vtu.py", whipple, "--fields", "velocity,displacement,stress,body",
                 check=1)
    no_traceback(r)
    assert "FAIL: frame_0000.vtu (point data): array displacement with 3 components" in r.stdout
    assert "FAIL: frame_0000.vtu (cell data): array stress with 6 components" in r.stdout
    # And arrays written that were not asked for are named.
    assert "array pressure written, not asked for" in r.stdout


def test_fewer_arrays_asked_for(binary, out):
    """A small run asking for two arrays only: they are checked, in node and cell data."""
    run_case(binary, case("cubes-edge"), out, "end_time=2e-6", "output.interval=1e-6",
             "output.fields=[velocity,body]")
    r = run_tool("post/check_vtu.py", out, check=0)
    assert "the arrays of the first frame: velocity, body" in r.stdout
    r = run_tool("post/check_vtu.py", out, "--fields", "velocity,body", check=0)
    assert " 0 failed" in r.stdout
    assert check_vtu.checks["failed"] == 0  # the module imports without running anything


def test_unknown_field_and_bad_folders(whipple, tmp_path):
    r = run_tool("post/check_vtu.py", whipple, "--fields", "velocity,colour", check=2)
    assert "unknown output field colour" in r.stderr
    no_traceback(r)
    r = run_tool("post/check_vtu.py", str(tmp_path), check=2)
    assert f"{tmp_path}/summary.json: no such file" in r.stderr
    no_traceback(r)
    r = run_tool("post/check_vtu.py", check=2)  # no arguments: the usage
    assert "check_vtu.py OUTDIR" in r.stderr


def test_a_missing_frame_is_a_failure(binary, out):
    run_case(binary, case("cubes-edge"), out, "end_time=2e-6", "output.interval=1e-6")
    os.remove(os.path.join(out, "frame_0001.vtu"))
    r = run_tool("post/check_vtu.py", out, check=1)
    no_traceback(r)
    assert "FAIL: frame_0001.vtu: the file case.pvd lists is there" in r.stdout
