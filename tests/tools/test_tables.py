"""tools/docs/tables.py: the generated blocks rewritten between their markers (temporary
files, no simulation), refusals (exit 2, the file named) of missing and doubled markers, the
machine line, the row builders on small fake summaries, and one real table (micro) written."""
import copy
import os

import pytest

from conftest import run_tool
from tools.common import christiansen
from tools.common.summary_keys import MissingKey
from tools.docs import tables as T


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def block_text(name, body):
    begin, end = T.markers(name)
    return f"{begin}\n{body}\n{end}\n"


# Markers -----------------------------------------------------------------------------------------
def test_rewrites_only_the_named_block(tmp_path):
    root = str(tmp_path)
    readme = ("# Title\n\nBefore.\n\n" + block_text("verify", "old verify table") + "\nBetween.\n\n"
              + block_text("verify-full", "old full table") + "\nAfter.\n")
    write(os.path.join(root, "README.md"), readme)
    path = T.write_block("verify", "line one\n\n| a |\n|---|\n| 1 |", root)
    assert path == os.path.join(root, "README.md")
    text = read(path)
    assert "old verify table" not in text
    assert "old full table" in text  # verify-full's block is another block
    assert text.startswith("# Title\n\nBefore.\n\n<!-- BEGIN generated: verify -->\nline one\n")
    assert "| 1 |\n\n<!-- END generated: verify -->\n\nBetween." in text
    assert text.endswith("<!-- END generated: verify-full -->\n\nAfter.\n")
    # Written again: the block replaced, not grown.
    T.write_block("verify", "line one\n\n| a |\n|---|\n| 2 |", root)
    again = read(path)
    assert again == text.replace("| 1 |", "| 2 |")
    assert again.count("<!-- BEGIN generated: verify -->") == 1


def test_finds_the_block_in_docs(tmp_path):
    root = str(tmp_path)
    write(os.path.join(root, "README.md"), "no tables here\n")
    doc = os.path.join(root, "docs", "whipple", "results.md")
    write(doc, "Intro.\n" + block_text("whipple-hole", "x"))
    assert T.locate("whipple-hole", root) == doc
    T.write_block("whipple-hole", "new", root)
    assert read(doc) == "Intro.\n<!-- BEGIN generated: whipple-hole -->\nnew\n\n<!-- END generated: whipple-hole -->\n"


@pytest.mark.parametrize("content, message", [
    ("nothing\n", "no <!-- BEGIN generated: micro -->"),
    (block_text("micro", "a") + block_text("micro", "b"), "appears 2 times"),
    ("<!-- BEGIN generated: micro -->\nno end\n", "without <!-- END generated: micro -->"),
    ("<!-- END generated: micro -->\nno begin\n", "without <!-- BEGIN generated: micro -->"),
    ("<!-- END generated: micro -->\n<!-- BEGIN generated: micro -->\n", "comes before"),
])
def test_refuses_bad_markers(tmp_path, content, message):
    root = str(tmp_path)
    write(os.path.join(root, "README.md"), content)
    with pytest.raises(T.MarkerError) as e:
        T.locate("micro", root)
    assert message in str(e.value)
    assert os.path.join(root, "README.md") in str(e.value)


def test_refuses_a_block_in_two_files(tmp_path):
    root = str(tmp_path)
    write(os.path.join(root, "README.md"), block_text("strength", "a"))
    write(os.path.join(root, "docs", "strength.md"), block_text("strength", "b"))
    with pytest.raises(T.MarkerError) as e:
        T.locate("strength", root)
    assert "README.md" in str(e.value) and "strength.md" in str(e.value)


def test_command_line_refuses_before_running(tmp_path):
    """Exit 2 naming the file, before any run: the program given does not even exist."""
    root = str(tmp_path)
    write(os.path.join(root, "README.md"), block_text("micro", "a") + block_text("micro", "b"))
    r = run_tool("docs/tables.py", "micro", "/nonexistent/tetcontact", "--write", "--docs-root",
                 root, check=2)
    assert os.path.join(root, "README.md") in r.stderr and "appears 2 times" in r.stderr
    # `all` checks every table's markers first: here only micro's are there.
    write(os.path.join(root, "README.md"), block_text("micro", "a"))
    r = run_tool("docs/tables.py", "all", "/nonexistent/tetcontact", "--write", "--docs-root",
                 root, check=2)
    assert "no <!-- BEGIN generated: stability -->" in r.stderr
    assert read(os.path.join(root, "README.md")) == block_text("micro", "a")


