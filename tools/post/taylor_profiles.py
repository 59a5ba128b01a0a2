#!/usr/bin/python3
"""The computed outlines of Taylor rods beside the digitised ones: radius against height of
each rod of data/validation/taylor-profiles/ at the end of its run, measured and computed.

    taylor_profiles.py DIR... [--out OUT.png] [--label TEXT]... [--index CSV] [--table TABLE.csv]

Each DIR is a `tetcontact campaign data/cases/taylor.yaml TABLE.csv` folder whose rows include
the profiled tests (its predictions.csv and runs/, each run's first and last ParaView frame);
a second DIR (another strength law) adds its outline beside the first's. The index (default
data/validation/taylor-profiles.csv) names the test of each outline by its line in the table
(default data/validation/taylor-tests.csv); every outline is checked against its test first:
the outline's top within 3 % of the measured final length, its undeformed tail within 3 % of
D0 / 2 (exit 2 naming the file otherwise).

The computed outline is the rod's original lateral surface where the run ends: the nodes that
start on the cylinder (r = R0), grouped by their starting height, each group's mean radius
and height (a quarter rod's nodes over its 90°), its heights from the rod's lowest node (a
rod rebounds once it has stopped). A digitised outline is drawn as it is, from the axis at
z = 0 (the foot's rim may stand above the anvil). Against the digitised points below the top
it reports the mean and largest |Δr| / R0 (the computed radius interpolated at each measured
height) and the footprint (the radius at the anvil) measured and computed, a line per
outline; OUT.png (default the first DIR's taylor-profiles.png, written through a temporary
file) draws a panel per outline. Needs Debian's python3-vtk9 and python3-matplotlib. Exit code
0, or 2 on bad input."""
import csv
import math
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VALIDATION = os.path.join(ROOT, "data", "validation")
TOLERANCE = 0.03  # an outline's top and tail against its test's Lf and D0 / 2


