#!/usr/bin/python3
"""Plots a `tetcontact campaign` folder to PNG: each prediction against its measurement.

    plot_campaign.py DIR [OUT.png]

DIR holds the campaign's predictions.csv and statistics.json (`tetcontact campaign` calls this
tool itself). A comparison of numbers is a panel of computed against measured, a point per row
(coloured by the campaign's group when it has one), the line of equality and, when the
comparison has a tolerance, its band; a comparison of categories is a panel of its confusion
table (measured × predicted, rows counted), with the accuracy in the title. OUT.png defaults to
DIR/campaign.png, written through a temporary file. Needs Debian's python3-matplotlib
(/usr/bin/python3). Exit code 0, or 2 on bad input."""
import csv
import json
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import figure_data  # noqa: E402


def fail(msg):
    print("plot_campaign.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    if len(argv) not in (1, 2):
        fail("usage: plot_campaign.py DIR [OUT.png]")
    folder = argv[0]
    out = argv[1] if len(argv) > 1 else os.path.join(folder, "campaign.png")
    paths = [os.path.join(folder, f) for f in ("predictions.csv", "statistics.json")]
    for p in paths:
        if not os.path.isfile(p):
            fail(p + ": no such file (not a campaign folder)")
    with open(paths[0]) as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames or []
        rows = list(reader)
    with open(paths[1]) as f:
        stats = json.load(f)
    comparisons = stats.get("comparisons")
    if not comparisons:
        fail(paths[1] + ": no comparisons")
    # The group of a row: the columns between `line` and the first parameter or material.
    first_input = next((i for i, h in enumerate(header)
                        if h.startswith(("parameters.", "materials.", "predicted:"))), len(header))
    group_columns = header[2:first_input]

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(comparisons), figsize=(5.2 * len(comparisons), 4.8),
                             squeeze=False)
    for ax, comp in zip(axes[0], comparisons):
        name = comp["predicted"]
        p_key, m_key = "predicted:" + name, "measured:" + name
        if p_key not in header or m_key not in header:
            fail(paths[0] + ": no columns " + p_key + ", " + m_key)
        everything = comp["all"]
        if "confusion" in everything:
            table = everything["confusion"]
            cats = list(table.keys())
            grid = [[table[a][b] for b in cats] for a in cats]
            ax.imshow(grid, cmap="Blues")
            for i, a in enumerate(cats):
                for j, b in enumerate(cats):
                    ax.text(j, i, str(grid[i][j]), ha="center", va="center", fontsize=14)
            ax.set_xticks(range(len(cats)), cats)
            ax.set_yticks(range(len(cats)), cats)
            ax.set_xlabel("computed")
            ax.set_ylabel("measured")
            acc = everything.get("accuracy")
            ax.set_title(f"{name}: {everything['compared']} compared"
                         + (f", accuracy {100 * acc:.0f} %" if acc is not None else ""))
            continue
        groups = {}
        for r in rows:
            p, m = number(r[p_key]), number(r[m_key])
            if p is None or m is None:
                continue
            g = " | ".join(r[c] for c in group_columns) or "all"
            groups.setdefault(g, ([], []))
            groups[g][0].append(m)
            groups[g][1].append(p)
        values = [x for ms, ps in groups.values() for x in ms + ps]
        if values:
            lo, hi = min(values), max(values)
            pad = 0.05 * (hi - lo or abs(hi) or 1.0)
            line = [lo - pad, hi + pad]
            ax.plot(line, line, "k-", lw=1, label="computed = measured")
            tol = everything.get("tolerance")
            if tol:
                ax.fill_between(line, [x * (1 - tol) for x in line], [x * (1 + tol) for x in line],
                                color="0.85", label=f"±{100 * tol:g} %")
        for g, (ms, ps) in sorted(groups.items()):
            ax.plot(ms, ps, "o", ms=4, label=g)
        ax.set_xlabel("measured " + comp["measured"])
        ax.set_ylabel("computed " + name)
        med = everything.get("median_abs_error")
        ax.set_title(f"{name}: {everything['compared']} compared"
                     + (f", median |error| {100 * med:.1f} %" if med is not None else ""))
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