def test_every_table_has_a_command():
    assert T.NAMES == ["stability", "micro", "profile", "ccd", "verify", "verify-full", "threads",
                       "mpi", "whipple", "whipple-mesh", "whipple-hole", "strength", "taylor-tests",
                       "taylor-temper", "whipple-shots", "whipple-shots-sph", "whipple-refined",
                       "whipple-refined-sph", "whipple-defaults", "whipple-wall", "whipple-tear", "whipple-debris",
                       "whipple-sph-faces", "whipple-erosion-reference", "whipple-sph-step",
                       "whipple-tillotson",
                       "hugoniot"]
    assert list(T.TABLES) == T.NAMES


# taylor-temper: the library's fitted value and a campaign's errors --------------------------------
def test_temper_reads_the_library_and_the_errors():
    eps = T.library_value(T.TEMPER_ENTRY, "initial_plastic_strain")
    assert T.TEMPER_BRACKET[0] < eps < T.TEMPER_BRACKET[1]
    with pytest.raises(SystemExit, match="no initial_plastic_strain"):
        T.library_value("ofhc-copper", "initial_plastic_strain")  # the entry it derives from
    rows = [{"error:final length": "-0.02", "error:footprint radius": "0.10"},
            {"error:final length": "0.01", "error:footprint radius": ""},
            {"error:final length": "0.04", "error:footprint radius": "-0.06"}]
    assert T.temper_row("r", "SG", "0.3", rows) == (
        "| r | SG | 0.3 | 3 | 2.0 %, 4.0 %, 4.0 % | +1.0 % | 8.0 %, +2.0 % |")


# The machine line --------------------------------------------------------------------------------
def test_machine_line(tmp_path, binary):
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("processor\t: 0\nmodel name\t: Test   CPU 9000\n\nprocessor\t: 1\n"
                       "model name\t: Test CPU 9000\n\nprocessor\t: 2\nmodel name\t: Test CPU 9000\n")
    build = tmp_path / "build"
    (build / "CMakeFiles" / "3.25.1").mkdir(parents=True)
    (build / "CMakeCache.txt").write_text("CMAKE_BUILD_TYPE:STRING=RelWithDebInfo\n")
    (build / "CMakeFiles" / "3.25.1" / "CMakeCXXCompiler.cmake").write_text(
        'set(CMAKE_CXX_COMPILER "/usr/bin/c++")\nset(CMAKE_CXX_COMPILER_ID "GNU")\n'
        'set(CMAKE_CXX_COMPILER_VERSION "12.2.0")\n')
    assert T.cpu(str(cpuinfo)) == ("Test CPU 9000", 3)
    assert T.cmake_build(str(build)) == ("GNU 12.2.0", "RelWithDebInfo")
    line = T.machine_line("micro", binary, cpuinfo=str(cpuinfo), build_dir=str(build))
    assert line.startswith("Measured on Test CPU 9000 (3 cores) with tetcontact ")
    assert "(GNU 12.2.0, RelWithDebInfo build, commit " in line
    assert "tools/docs/tables.py micro" in line
    assert "\n" not in line
    assert T.cmake_build(str(tmp_path / "nowhere")) == ("unknown compiler", "unknown")