def fail(msg):
    print("taylor_profiles.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def read_csv(path):
    """The rows of a CSV whose leading `#` lines are comments, as dicts, with each row's line."""
    if not os.path.isfile(path):
        fail(path + ": no such file")
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    body = [(k + 1, s) for k, s in enumerate(lines) if s.strip() and not s.startswith("#")]
    if not body:
        fail(path + ": no header")
    header = next(csv.reader([body[0][1]]))
    rows = []
    for line, text in body[1:]:
        values = next(csv.reader([text]))
        if len(values) != len(header):
            fail(f"{path}:{line}: {len(values)} values under {len(header)} columns")
        row = {h.strip(): v.strip() for h, v in zip(header, values)}
        row["#line"] = line
        rows.append(row)
    return rows


def read_outline(path):
    """The digitised polygon (radius, height) in mm: its points off the axis, as given."""
    points = []
    with open(path) as f:
        for k, text in enumerate(f, 1):
            if not text.strip():
                continue
            try:
                r, z = (float(x) for x in text.split())
            except ValueError:
                fail(f"{path}:{k}: not 'radius_mm z_mm'")
            if r > 0.0:
                points.append((r, z))
    if len(points) < 2:
        fail(path + ": fewer than two points off the axis")
    return points


def checked_profiles(index_path, table_path, profiles_dir):
    """[(file, test row, outline)] of the index, each outline checked against its test."""
    tests = {row["#line"]: row for row in read_csv(table_path)}
    out = []
    for entry in read_csv(index_path):
        name, line = entry.get("file"), entry.get("line")
        if not name or not line or not line.isdigit():
            fail(f"{index_path}:{entry['#line']}: needs a file and a line number")
        test = tests.get(int(line))
        if test is None:
            fail(f"{index_path}:{entry['#line']}: {table_path} has no test on line {line}")
        outline = read_outline(os.path.join(profiles_dir, name))
        top = max(z for _, z in outline)
        tail = max(outline, key=lambda p: p[1])[0]
        lf, d0 = float(test["Lf_mm"]), float(test["D0_mm"])
        if abs(top - lf) > TOLERANCE * lf:
            fail(f"{name}: its top {top:.2f} mm is not the final length {lf} mm of line {line}")
        if abs(tail - d0 / 2) > TOLERANCE * d0 / 2:
            fail(f"{name}: its tail radius {tail:.2f} mm is not D0 / 2 = {d0 / 2} mm of line {line}")
        out.append((name, test, outline))
    return out


def frame_files(run):
    """The first and the last frame of a run folder (check_vtu's reading of its case.pvd)."""
    from tools.post import check_vtu
    try:
        files = [f for _, f in check_vtu.frame_list(run, "case.pvd")]
    except check_vtu.BadFolder as e:
        fail(str(e))
    if len(files) < 2:
        fail(os.path.join(run, "case.pvd") + ": fewer than two frames")
    return os.path.join(run, files[0]), os.path.join(run, files[-1])


def points(vtu):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        fail(vtu + ": no points")
    return vtk_to_numpy(grid.GetPoints().GetData())


def computed_outline(run):
    """(outline [(r, z)] in mm from the anvil up, footprint radius in mm) at a run's end."""
    first, last = frame_files(run)
    x0, x1 = points(first), points(last)
    if x0.shape != x1.shape:
        fail(f"{run}: its first and last frames hold different nodes")
    r0 = [math.hypot(p[0], p[1]) for p in x0]
    radius = max(r0)
    groups = {}
    for k, p in enumerate(x0):
        if r0[k] >= radius * (1 - 1e-6):
            groups.setdefault(round(p[2] / radius, 6), []).append(k)
    outline = []
    for z0 in sorted(groups):
        ks = groups[z0]
        outline.append((1e3 * sum(math.hypot(x1[k][0], x1[k][1]) for k in ks) / len(ks),
                        1e3 * sum(x1[k][2] for k in ks) / len(ks)))
    zmin = min(p[2] for p in x0)
    face = [k for k, p in enumerate(x0) if abs(p[2] - zmin) <= 1e-9 * radius]
    foot = 1e3 * max(math.hypot(x1[k][0], x1[k][1]) for k in face)
    anvil = 1e3 * min(p[2] for p in x1)  # a rod rebounds once it has stopped
    return [(r, z - anvil) for r, z in outline], foot


def interpolate(outline, z):
    """The outline's radius at height z: linear between its points, sorted by height."""
    pts = sorted(outline, key=lambda p: p[1])
    if z <= pts[0][1]:
        return pts[0][0]
    for (ra, za), (rb, zb) in zip(pts, pts[1:]):
        if za <= z <= zb:
            return ra if zb == za else ra + (rb - ra) * (z - za) / (zb - za)
    return pts[-1][0]


def compare(measured, computed, r0):
    """(mean, largest) |Δr| / R0 over the measured points below the measured top."""
    top = max(z for _, z in measured)
    d = [abs(interpolate(computed, z) - r) / r0 for r, z in measured if z < top]
    return sum(d) / len(d), max(d)


def runs_by_line(folder):
    path = os.path.join(folder, "predictions.csv")
    if not os.path.isfile(path):
        fail(path + ": no such file (not a campaign folder)")
    with open(path, newline="") as f:
        return {int(r["line"]): os.path.join(folder, "runs", r["folder"])
                for r in csv.DictReader(f) if r.get("folder")}


def rows(profiles, folders):
    """Per outline and campaign folder: (file, test, outline, [(computed, foot, mean, largest)])."""
    maps = [runs_by_line(f) for f in folders]
    out = []
    for name, test, outline in profiles:
        results = []
        for folder, runs in zip(folders, maps):
            run = runs.get(test["#line"])
            if run is None:
                fail(f"{folder}: no run of line {test['#line']} (the test of {name})")
            computed, foot = computed_outline(run)
            mean, largest = compare(outline, computed, float(test["D0_mm"]) / 2)
            results.append((computed, foot, mean, largest))
        out.append((name, test, outline, results))
    return out


def title(test):
    return (f"{test['material']}, {test['source'].split(' (')[0].split(' and ')[0]}\n"
            f"{test['U0_m_s']} m/s, {test['T0_K']} K")


def plot(table, labels, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(table)
    cols = 7 if n > 7 else n
    nrows = -(-n // cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(2.6 * cols, 4.2 * nrows), squeeze=False)
    colours = ["tab:blue", "tab:orange", "tab:green"]
    for ax in axes.flat[n:]:
        ax.axis("off")
    for ax, (name, test, outline, results) in zip(axes.flat, table):
        r = [0.0] + [p[0] for p in outline] + [0.0]
        z = [outline[0][1]] + [p[1] for p in outline] + [outline[-1][1]]
        ax.plot(r, z, "k-", lw=1.6, label="measured")
        for k, (computed, _, mean, _) in enumerate(results):
            ax.plot([p[0] for p in computed], [p[1] for p in computed], "-", lw=1.2,
                    color=colours[k % len(colours)], label=f"{labels[k]} ({100 * mean:.0f} %)")
        ax.set_title(title(test), fontsize=7)
        ax.set_aspect("equal")
        ax.set_xlim(0, None)
        ax.set_ylim(0, None)
        ax.tick_params(labelsize=6)
        ax.legend(fontsize=5, loc="upper right")
    fig.supxlabel("radius (mm)  ·  in the legend: mean |Δr| / R0", fontsize=8)
    fig.supylabel("height above the anvil (mm)", fontsize=8)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=130)
    os.replace(tmp, out)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    opts = {"--out": None, "--index": os.path.join(VALIDATION, "taylor-profiles.csv"),
            "--table": os.path.join(VALIDATION, "taylor-tests.csv")}
    labels, folders = [], []
    i = 0
    while i < len(argv):
        if argv[i] in ("--out", "--label", "--index", "--table"):
            if i + 1 >= len(argv):
                fail(argv[i] + " needs a value")
            if argv[i] == "--label":
                labels.append(argv[i + 1])
            else:
                opts[argv[i]] = argv[i + 1]
            i += 2
        elif argv[i].startswith("--"):
            fail("unknown option " + argv[i])
        else:
            folders.append(argv[i])
            i += 1
    if not folders:
        fail("name a campaign folder")
    labels += [os.path.basename(os.path.normpath(f)) for f in folders[len(labels):]]
    index = opts["--index"]
    profiles = checked_profiles(index, opts["--table"],
                                os.path.join(os.path.dirname(index), "taylor-profiles"))
    table = rows(profiles, folders)
    print("file,line,material,speed_m_s,T0_K,law,footprint_measured_mm,footprint_computed_mm,"
          "mean_abs_dr_over_R0,largest_abs_dr_over_R0")
    for name, test, outline, results in table:
        bottom = min(z for _, z in outline)
        foot = max(r for r, z in outline if z == bottom)
        for label, (_, computed_foot, mean, largest) in zip(labels, results):
            print(f"{name},{test['#line']},{test['material']},{test['U0_m_s']},{test['T0_K']},"
                  f"{label},{foot:.3f},{computed_foot:.3f},{mean:.4f},{largest:.4f}")
    plot(table, labels, opts["--out"] or os.path.join(folders[0], "taylor-profiles.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
