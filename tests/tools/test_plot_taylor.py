"""tools/post/plot_taylor.py on campaign folders of data/cases/taylor.yaml (the columns of
src/app/campaign.cpp's predictions.csv): two laws drawn side by side to a PNG, a panel per
material; a folder that is not such a campaign refused (exit 2)."""
import os

from conftest import figure, run_tool

HEADER = ("row,line,material,parameters.D0,parameters.L0,parameters.v,parameters.T0,"
          "parameters.rho,materials.rod,predicted:final length,measured:final length,"
          "error:final length,status,wall_seconds,folder\n")
ROWS = ("1,15,Al 6061-T6,0.0076,0.0114,227,294,2700,al6061-t6,0.00985,0.0102,-0.034,ok,1,a\n"
        "2,16,Cu OFHC,0.0076,0.0254,190,718,8930,ofhc-copper,0.018,0.0171,0.05,ok,1,b\n"
        "3,17,Cu OFHC,0.0076,0.0254,150,294,8930,ofhc-copper,0.020,,,ok,1,c\n")


def test_two_laws(out):
    folders = []
    for name in ("default", "johnson_cook"):
        f = os.path.join(out, name)
        os.makedirs(f)
        open(os.path.join(f, "predictions.csv"), "w").write(HEADER + ROWS)
        folders.append(f)
    png = os.path.join(out, "lf.png")
    r = run_tool("post/plot_taylor.py", *folders, "--label", "SG", "--label", "JC", "--out", png,
                 check=0)
    assert r.stdout.strip() == "written: " + png
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    # What is drawn, a panel per material: Lf / L0 measured and computed at each speed.
    panels = {a["title"]: a for a in figure(png)["axes"]}
    assert sorted(panels) == ["Al 6061-T6", "Cu OFHC"]

    def points(panel):
        return sorted((x["x"][0], round(x["y"][0], 12)) for x in panels[panel]["lines"]
                      if len(x["x"]) == 1)
    al = points("Al 6061-T6")  # measured once, computed by each law
    assert al == sorted([(227.0, round(0.0102 / 0.0114, 12))]
                        + 2 * [(227.0, round(0.00985 / 0.0114, 12))])
    cu = points("Cu OFHC")  # row 3: computed only
    assert cu == sorted([(190.0, round(0.0171 / 0.0254, 12))]
                        + 2 * [(190.0, round(0.018 / 0.0254, 12))]
                        + 2 * [(150.0, round(0.020 / 0.0254, 12))])


def test_refusals(out):
    r = run_tool("post/plot_taylor.py", out, check=2)
    assert "no such file (not a campaign folder)" in r.stderr
    open(os.path.join(out, "predictions.csv"), "w").write("row,line\n1,2\n")
    r = run_tool("post/plot_taylor.py", out, check=2)
    assert "not a campaign of taylor.yaml" in r.stderr
    r = run_tool("post/plot_taylor.py", out, "--out", check=2)
    assert "--out needs a value" in r.stderr
