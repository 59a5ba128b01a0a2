"""tools/post/whipple_scores.py: the engine's and Christiansen's verdicts on the same shots,
per configuration. The equation's verdicts are checked against tools/common/christiansen.py
called directly; a folder that is not a campaign's, and a row outside the table, are refused."""
import os

from conftest import run_tool

TABLE = """# two shots of one shield, one of another
source,shotID,proj_mat,proj_density,proj_diam,angle,velocity,bumper_mat,bumper_density,bumper_thick,standoff,wall_mat,wall_density,wall_yield,wall_thick,result,perforated_class
-,-,-,g/cm3,cm,deg,km/s,-,g/cm3,cm,cm,-,g/cm3,ksi,cm,-,-
a,1,AA2017-T4,2.8,0.3175,0,6.5,AA6061-T6,2.7,0.07874,5.08,AA6061-T6,2.7,40,0.254,P,1
a,2,AA2017-T4,2.8,0.1,0,6.5,AA6061-T6,2.7,0.07874,5.08,AA6061-T6,2.7,40,0.254,NP,0
a,3,AA2017-T4,2.8,0.3175,0,3.0,AA6061-T6,2.7,0.07874,5.08,AA6061-T6,2.7,40,0.4064,NP,0
"""


def test_scores_and_figures(out):
    table = os.path.join(out, "shots.csv")
    open(table, "w").write(TABLE)
    camp = os.path.join(out, "campaign")
    os.makedirs(camp)
    # The engine: right on row 1, wrong on row 2 (P for an NP), right on row 3.
    open(os.path.join(camp, "predictions.csv"), "w").write(
        "row,line,predicted:wall perforated,measured:wall perforated,right:wall perforated\n"
        "1,4,P,P,1\n2,5,P,NP,0\n3,6,NP,NP,1\n")
    r = run_tool("post/whipple_scores.py", table, camp, "--markdown", check=0)
    # The equation's verdicts, from the function itself (rows 1 and 2: one shield at 6.5 km/s).
    import sys
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    from tools.common import christiansen

    def says(d, v, tw):
        d_c = christiansen.critical_diameter(v, 0.7874e-3, tw, 50.8e-3, rho_p=2800.0,
                                             rho_b=2700.0, sigma_pa=40 * christiansen.KSI)
        return "P" if d > d_c else "NP"
    right = [says(3.175e-3, 6500.0, 2.54e-3) == "P", says(1.0e-3, 6500.0, 2.54e-3) == "NP",
             says(3.175e-3, 3000.0, 4.064e-3) == "NP"]
    assert says(1.0e-3, 6500.0, 2.54e-3) != says(8.0e-3, 6500.0, 2.54e-3)  # not one verdict
    lines = r.stdout.splitlines()
    q = right[0] + right[1]
    assert (f"| AA6061-T6 0.7874 mm | 50.8 mm | AA6061-T6 2.54 mm | 2 (1 / 1) | 1 (50 %) | "
            f"{q} ({100 * q / 2:.0f} %) |") in lines
    q = sum(right)
    assert lines[-1] == f"| all | | | 3 (1 / 2) | 2 (67 %) | {q} ({100 * q / 3:.0f} %) |"
    pngs = sorted(f for f in os.listdir(camp) if f.endswith(".png"))
    assert len(pngs) == 2
    for p in pngs:
        assert open(os.path.join(camp, p), "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    # --errors: the engine's one wrong call (row 2) is an NP shot called P.
    r = run_tool("post/whipple_scores.py", table, camp, "--markdown", "--errors", check=0)
    lines = r.stdout.splitlines()
    assert lines[0].endswith("| engine wrong: P called NP / NP called P |")
    assert lines[-1].endswith(f"({100 * q / 3:.0f} %) | 0 / 1 |")
    assert any(x.startswith("| AA6061-T6 0.7874 mm | 50.8 mm | AA6061-T6 4.064 mm |")
               and x.endswith("| 0 / 0 |") for x in lines)
    # --figures into a folder that is not there yet: made.
    figures = os.path.join(out, "figures", "new")
    run_tool("post/whipple_scores.py", table, camp, "--figures", figures, check=0)
    assert sorted(f for f in os.listdir(figures) if f.endswith(".png")) == pngs


def test_refusals(out):
    table = os.path.join(out, "shots.csv")
    open(table, "w").write(TABLE)
    r = run_tool("post/whipple_scores.py", table, out, check=2)
    assert "predictions.csv: no such file (not a campaign folder)" in r.stderr
    open(os.path.join(out, "predictions.csv"), "w").write(
        "row,line,predicted:wall perforated\n9,4,P\n")
    r = run_tool("post/whipple_scores.py", table, out, check=2)
    assert "row 9 is not a row of" in r.stderr
    r = run_tool("post/whipple_scores.py", os.path.join(out, "none.csv"), out, check=2)
    assert "none.csv: no such file" in r.stderr


def test_limits(out):
    """--limits: the engine's brackets read per configuration (diameters cm → mm), what each
    shows, drawn on that configuration's figure only; a file without a column, with a word for a
    number, or naming a configuration no campaign ran, is refused naming it, before any table."""
    table = os.path.join(out, "shots.csv")
    open(table, "w").write(TABLE)
    camp = os.path.join(out, "campaign")
    os.makedirs(camp)
    open(os.path.join(camp, "predictions.csv"), "w").write(
        "row,line,predicted:wall perforated\n1,4,NP\n2,5,NP\n3,6,NP\n")
    key = "AA6061-T6,0.07874,5.08,AA6061-T6,0.254"
    limits = os.path.join(out, "limits.csv")
    open(limits, "w").write(
        "bumper_mat,bumper_thick,standoff,wall_mat,wall_thick,velocity,lo,hi,status\n"
        f"{key},3,0.3,0.33,ok\n"
        f"{key},7,0.2,1.2,no bracket: the criterion is not met at both ends\n")
    import sys
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    from tools.post import whipple_scores as ws
    got = ws.read_limits(limits)
    assert list(got) == [("AA6061-T6", "0.07874", "5.08", "AA6061-T6", "0.254")]
    import pytest
    assert got[list(got)[0]] == [(3.0, 3.0, pytest.approx(3.3), "ok"),
                                 (7.0, 2.0, 12.0, "no bracket: the criterion is not met at both ends")]
    assert ws.limit_marks(got[list(got)[0]]) == [("bracket", 3.0, 3.0, pytest.approx(3.3)),
                                                ("above", 7.0, 12.0)]
    assert ws.limit_marks([(5.0, 1.0, 2.0, "no bracket: the criterion is met at both ends"),
                           (6.0, 1.0, 2.0, "reversed bracket"),
                           (7.0, 1.0, 2.0, "run at parameters.d=0.01: failed")]) == [
        ("below", 5.0, 1.0)]
    plain, drawn = os.path.join(out, "plain"), os.path.join(out, "drawn")
    run_tool("post/whipple_scores.py", table, camp, "--figures", plain, check=0)
    run_tool("post/whipple_scores.py", table, camp, "--figures", drawn, "--limits", limits, check=0)
    name = "whipple-AA6061-T6-0.07874-5.08-AA6061-T6-0.254.png"
    other = "whipple-AA6061-T6-0.07874-5.08-AA6061-T6-0.4064.png"
    read = lambda d, f: open(os.path.join(d, f), "rb").read()
    assert read(plain, name) != read(drawn, name)    # the limit drawn
    assert read(plain, other) == read(drawn, other)  # the other shield has none
    open(limits, "w").write(
        "bumper_mat,bumper_thick,standoff,wall_mat,wall_thick,velocity,lo,hi,status\n"
        "AA6061-T6,0.07874,5.08,AA6061-T6,0.3175,3,0.3,0.33,ok\n")
    r = run_tool("post/whipple_scores.py", table, camp, "--limits", limits, check=2)
    assert "none of the campaigns' shots" in r.stderr and r.stdout == ""
    open(limits, "w").write("bumper_mat,velocity,lo,hi,status\nAA6061-T6,3,0.3,0.33,ok\n")
    r = run_tool("post/whipple_scores.py", table, camp, "--limits", limits, check=2)
    assert "limits.csv: no column bumper_thick" in r.stderr
    open(limits, "w").write(
        "bumper_mat,bumper_thick,standoff,wall_mat,wall_thick,velocity,lo,hi,status\n"
        f"{key},fast,0.3,0.33,ok\n")
    r = run_tool("post/whipple_scores.py", table, camp, "--limits", limits, check=2)
    assert "limits.csv: line 2: velocity, lo and hi must be numbers" in r.stderr