# Row builders on fake summaries ------------------------------------------------------------------
def fake_summary(**over):
    s = {
        "case": "fake", "status": "ok", "steps": 12345, "time": 1e-5, "wall_seconds": 10.0,
        "modules": ["broadphase:grid"], "mesh": {"nodes": 10, "tets": 2400},
        "timings": {"elements": 6.0, "broadphase": 1.0, "narrowphase": 0.5, "response": 0.5,
                    "output": 1.0, "verify": 0.25},
        "energy": {"balance_error": 1.5e-4, "balance_error_max": 2.5e-4},
        "momentum": {"relative_error": 3e-16}, "mass": {"relative_error": 0.0},
        "bodies": [{"name": "rod", "mass": 1.0, "velocity": [0, 0, 0],
                    "bbox_min": [-0.005, -0.005, 0.0], "bbox_max": [0.005, 0.005, 0.02]}],
        "time_step": {"min": 1e-9, "first": 2e-9, "collapses": [{}, {}]},
        "penetration": {"max_depth_over_h": 0.05, "max_nodes_inside": 3, "max_crossings": 1,
                        "measured_at": "every step", "samples": 12345},
        "fracture": {"particles": 0, "mass_to_particles": 0.0},
        "safeguards": {"eroded": None, "particles_moved_out": None},
        "contact": {"verification": {"failed_after_passes": 1234, "steps_failed": 7,
                                     "step_cuts": 1500, "steps_with_zones": 5, "impact_zones": 9,
                                     "translated_zones": 8, "frozen_zones": 1}},
        "expect": [{"name": "max_depth_over_h", "bound": 0.1, "measured": 0.05, "pass": True},
                   {"name": "energy_balance", "bound": 1e-3, "measured": 2.5e-4, "pass": True}],
        "expect_pass": True,
    }
    s.update(over)
    return s


def cells(row):
    assert row.startswith("| ") and row.endswith(" |")
    return [c.strip() for c in row[2:-2].split(" | ")]


def test_stability_row():
    on, off = fake_summary(), fake_summary(expect_pass=False)
    off["penetration"] = dict(off["penetration"], max_depth_over_h=0.8)
    row = cells(T.stability_row("touching-gap0", on, 0, off, 1))
    assert row[0] == "`touching-gap0`" and row[1] == T.WHAT["touching-gap0"]
    assert row[2] == "12,345, 1.0e-9 s"
    assert row[3] == "3.0e-16"
    assert row[4] == "2.5e-4 (1.0e-3)"
    assert row[5] == "0.05 (0.1), 3, 1"
    assert row[6] == "–"
    assert row[7] == "0.8, fails"
    # A missed check is flagged; contact off that still passes says so.
    assert T.stability_row("x", on, 1, fake_summary(), 0).endswith("| **check failed**")
    assert cells(T.stability_row("x", on, 0, fake_summary(), 0))[7] == "0.05, PASSES"
    eroding = fake_summary(safeguards={"eroded": 1200, "particles_moved_out": 3})
    assert cells(T.stability_row("x", eroding, 0, None, None))[6] == "1,200 eroded, 3 moved out"


def test_a_missing_key_is_named():
    s = fake_summary()
    del s["energy"]["balance_error_max"]
    with pytest.raises(MissingKey) as e:
        T.stability_row("x", s, 0, None, None)
    assert "energy.balance_error_max" in str(e.value)


def test_micro_row():
    scene = {"name": "edge-in-face", "steps": 39, "pass": True, "momentum_error": 1e-16,
             "balance_error": 5e-3, "max_depth_over_h": 0.0, "nodes_inside": 0, "crossings": 4,
             "expect": [{"name": "max_depth_over_h", "bound": 2e-6}]}
    verified = dict(scene, crossings=0)
    off = dict(scene, max_depth_over_h=0.16, **{"pass": False})
    assert cells(T.micro_row("edge-in-face", scene, verified, off)) == [
        "edge-in-face", "39", "yes", "1.0e-16", "5.0e-3", "0 (2.0e-6)", "0", "4", "0 / 0, yes",
        "0.16, no"]


def test_profile_row():
    m = {"method": "grid", "primitives": 12345.0, "candidates_per_step": 10.25,
         "contacts_per_step": 2.0, "pruning_ratio": 1e-4,
         "seconds_per_step": {"build": 1e-4, "query": 2e-4, "step": 1e-3},
         "broadphase_share": 0.3, "contact_share": 0.45}
    assert cells(T.profile_row(m)) == ["grid", "12,345", "10.2", "2.0", "1.0e-4", "0.100",
                                       "0.200", "1.000", "30.0 %", "45.0 %"]


