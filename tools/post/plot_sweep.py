#!/usr/bin/python3
"""Plots a `tetcontact sweep` table: error against wall time, log–log, to PNG.

    plot_sweep.py SWEEP.csv [OUT.png] [--title TEXT]

One line per value of the other varied keys, through the values of the first varied key
(with one key, one line); each point labelled with its first key's value. A second panel shows
the energy balance error against wall time. OUT.png defaults to SWEEP.csv with .png; it is
written through a temporary file. Runs that failed or have no error are left out (and
counted). Needs Debian's python3-matplotlib (run with /usr/bin/python3). Exit code 0, or 2 on
bad input."""
import csv
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import figure_data  # noqa: E402
from tools.common import summary_keys as K  # noqa: E402


def fail(msg):
    print("plot_sweep.py: error: " + msg, file=sys.stderr)
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
        argv = argv[:i] + argv[i + 2:]
    if len(argv) not in (1, 2):
        fail("usage: plot_sweep.py SWEEP.csv [OUT.png] [--title TEXT]")
    path = argv[0]
    out = argv[1] if len(argv) == 2 else os.path.splitext(path)[0] + ".png"
    if not os.path.isfile(path):
        fail(path + ": no such file")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
        header = f.seek(0) or next(csv.reader(f))
    if K.SWEEP_STATUS not in header or K.SWEEP_ERROR not in header:
        fail(path + ": not a sweep.csv (no status or error column)")
    keys = header[:header.index(K.SWEEP_STATUS)]
    good = [r for r in rows if r[K.SWEEP_STATUS] == "ok" and r[K.SWEEP_ERROR] not in ("", "nan")]
    if not good:
        fail(path + ": no finished run with an error to plot")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    groups = {}
    for r in good:
        groups.setdefault(tuple(r[k] for k in keys[1:]), []).append(r)
    for other, runs in groups.items():
        runs.sort(key=lambda r: float(r[K.SWEEP_WALL_SECONDS]))
        label = ", ".join("%s=%s" % (k.split(".")[-1], v) for k, v in zip(keys[1:], other)) or keys[0]
        t = [float(r[K.SWEEP_WALL_SECONDS]) for r in runs]
        e = [max(abs(float(r[K.SWEEP_ERROR])), 1e-16) for r in runs]
        b = [max(float(r[K.SWEEP_ENERGY_BALANCE_MAX]), 1e-16) for r in runs]
        ax.loglog(t, e, "o-", label=label)
        ax2.loglog(t, b, "o-", label=label)
        for x, y, r in zip(t, e, runs):
            ax.annotate(r[keys[0]], (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
    ax.set_xlabel("wall time, s")
    ax.set_ylabel("error (relative)")
    ax.set_title(title or "error against run time (points: %s)" % keys[0].split(".")[-1], fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax2.set_xlabel("wall time, s")
    ax2.set_ylabel("energy balance error (max over the run)")
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=90)
    os.replace(tmp, out)
    figure_data.save(fig, out)
    print("%s: %d runs plotted, %d left out (failed or no error)" % (out, len(good), len(rows) - len(good)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
