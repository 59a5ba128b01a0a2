#!/usr/bin/python3
"""Run one case with two tetcontact binaries and say whether the results are bit-identical.

    tools/dev/compare_runs.py OLD_BINARY NEW_BINARY CASE.yaml [--set KEY=VALUE ...]
                          [--new-set KEY=VALUE ...] [--work DIR]

Compares every frame_*.vtu and particles_*.vtu byte for byte, and history.csv without its
wall-clock columns (seconds_*). Exit 0 when identical, 1 when not (the first difference is
named), 2 when a run fails. For refactors that must not change results.
"""
import argparse
import csv
import filecmp
import io
import os
import shutil
import subprocess
import sys
import tempfile

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import summary_keys as K  # noqa: E402


def run(binary, case, sets, out):
    cmd = [binary, "run", case, "--quiet", "--force", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:  # exit 2, as the docstring says (sys.exit(text) would give 1)
        print(f"compare_runs.py: {binary}: exit {r.returncode}: {r.stderr.strip()}",
              file=sys.stderr)
        sys.exit(2)


def history_without_timings(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    keep = [i for i, name in enumerate(rows[0]) if not name.startswith(K.HISTORY_SECONDS_PREFIX)]
    out = io.StringIO()
    csv.writer(out).writerows([[r[i] for i in keep] for r in rows])
    return out.getvalue()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("case")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--new-set", action="append", default=[],
                    help="a key for the new binary only (output.format=ascii against a build "
                         "that wrote text frames)")
    ap.add_argument("--work", help="keep the two runs here (default: a temporary folder)")
    a = ap.parse_args()
    work = a.work or tempfile.mkdtemp(prefix="compare-runs-")
    dirs = [os.path.join(work, "old"), os.path.join(work, "new")]
    for binary, d, extra in zip([a.old, a.new], dirs, [[], a.new_set]):
        run(binary, a.case, a.set + extra, d)
    files = sorted(f for f in os.listdir(dirs[0]) if f.endswith(".vtu"))
    if files != sorted(f for f in os.listdir(dirs[1]) if f.endswith(".vtu")):
        print(f"{a.case}: DIFFERENT file lists")
        return 1
    for f in files:
        if not filecmp.cmp(os.path.join(dirs[0], f), os.path.join(dirs[1], f), shallow=False):
            print(f"{a.case}: DIFFERENT at {f}")
            return 1
    if history_without_timings(os.path.join(dirs[0], "history.csv")) != history_without_timings(
            os.path.join(dirs[1], "history.csv")):
        print(f"{a.case}: DIFFERENT history.csv")
        return 1
    print(f"{a.case}: identical ({len(files)} frames and history.csv)")
    if not a.work:
        shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