def test_ccd_rows():
    fcl = {"collisions": 9, "false_positives": 3, "false_negatives": 1, "mean_ns": 40.2}
    truth = {"ee": {"queries": 1234, "collisions": 7, "mean_ns": 812.6, "false_positives": 0,
                    "false_negatives": 0, "fcl": fcl},
             "vf": {"queries": 10, "collisions": 2, "mean_ns": 99.4, "false_positives": 1,
                    "false_negatives": 2, "fcl": fcl}}
    ee, vf = (cells(r) for r in T.ccd_rows("set", truth))
    assert ee == ["set", "edge–edge", "1,234", "7", "**0 / 0**", "**813 ns**", "9, 3 / 1, 40 ns"]
    assert vf[4] == "**1 / 2**"
    blind = {k: {"queries": 5, "collisions": 1, "mean_ns": 50.0,
                 "fcl": {"collisions": 0, "mean_ns": 16.0}} for k in ("ee", "vf")}
    ee, _ = (cells(r) for r in T.ccd_rows("steps", blind))
    assert ee[4] == "– (no ground truth)" and ee[6] == "0, 16 ns"
    with pytest.raises(KeyError):
        list(T.ccd_rows("broken", {"ee": {}}))


def test_threads_row_and_stage_shares():
    one, two = fake_summary(), fake_summary(wall_seconds=5.0)
    assert T.stage_shares(one) == "elements 60 %, contact 20 %, output 10 %"
    row = cells(T.threads_row("bars", one, two))
    assert row[:6] == ["bars", "2,400", "12,345", "10.0 s", "5.0 s", "2.00×"]
    assert row[7] == "elements 120 %, contact 40 %, output 20 %"


def test_mpi_rows():
    a = fake_summary()
    c = fake_summary(wall_seconds=6.0, parallel={"communication_seconds": 0.5})
    row = cells(T.mpi_row("bars", a, fake_summary(wall_seconds=7.0), c))
    assert row == ["bars", "2,400", "12,345", "10.0 s", "7.0 s", "6.0 s", "6.0 s / 6.0 s",
                   "0.2 s / 0.2 s", "0.50 s", "yes"]
    different = copy.deepcopy(c)
    different["energy"]["balance_error"] = 0.1
    assert cells(T.mpi_row("bars", a, a, different))[-1] == "NO"
    assert cells(T.weak_row("pair", 12.5, [a, a], 10.0, True)) == [
        "pair", "2 × 2,400", "12,345", "12.5 s", "6.0 s", "–", "80 %"]
    with pytest.raises(MissingKey):  # a 2-rank row needs the communication time
        T.weak_row("two", 12.5, [a], 10.0, False)


def test_verify_rows():
    s = fake_summary(references=[{"name": "hole", "measured": 2.0, "pass": False}])
    row = cells(T.verify_row("cubes-edge", s))
    assert row == ["cubes-edge", "on", "1 / 3 at all 12345 steps", "**hole 2**",
                   "1,234 (7 of 12345)", "1,500", "5: 9 (8 / 1)", "0.25 s / 10 s"]
    off = fake_summary(contact={})
    off["penetration"]["measured_at"] = "output frames"
    assert cells(T.verify_row("bars", off)) == ["bars", "off", "1 / 3 at the frames", "pass",
                                                "—", "—", "—", "— / 10 s"]
    full = cells(T.verify_full_row("ball-plate", fake_summary()))
    assert full == ["ball-plate", "1 / 3 at all 12345 steps", "pass", "3.0e-16", "2.5e-4",
                    "1,234 (7 of 12345)", "1,500", "5: 9 (8 / 1)", "0.25 s / 10 s"]


def test_strength_row():
    rod = fake_summary()
    plate = fake_summary(references=[{"name": "elastic precursor (HEL)", "measured": 0.672e9}])
    row = cells(T.strength_row("johnson_cook", rod, plate))
    assert row == ["Johnson–Cook", "12,345", "0.500", "2", "20.00, 0.852", "5.00, 1.31",
                   "1.5e-4", "10.0 s", "0.672 (+5.0 %)"]


