#!/usr/bin/python3
"""Plots a campaign of Taylor tests to PNG: final length over initial length against the impact
speed, measured and computed, a panel per material.

    plot_taylor.py DIR... [--out OUT.png] [--label TEXT]...

Each DIR is a `tetcontact campaign data/cases/taylor.yaml TABLE.csv` folder (its
predictions.csv: the columns `material`, `parameters.L0`, `parameters.v`, `parameters.T0`,
`predicted:final length`, `measured:final length`); a second DIR (another strength law, say)
adds its computed points beside the first's, named by its --label (default the folder's name).
Measured points are open circles, computed ones filled, a thin line joins each test's pair;
tests above 400 K are marked in red. OUT.png defaults to the first DIR's taylor.png, written
through a temporary file. Needs Debian's python3-matplotlib. Exit code 0, or 2 on bad input."""
import csv
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import figure_data  # noqa: E402

COLUMNS = ["material", "parameters.L0", "parameters.v", "parameters.T0",
           "predicted:final length", "measured:final length"]
MARKERS = ["o", "s", "^", "D"]


def fail(msg):
    print("plot_taylor.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def read(folder):
    path = os.path.join(folder, "predictions.csv")
    if not os.path.isfile(path):
        fail(path + ": no such file (not a campaign folder)")
    with open(path) as f:
        reader = csv.DictReader(f)
        missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            fail(path + ": no column " + ", ".join(missing) + " (not a campaign of taylor.yaml)")
        return list(reader)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    out, labels, folders = None, [], []
    i = 0
    while i < len(argv):
        if argv[i] in ("--out", "--label"):
            if i + 1 >= len(argv):
                fail(argv[i] + " needs a value")
            if argv[i] == "--out":
                out = argv[i + 1]
            else:
                labels.append(argv[i + 1])
            i += 2
        else:
            folders.append(argv[i])
            i += 1
    if not folders:
        fail("name a campaign folder")
    runs = [read(f) for f in folders]
    labels += [os.path.basename(os.path.normpath(f)) for f in folders[len(labels):]]
    out = out or os.path.join(folders[0], "taylor.png")
    materials = sorted({r["material"] for r in runs[0]})

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(materials), figsize=(5 * len(materials), 4.4), squeeze=False)
    for ax, material in zip(axes[0], materials):
        for k, (rows, label) in enumerate(zip(runs, labels)):
            for r in rows:
                if r["material"] != material:
                    continue
                v, L0 = float(r["parameters.v"]), float(r["parameters.L0"])
                hot = float(r["parameters.T0"]) > 400.0
                colour = "tab:red" if hot else "tab:blue"
                m = float(r["measured:final length"]) / L0 if r["measured:final length"] else None
                p = float(r["predicted:final length"]) / L0 if r["predicted:final length"] else None
                if k == 0 and m is not None:
                    ax.plot([v], [m], "o", mfc="none", mec=colour, ms=6)
                if p is not None:
                    ax.plot([v], [p], MARKERS[k % len(MARKERS)], color=colour, ms=4 if k else 5,
                            alpha=1.0 if k == 0 else 0.6)
                    if m is not None and k == 0:
                        ax.plot([v, v], [m, p], "-", color=colour, lw=0.6)
        ax.plot([], [], "o", mfc="none", mec="tab:blue", label="measured")
        for k, label in enumerate(labels):
            ax.plot([], [], MARKERS[k % len(MARKERS)], color="tab:blue", label="computed: " + label)
        ax.plot([], [], "o", color="tab:red", label="above 400 K (its pair red)")
        ax.set_title(material)
        ax.set_xlabel("impact speed, m/s")
        ax.set_ylabel("Lf / L0")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=100, bbox_inches="tight")
    os.replace(tmp, out)
    figure_data.save(fig, out)
    print("written: " + out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
