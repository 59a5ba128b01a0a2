#!/usr/bin/python3
"""Plots a `tetcontact limit` curve beside Christiansen's Whipple shield equations, to PNG.

    plot_limit.py LIMIT.csv [OUT.png] --shield TB TW S [--title TEXT]

LIMIT.csv: a search with `--find parameters.d` (the projectile diameter, m) and `--vary` over
the speed (m/s), e.g. `--vary parameters.v=3000,5000,7000`. Each bracket is drawn as a bar
from its lower end (not perforated) to its upper end (perforated); the line is
tools/common/christiansen.py's critical diameter for a bumper TB, a wall TW and a standoff S (m;
aluminium, 6061-T6's 40 ksi, normal incidence), with its ballistic, shatter and hypervelocity
regimes. Brackets not found are listed, not drawn. OUT.png defaults to LIMIT.csv with .png,
written through a temporary file. Needs Debian's python3-matplotlib (/usr/bin/python3). Exit
code 0, or 2 on bad input."""
import csv
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import figure_data  # noqa: E402
from tools.common import christiansen  # noqa: E402
from tools.common import summary_keys as K  # noqa: E402


def fail(msg):
    print("plot_limit.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    title = None
    if "--title" in argv:
        i = argv.index("--title")
        if i + 1 >= len(argv):
            fail("--title needs a text")
        title = argv[i + 1]
        del argv[i:i + 2]
    if "--shield" not in argv:
        fail("--shield TB TW S is required")
    i = argv.index("--shield")
    try:
        tb, tw, s = (float(x) for x in argv[i + 1:i + 4])
    except ValueError:
        fail("--shield needs three numbers (m)")
    del argv[i:i + 4]
    if len(argv) not in (1, 2):
        fail("usage: plot_limit.py LIMIT.csv [OUT.png] --shield TB TW S [--title TEXT]")
    path = argv[0]
    out = argv[1] if len(argv) > 1 else os.path.splitext(path)[0] + ".png"
    if not os.path.isfile(path):
        fail(path + ": no such file")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows or K.LIMIT_LO not in rows[0]:
        fail(path + ": not a limit.csv")
    speed_key = list(rows[0].keys())[0]
    if speed_key == K.LIMIT_KEY:
        fail(path + ": the search has no --vary (one bracket, no curve)")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    vs = [1000.0 + 50.0 * k for k in range(181)]
    ax.plot([v / 1e3 for v in vs], [christiansen.critical_diameter(v, tb, tw, s) * 1e3 for v in vs],
            "k-", label="Christiansen (1993), Whipple shield")
    missing = []
    for r in rows:
        v = float(r[speed_key])
        if r[K.LIMIT_STATUS] != "ok":
            missing.append(f"{v:g} m/s: {r[K.LIMIT_STATUS]}")
            continue
        lo, hi = float(r[K.LIMIT_LO]) * 1e3, float(r[K.LIMIT_HI]) * 1e3
        ax.plot([v / 1e3, v / 1e3], [lo, hi], "r-", lw=3)
        ax.plot([v / 1e3], [0.5 * (lo + hi)], "ro", ms=4)
    ax.plot([], [], "r-", lw=3, label="tetcontact limit: bracket")
    ax.set_xlabel("impact speed, km/s")
    ax.set_ylabel("critical projectile diameter, mm")
    ax.set_title(title or f"bumper {tb * 1e3:g} mm, wall {tw * 1e3:g} mm, standoff {s * 1e3:g} mm")
    ax.grid(True, alpha=0.3)
    ax.legend()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    os.replace(tmp, out)
    figure_data.save(fig, out)
    print("written: " + out)
    for m in missing:
        print("not found: " + m)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