WHIPPLE_REFERENCES = [
    {"name": "bumper hole diameter", "measured": 9.5e-3},
    {"name": "debris leading-edge speed", "measured": 6123.0},
    {"name": "debris cone half-angle", "measured": 31.4},
    {"name": "debris mass", "measured": 0.41e-3},
    {"name": "debris mass in particles", "measured": 0.2e-3},
    {"name": "largest fragment", "measured": 1.25e-6},
    {"name": "wall perforated", "measured": 1.0},
    {"name": "mass through the wall", "measured": 12.3e-6},
]


def test_whipple_rows():
    p = {"d": 4e-3, "v": 6500.0, "tb": 1e-3, "tw": 2e-3, "S": 15e-3, "theta": 0.0}
    parts = [{"name": "projectile", "particles": 1, "mass": 1e-6, "ductile_failed": 321,
              "ductile_failed_at_floor": 300},
             {"name": "bumper", "particles": 2, "mass": 1e-6, "ductile_failed": 3000,
              "ductile_failed_at_floor": 1234},
             {"name": "wall", "particles": 2, "mass": 1e-6, "ductile_failed": 1000,
              "ductile_failed_at_floor": 0}]
    s = fake_summary(parameters=p, references=WHIPPLE_REFERENCES,
                     fracture={"particles": 5, "mass_to_particles": 1e-4, "ductile_failed": 4321,
                               "from_bodies": parts})
    dc = christiansen.critical_diameter(6500.0, 1e-3, 2e-3, 15e-3)
    row = cells(T.whipple_row("2 mm wall", s))
    assert row[1] == f"{4e-3 / dc:.2f} (4 / {dc * 1e3:.2f} mm)"
    assert row[2:] == ["12,345, 10 s", "9.5 mm", "6,123 m/s", "31°", "0.410 g (0.200 g)",
                       "1.25 mg", "yes: 12.3 mg", "1.5e-4"]
    assert cells(T.whipple_mesh_row("coarse", s)) == [
        "coarse", "2,400", "12,345, 10 s", "9.5 mm", "6,123 m/s", "31°", "0.410 g",
        "yes: 12.3 mg", "4,321", "300/321, 1,234/3,000, 0/1,000", "1.5e-4"]
    assert cells(T.whipple_hole_row("fine", s)) == [
        "fine", "2,400", "12,345, 10 s", "9.5 mm", "6,123 m/s", "4,321",
        "300/321, 1,234/3,000, 0/1,000", "1.5e-4"]
    assert T.ductile_parts(s) == [(321, 300), (3000, 1234), (1000, 0)]
    with pytest.raises(KeyError):  # a run without the case's measures
        T.whipple_mesh_row("coarse", fake_summary(references=[], fracture=s["fracture"]))


def test_whipple_refined_sph_runs_both_meshes_with_sph_debris(monkeypatch):
    seen = {}

    def rows(binary, work, prefix, rows, meshes):
        seen.update(prefix=prefix, rows=rows, meshes=meshes)
        return [], [("P", "NP", ["NP", "P"])]
    monkeypatch.setattr(T, "whipple_mesh_rows", rows)
    lines = list(T.whipple_refined_sph("tetcontact", "work", None))
    assert seen["prefix"] == "whipple-refined-sph-"
    assert seen["rows"] == T.WHIPPLE_REFINED_SPH_ROWS
    assert set(T.WHIPPLE_REFINED_SPH_ROWS.split(",")) < set(T.WHIPPLE_REFINED_ROWS.split(","))
    assert [m[2] for m in seen["meshes"]] == [
        ["fracture.debris=sph", "fracture.erosion_step_ratio=0.5"],
        ["fracture.debris=sph", "fracture.erosion_step_ratio=0.5", 'parameters.hw="= tw / 6"']]
    assert lines[-1] == ("Right: the equation 0 of 1, the shipped mesh 0, the finer wall 1; the "
                         "verdict changes with the wall's refinement on 1 of 1.")


