"""tools/common/summary_keys.py against the program's own output: every path the tools read
is in the summaries of small runs that have what it needs (verification, particles, parameters
and references, ductile failure, mpirun), every measure name the tables read is one the shipped
cases name, the sweep.csv and limit.csv columns are the program's, and `get` names a missing
key and its file."""
import os
import subprocess

import pytest

from conftest import ROOT, SMALL_WHIPPLE, case, run_case
from tools.common import summary_keys as K


def paths(*names):
    return [getattr(K, n) for n in names]


@pytest.fixture(scope="module")
def runs(binary, module_out):
    out = {}
    out["cubes"] = run_case(binary, case("cubes-edge"), os.path.join(module_out, "cubes"),
                            "end_time=2e-6", "contact.verify=true")
    out["whipple"] = run_case(binary, case("whipple"), os.path.join(module_out, "whipple"),
                              *SMALL_WHIPPLE)
    out["whipple_sph"] = run_case(binary, case("whipple"), os.path.join(module_out, "whipple-sph"),
                                  *SMALL_WHIPPLE, "fracture.debris=sph")
    out["plate"] = run_case(binary, case("plate-impact-1d"), os.path.join(module_out, "plate"))
    mpi = os.path.join(module_out, "mpi")
    r = subprocess.run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", binary,
                        "run", case("cubes-edge"), "--quiet", "--force", "--threads", "1",
                        "--out", mpi, "--set", "end_time=2e-6"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    import json
    with open(os.path.join(mpi, "summary.json")) as f:
        out["mpi"] = json.load(f)
    return out


def test_every_run_has_the_always_paths(runs):
    for name, s in runs.items():
        for path in K.ALWAYS:
            K.get(s, path, name)  # MissingKey names the path when it is not there


def test_conditional_paths(runs):
    for path in paths("EXPECT", "EXPECT_PASS", "VERIFICATION", "VERIFY_FAILED_AFTER_PASSES",
                      "VERIFY_STEPS_FAILED", "VERIFY_STEPS_WITH_ZONES", "VERIFY_IMPACT_ZONES",
                      "VERIFY_TRANSLATED_ZONES", "VERIFY_FROZEN_ZONES", "MAX_NODES_INSIDE",
                      "MAX_CROSSINGS", "PENETRATION_MEASURED_AT"):
        K.get(runs["cubes"], path, "cubes-edge with contact.verify")
    for path in paths("PARAMETERS", "REFERENCES", "PARTICLES_INSIDE_AT_END",
                      "FRACTURE_FROM_BODIES", "FRACTURE_DUCTILE_FAILED",
                      "FRACTURE_DUCTILE_FAILED_AT_FLOOR", "FRACTURE_DEBRIS",
                      "ENERGY_CONTACT_WORK", "ENERGY_TOTAL_INITIAL"):
        K.get(runs["whipple"], path, "whipple")
    assert K.get(runs["whipple"], K.FRACTURE_DEBRIS) == "points"
    assert K.get(runs["whipple_sph"], K.FRACTURE_DEBRIS) == "sph"
    assert K.get(runs["whipple_sph"], K.FRACTURE_SPH_NEIGHBOURS) >= 0
    K.get(runs["mpi"], K.COMMUNICATION_SECONDS, "cubes-edge under mpirun")
    for item in K.get(runs["cubes"], K.EXPECT):
        assert {K.NAME, K.BOUND, K.MEASURED, K.PASS} <= set(item)
    for body in K.get(runs["cubes"], K.BODIES):
        assert {K.NAME, K.MASS, K.VELOCITY, K.BBOX_MIN, K.BBOX_MAX} <= set(body)
    by_body = K.get(runs["whipple"], K.FRACTURE_FROM_BODIES)
    for b in by_body:
        assert {K.NAME, K.PARTICLES, K.MASS, K.DUCTILE_FAILED, K.DUCTILE_FAILED_AT_FLOOR} <= set(b)
        assert 0 <= b[K.DUCTILE_FAILED_AT_FLOOR] <= b[K.DUCTILE_FAILED]
    # The bodies' ductile failures are the run's (each cell counted once, in its body).
    assert sum(b[K.DUCTILE_FAILED] for b in by_body) == K.get(runs["whipple"],
                                                               K.FRACTURE_DUCTILE_FAILED) > 0
    assert sum(b[K.DUCTILE_FAILED_AT_FLOOR] for b in by_body) == K.get(
        runs["whipple"], K.FRACTURE_DUCTILE_FAILED_AT_FLOOR)
    names = {e[K.NAME] for e in K.get(runs["cubes"], K.EXPECT)}
    assert K.EXPECT_ENERGY in names
    stages = set(K.get(runs["cubes"], K.TIMINGS))
    assert {K.STAGE_ELEMENTS, K.STAGE_VERIFY, K.STAGE_OUTPUT, K.STAGE_BALANCE} <= stages
    assert set(K.CONTACT_STAGES) <= stages


def test_measure_names(runs):
    whipple = {r[K.NAME] for r in K.get(runs["whipple"], K.REFERENCES)}
    assert {K.HOLE_DIAMETER, K.DEBRIS_SPEED, K.DEBRIS_CONE_ANGLE, K.DEBRIS_MASS,
            K.DEBRIS_PARTICLE_MASS, K.LARGEST_FRAGMENT, K.WALL_PERFORATED,
            K.MASS_THROUGH_WALL} <= whipple
    assert K.HEL in {r[K.NAME] for r in K.get(runs["plate"], K.REFERENCES)}


def test_history_and_csv_columns(runs, binary, module_out):
    history = os.path.join(module_out, "cubes", "history.csv")
    header = open(history).readline().strip().split(",")
    assert any(h.startswith(K.HISTORY_SECONDS_PREFIX) for h in header)
    out = os.path.join(module_out, "sweep")
    r = subprocess.run([binary, "sweep", case("bars-impact"), "--vary", "contact.passes=1,2",
                        "--threads", "1", "--quiet", "--out", out],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    columns = open(os.path.join(out, "sweep.csv")).readline().strip().split(",")
    assert columns[1:6] == [K.SWEEP_STATUS, K.SWEEP_WALL_SECONDS, K.SWEEP_STEPS, K.SWEEP_TETS,
                            K.SWEEP_ERROR]
    assert K.SWEEP_ENERGY_BALANCE_MAX in columns
    # limit.csv's header, as src/app/limit.cpp writes it.
    source = open(os.path.join(ROOT, "src", "app", "limit.cpp")).read()
    assert f'"{K.LIMIT_KEY},{K.LIMIT_LO},{K.LIMIT_HI},' in source


def test_get_names_the_missing_key():
    doc = {"energy": {"balance_error": 1.0}}
    assert K.get(doc, K.ENERGY_BALANCE_ERROR) == 1.0
    with pytest.raises(K.MissingKey) as e:
        K.get(doc, K.ENERGY_BALANCE_ERROR_MAX, "run/summary.json")
    assert str(e.value) == "run/summary.json: no key energy.balance_error_max"
    with pytest.raises(K.MissingKey) as e:
        K.get(doc, K.MESH_TETS)
    assert str(e.value) == "summary.json: no key mesh"
    assert K.has(doc, K.ENERGY_BALANCE_ERROR) and not K.has(doc, K.MESH_TETS)
