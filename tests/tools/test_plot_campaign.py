"""tools/post/plot_campaign.py on a campaign folder in the program's format
(src/app/campaign.cpp): a comparison of numbers and one of categories drawn to a PNG; a folder
that is not a campaign's refused (exit 2). `Campaign.*` in tests/app/test_campaign.cpp runs it
through the program itself on real runs."""
import json
import os

from conftest import figure, run_tool

PREDICTIONS = """row,line,metal,parameters.L,predicted:box length,measured:box length,error:box length,predicted:perforated,measured:perforated,right:perforated,status,wall_seconds,folder
1,3,Al,0.001,0.001,0.001,0,P,P,1,ok,0.1,row-1_0123456789ab
2,4,Cu,0.002,0.002,0.0025,-0.2,NP,P,0,ok,0.1,row-2_0123456789ab
3,5,Al,0.0015,0.0015,,,P,,,ok,0.1,row-3_0123456789ab
"""

STATISTICS = {
    "rows": 3, "failed": 0,
    "comparisons": [
        {"predicted": "box length", "measured": "Lf_mm",
         "all": {"compared": 2, "median_abs_error": 0.1, "p90_abs_error": 0.2,
                 "max_abs_error": 0.2, "mean_error": -0.1, "tolerance": 0.05,
                 "within_tolerance": 0.5}},
        {"predicted": "perforated", "measured": "result",
         "all": {"compared": 2, "accuracy": 0.5,
                 "confusion": {"P": {"P": 1, "NP": 1}, "NP": {"P": 0, "NP": 0}}}},
    ],
}


def test_numbers_and_categories(out):
    with open(os.path.join(out, "predictions.csv"), "w") as f:
        f.write(PREDICTIONS)
    with open(os.path.join(out, "statistics.json"), "w") as f:
        json.dump(STATISTICS, f)
    r = run_tool("post/plot_campaign.py", out, check=0)
    png = os.path.join(out, "campaign.png")
    assert r.stdout.splitlines()[0] == "written: " + png
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert not os.path.exists(png + ".tmp.png")
    # What is drawn: the numbers measured against computed, a set of points per group (row 3
    # has no measurement: not drawn), and the confusion table with its counts.
    numbers, categories = figure(png)["axes"][:2]
    points = {x["label"]: (x["x"], x["y"]) for x in numbers["lines"] if x["label"] in ("Al", "Cu")}
    assert points == {"Al": ([0.001], [0.001]), "Cu": ([0.0025], [0.002])}
    assert categories["images"] == [[[1.0, 1.0], [0.0, 0.0]]]
    assert sorted(t["text"] for t in categories["texts"]) == ["0", "0", "1", "1"]


def test_refusals(out):
    r = run_tool("post/plot_campaign.py", out, check=2)
    assert "predictions.csv: no such file (not a campaign folder)" in r.stderr
    with open(os.path.join(out, "predictions.csv"), "w") as f:
        f.write("row,line\n1,2\n")
    with open(os.path.join(out, "statistics.json"), "w") as f:
        json.dump(STATISTICS, f)
    r = run_tool("post/plot_campaign.py", out, check=2)
    assert "no columns predicted:box length" in r.stderr
    r = run_tool("post/plot_campaign.py", check=2)