def test_whipple_refined_row():
    refs = WHIPPLE_REFERENCES + [{"name": "wall thickness left", "measured": 0.4444}]
    s = fake_summary(references=refs, fracture={"from_bodies": [
        {"name": "projectile", "particles": 7, "mass": 1e-6},
        {"name": "wall", "particles": 9, "mass": 25e-6}]})
    shipped = T.whipple_refined_cells({"predicted:wall perforated": "NP", "wall_seconds": "31.6"}, s)
    assert shipped == ("NP", 12.3e-6, 0.4444, 100e-6, 31.6)  # the particles: four quarters
    finer = ("P", 1.1e-6, 0.0, 384e-6, 455.2)
    shot = {"wall_thick": "0.254", "velocity": "6.9", "result": "P"}
    assert cells(T.whipple_refined_row(306, 317, shot, "NP", [shipped, finer])) == [
        "306 (317)", "2.54 mm", "6.9 km/s", "P", "NP", "NP, 0.44, 100.0 mg",
        "P (1.1 mg), 0.00, 384.0 mg", "32 s, 455 s"]
    # Any number of meshes, each its cell and its time (whipple-wall's three).
    assert cells(T.whipple_refined_row(306, 317, shot, "NP", [shipped, finer, shipped])) == [
        "306 (317)", "2.54 mm", "6.9 km/s", "P", "NP", "NP, 0.44, 100.0 mg",
        "P (1.1 mg), 0.00, 384.0 mg", "NP, 0.44, 100.0 mg", "32 s, 455 s, 32 s"]
    with pytest.raises(KeyError):  # a run of a case without the measure
        T.whipple_refined_cells({"predicted:wall perforated": "NP", "wall_seconds": "1"},
                                fake_summary(references=WHIPPLE_REFERENCES, fracture=s["fracture"]))


def test_whipple_tear_row():
    refs = WHIPPLE_REFERENCES + [{"name": "wall thickness left", "measured": 0.4444},
                                 {"name": "wall bulge", "measured": 0.9876e-3}]
    s = fake_summary(references=refs)
    tear = T.whipple_tear_cells({"predicted:wall perforated": "P", "wall_seconds": "40.4"}, s)
    assert tear == ("P", 12.3e-6, 0.4444, 0.9876e-3, 40.4)
    shot = {"wall_thick": "0.254", "velocity": "6.9", "result": "P"}
    assert cells(T.whipple_refined_row(306, 317, shot, "NP", [tear], T.mm)) == [
        "306 (317)", "2.54 mm", "6.9 km/s", "P", "NP", "P (12.3 mg), 0.44, 0.99 mm", "40 s"]
    with pytest.raises(KeyError):  # a run of a case without the bulge
        T.whipple_tear_cells({"predicted:wall perforated": "NP", "wall_seconds": "1"},
                             fake_summary(references=WHIPPLE_REFERENCES + refs[-2:-1]))


def test_whipple_tillotson_row():
    refs = WHIPPLE_REFERENCES + [{"name": "wall thickness left", "measured": 0.5}]
    refs = [dict(r, measured=5990.0) if r["name"] == "debris leading-edge speed" else r
            for r in refs]
    s = fake_summary(references=refs, steps=12345, energy={"balance_error_max": 1.75e-3})
    eos = T.whipple_eos_cells({"predicted:wall perforated": "P", "wall_seconds": "200.2"}, s)
    assert eos == ("P", 12.3e-6, 0.5, (5990.0, 12345, 1.75e-3), 200.2)
    shot = {"wall_thick": "0.254", "velocity": "6.9", "result": "P"}
    assert cells(T.whipple_refined_row(306, 317, shot, "NP", [eos], T.speed_steps_balance)) == [
        "306 (317)", "2.54 mm", "6.9 km/s", "P", "NP", "P (12.3 mg), 0.50, 5.99 km/s, 12,345, "
        "1.8e-3", "200 s"]
    with pytest.raises(KeyError):  # a run of a case without the cloud's speed
        T.whipple_eos_cells({"predicted:wall perforated": "NP", "wall_seconds": "1"},
                            fake_summary(references=[r for r in refs if "speed" not in r["name"]],
                                         steps=1, energy={"balance_error_max": 0.0}))


def test_whipple_defaults_row():
    # (measured, the shipped verdict, this setting's cells, the wall's momentum, the largest
    # fragment, the parts' ductile failures): two P shots, one NP.
    shots = [("P", "NP", ("P", 1e-6, 0.30, 200e-6, 40.0), 0.25, 3e-7, [(10, 9), (5, 1), (2, 0)]),
             ("P", "NP", ("NP", 0.0, 0.50, 100e-6, 20.0), 0.125, 1e-6, [(0, 0), (5, 5), (0, 0)]),
             ("NP", "NP", ("NP", 0.0, 0.90, 0.0, 60.0), 0.125, 2e-8, [(990, 1), (0, 0), (1, 1)])]
    assert cells(T.whipple_defaults_row("erosion", shots)) == [
        "erosion", "2 of 3", "1", "0.40, 0.90", "300.0 mg", "0.50 kg m/s", "0.30 mg",
        "10/1,000, 6/10, 1/3", "2.0 min (60 s)"]
    assert cells(T.whipple_defaults_row("no NP", shots[:2]))[3] == "0.40, –"
    # The whole wall's momentum along −z: the quarter's times four.
    s = fake_summary(bodies=[{"name": "bumper", "mass": 1.0, "velocity": [0, 0, -9.0]},
                             {"name": "wall", "mass": 0.5, "velocity": [0.1, 0.0, -2.0]}],
                     mesh={"multiplicity": 4})
    assert T.wall_momentum(s) == pytest.approx(4.0)
    s = fake_summary(references=[{"name": "largest fragment", "measured": 2.5e-7}])
    assert T.largest_fragment(s) == 2.5e-7


def test_whipple_limit_helpers(tmp_path):
    key = tmp_path / "run.key"
    key.write_text("program 0123456789abcdef\ncase /x/whipple.yaml\nset parameters.d=0.003175\nset parameters.v=6900\n"
                   "set parameters.tw=0.00254\nset materials.wall.from=al6061-t6\ntext\nname: w\n"
                   "set up: a case's text line that is not an override\n")
    assert T.limit_search_sets(str(key)) == ["parameters.tw=0.00254", "materials.wall.from=al6061-t6"]
    assert T.whipple_limit_cell(3.1e-3, 3.4e-3, "ok") == "3.10–3.40 mm"
    assert T.whipple_limit_cell(3.1e-3, 3.4e-3, "ok", "1", "0") == \
        "3.10–3.40 mm, reversed (P at 3.10 mm)"
    assert T.whipple_limit_cell(2e-3, 12e-3, "no bracket: the criterion is not met at both ends") \
        == "above 12.00 mm (NP at 2.00 and 12.00 mm)"
    assert T.whipple_limit_cell(2e-3, 12e-3, "no bracket: the criterion is met at both ends") \
        == "below 2.00 mm (P at 2.00 and 12.00 mm)"
    assert T.whipple_limit_cell(2e-3, 12e-3, "run at parameters.d=0.002: failed") \
        == "not found: run at parameters.d=0.002: failed"


# One real table ----------------------------------------------------------------------------------
def test_micro_table_written(tmp_path, binary, out):
    root = str(tmp_path)
    doc = os.path.join(root, "docs", "contact.md")
    write(os.path.join(root, "README.md"), "See docs/contact.md.\n")
    write(doc, "# Contact\n\n" + block_text("micro", "stale") + "\nEnd.\n")
    r = run_tool("docs/tables.py", "micro", binary, "--write", "--docs-root", root, "--work",
                 out, check=0)
    assert f"written: micro in {doc}" in r.stdout
    text = read(doc)
    inner = text.split("<!-- BEGIN generated: micro -->\n")[1].split("<!-- END generated: micro -->")[0]
    lines = inner.strip().splitlines()
    assert lines[0].startswith("Measured on ") and "cores) with tetcontact" in lines[0]
    assert lines[1] == ""
    assert lines[2:4] == T.MICRO_HEADER
    rows = [cells(line) for line in lines[4:]]
    assert {r[0] for r in rows} == {"coincident-faces", "edge-in-face", "point-touch",
                                    "vertex-on-edge"}
    assert all(r[2] == "yes" for r in rows)  # the shipped micro-scenes hold their bounds
    assert text.startswith("# Contact\n\n") and text.endswith("\nEnd.\n")
    assert read(os.path.join(root, "README.md")) == "See docs/contact.md.\n"
