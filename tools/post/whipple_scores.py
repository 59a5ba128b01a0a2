#!/usr/bin/python3
"""Scores a campaign of Whipple-shield shots against the Christiansen equation on the same
shots, per shield configuration, and draws each configuration's shots in diameter–speed.

    whipple_scores.py TABLE.csv DIR... [--figures DIR] [--markdown] [--errors]
                      [--limits LIMITS.csv]

TABLE.csv: the table the campaigns ran (the shared database's format: cm, km/s, ksi under a
row of units); each DIR a `tetcontact campaign data/cases/whipple.yaml TABLE.csv` folder (its
predictions.csv: `row`, `predicted:wall perforated`, `measured:wall perforated`). For every row
a campaign ran, the equation's verdict is P when the projectile's diameter exceeds
tools/common/christiansen.py's critical diameter for that shot's bumper, wall (thickness and
yield `wall_yield`), standoff, densities, speed and obliquity. A configuration is the bumper's
alloy and thickness, the standoff and the wall's alloy and thickness. Prints, per
configuration and over all, the shots, P and NP measured, and the engine's and the equation's
right calls and accuracy (a markdown table with --markdown; with --errors a column more: the
engine's wrong calls on each side, a perforated shield called safe / a safe one called
perforated), and writes
whipple-<configuration>.png per configuration into --figures (default the first DIR; made
when missing): the
shots, P filled and NP open, the engine's wrong calls crossed, and the equation's curve at the
configuration's wall yield. With --limits, the engine's ballistic limit on the figures of the
configurations it names: LIMITS.csv has the configuration's columns (as TABLE.csv's), velocity
(km/s), lo and hi (the projectile's diameter, cm: the largest not perforating and the smallest
perforating, `tetcontact limit`'s bracket) and status (`limit`'s: ok, or why no bracket); a
bracket is drawn as a bar from lo to hi, a limit beyond the searched diameters as a triangle
at the end it lies beyond; a configuration that none of the DIRs' shots has is refused. Exit
code 0, or 2 on bad input."""
import csv
import os
import sys

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import christiansen  # noqa: E402

KEY = ["bumper_mat", "bumper_thick", "standoff", "wall_mat", "wall_thick"]
PRED, MEAS = "predicted:wall perforated", "measured:wall perforated"


def fail(msg):
    print("whipple_scores.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def read_table(path):
    if not os.path.isfile(path):
        fail(path + ": no such file")
    with open(path) as f:
        lines = [x for x in f if not x.startswith("#")]
    rows = list(csv.reader(lines))
    if len(rows) < 3:
        fail(path + ": no shots")
    header, data = rows[0], rows[2:]  # the second row is the units
    need = KEY + ["proj_diam", "proj_density", "velocity", "angle", "bumper_density",
                  "wall_yield", "result"]
    missing = [c for c in need if c not in header]
    if missing:
        fail(path + ": no column " + ", ".join(missing))
    return [dict(zip(header, r)) for r in data]


def equation_says(shot):
    """'P' when the diameter exceeds the critical one (SI through the equation's function)."""
    cm = 0.01
    d_c = christiansen.critical_diameter(
        float(shot["velocity"]) * 1000.0, float(shot["bumper_thick"]) * cm,
        float(shot["wall_thick"]) * cm, float(shot["standoff"]) * cm,
        rho_p=float(shot["proj_density"]) * 1000.0, rho_b=float(shot["bumper_density"]) * 1000.0,
        sigma_pa=float(shot["wall_yield"]) * christiansen.KSI, theta_deg=float(shot["angle"]))
    return "P" if float(shot["proj_diam"]) * cm > d_c else "NP"


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    figures, markdown, errors, args, limits_path = None, False, False, [], None
    i = 0
    while i < len(argv):
        if argv[i] == "--figures":
            if i + 1 >= len(argv):
                fail("--figures needs a folder")
            figures = argv[i + 1]
            i += 2
        elif argv[i] == "--limits":
            if i + 1 >= len(argv):
                fail("--limits needs a file")
            limits_path = argv[i + 1]
            i += 2
        elif argv[i] == "--markdown":
            markdown = True
            i += 1
        elif argv[i] == "--errors":
            errors = True
            i += 1
        else:
            args.append(argv[i])
            i += 1
    if len(args) < 2:
        fail("usage: whipple_scores.py TABLE.csv DIR... [--figures DIR] [--markdown] "
             "[--errors] [--limits LIMITS.csv]")
    table = read_table(args[0])
    limits = read_limits(limits_path) if limits_path else {}
    shots = {}  # row number → (shot, engine's verdict)
    for folder in args[1:]:
        path = os.path.join(folder, "predictions.csv")
        if not os.path.isfile(path):
            fail(path + ": no such file (not a campaign folder)")
        with open(path) as f:
            reader = csv.DictReader(f)
            if PRED not in (reader.fieldnames or []):
                fail(path + ": no column " + PRED + " (not a campaign of whipple.yaml)")
            for r in reader:
                n = int(r["row"])
                if not 1 <= n <= len(table):
                    fail(f"{path}: row {n} is not a row of {args[0]}")
                if r[PRED]:
                    shots[n] = (table[n - 1], r[PRED])
    groups = {}
    for n, (shot, engine) in sorted(shots.items()):
        groups.setdefault(tuple(shot[k] for k in KEY), []).append((n, shot, engine))
    for key in limits:
        if key not in groups:
            fail(f"{limits_path}: the configuration {', '.join(key)} is none of the campaigns' "
                 f"shots (--limits)")
    lines = []
    if markdown:
        head = "| bumper | standoff | wall | shots (P / NP) | engine right | equation right |"
        rule = "|---|---|---|---|---|---|"
        if errors:
            head += " engine wrong: P called NP / NP called P |"
            rule += "---|"
        lines += [head, rule]
    totals = [0, 0, 0, 0, 0, 0]
    for key, members in sorted(groups.items()):
        p = sum(1 for _, s, _ in members if s["result"] == "P")
        e = sum(1 for _, s, v in members if v == s["result"])
        q = sum(1 for _, s, _ in members if equation_says(s) == s["result"])
        n = len(members)
        unsafe = sum(1 for _, s, v in members if s["result"] == "P" and v != "P")
        safe = n - e - unsafe  # NP shots called P
        totals = [a + b for a, b in zip(totals, [n, p, e, q, unsafe, safe])]
        bumper = f"{key[0]} {float(key[1]) * 10:g} mm"
        wall = f"{key[3]} {float(key[4]) * 10:g} mm"
        side = f" {unsafe} / {safe} |" if errors else ""
        if markdown:
            lines.append(f"| {bumper} | {float(key[2]) * 10:g} mm | {wall} | {n} ({p} / {n - p}) | "
                         f"{e} ({100 * e / n:.0f} %) | {q} ({100 * q / n:.0f} %) |" + side)
        else:
            lines.append(f"{bumper}, standoff {float(key[2]) * 10:g} mm, {wall}: {n} shots "
                         f"({p} P, {n - p} NP): engine right on {e}, equation on {q}"
                         + (f"; engine wrong {unsafe} P called NP, {safe} NP called P"
                            if errors else ""))
    n, p, e, q, unsafe, safe = totals
    if n == 0:
        fail("no shot with a prediction")
    if markdown:
        lines.append(f"| all | | | {n} ({p} / {n - p}) | {e} ({100 * e / n:.0f} %) | "
                     f"{q} ({100 * q / n:.0f} %) |" + (f" {unsafe} / {safe} |" if errors else ""))
    else:
        lines.append(f"all: {n} shots ({p} P, {n - p} NP): engine right on {e} "
                     f"({100 * e / n:.0f} %), equation on {q} ({100 * q / n:.0f} %)"
                     + (f"; engine wrong {unsafe} P called NP, {safe} NP called P"
                        if errors else ""))
    print("\n".join(lines))
    figures = figures or args[1]
    if os.path.exists(figures) and not os.path.isdir(figures):
        fail(figures + ": not a folder (--figures)")
    os.makedirs(figures, exist_ok=True)
    draw(groups, figures, limits)
    return 0


def read_limits(path):
    """{configuration key: [(speed km/s, lo mm, hi mm, status)]} from a --limits file."""
    if not os.path.isfile(path):
        fail(path + ": no such file (--limits)")
    with open(path) as f:
        reader = csv.DictReader(f)
        need = KEY + ["velocity", "lo", "hi", "status"]
        missing = [c for c in need if c not in (reader.fieldnames or [])]
        if missing:
            fail(path + ": no column " + ", ".join(missing))
        out = {}
        for n, r in enumerate(reader, start=2):
            try:
                point = (float(r["velocity"]), float(r["lo"]) * 10.0, float(r["hi"]) * 10.0,
                         r["status"])
            except (TypeError, ValueError):
                fail(f"{path}: line {n}: velocity, lo and hi must be numbers")
            out.setdefault(tuple(r[k] for k in KEY), []).append(point)
    return out


def limit_marks(points):
    """What the figure shows of the engine's limit at each speed: ("bracket", v, lo, hi) for a
    bracket found, ("above", v, hi) when the search's ends were both NP, ("below", v, lo) when
    both were P; a reversed bracket or a failed search shows nothing."""
    marks = []
    for v, lo, hi, status in sorted(points):
        if status == "ok":
            marks.append(("bracket", v, lo, hi))
        elif "not met at both ends" in status:
            marks.append(("above", v, hi))
        elif "met at both ends" in status:
            marks.append(("below", v, lo))
    return marks


def draw(groups, folder, limits):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for key, members in sorted(groups.items()):
        fig, ax = plt.subplots(figsize=(6, 4.2))
        shot = members[0][1]
        vs = [1.0 + 0.05 * k for k in range(181)]
        cm = 0.01
        ax.plot(vs, [1e3 * christiansen.critical_diameter(
            v * 1000.0, float(key[1]) * cm, float(key[4]) * cm, float(key[2]) * cm,
            rho_p=float(shot["proj_density"]) * 1000.0,
            rho_b=float(shot["bumper_density"]) * 1000.0,
            sigma_pa=float(shot["wall_yield"]) * christiansen.KSI) for v in vs],
            "k-", lw=1, label="Christiansen's critical diameter")
        for _, s, engine in members:
            v, d = float(s["velocity"]), float(s["proj_diam"]) * 10.0
            perforated = s["result"] == "P"
            ax.plot([v], [d], "o", color="tab:red" if perforated else "tab:blue",
                    mfc=None if perforated else "none", ms=7)
            if engine != s["result"]:
                ax.plot([v], [d], "kx", ms=9)
        marks = limit_marks(limits.get(key, []))
        for mark in marks:
            if mark[0] == "bracket":
                ax.plot([mark[1]] * 2, mark[2:], "-", color="tab:green", lw=3,
                        solid_capstyle="butt")
            else:  # the limit lies above (below) the searched diameters: a triangle at the end
                ax.plot([mark[1]], [mark[2]], "^" if mark[0] == "above" else "v",
                        color="tab:green", ms=9)
        if marks:
            ax.plot([], [], "-", color="tab:green", lw=3,
                    label="the engine's limit (▲ above the search's largest diameter, "
                          "▼ below its smallest)")
        ax.plot([], [], "o", color="tab:red", label="perforated (P)")
        ax.plot([], [], "o", mfc="none", color="tab:blue", label="not perforated (NP)")
        ax.plot([], [], "kx", label="the engine calls it wrong")
        ax.set_xlabel("impact speed, km/s")
        ax.set_ylabel("projectile diameter, mm")
        ax.set_title(f"{key[0]} {float(key[1]) * 10:g} mm bumper, {float(key[2]) * 10:g} mm, "
                     f"{key[3]} {float(key[4]) * 10:g} mm wall", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
        name = "whipple-" + "-".join(k.replace("%", "") for k in key) + ".png"
        out = os.path.join(folder, name)
        fig.savefig(out + ".tmp.png", dpi=100, bbox_inches="tight")
        os.replace(out + ".tmp.png", out)
        plt.close(fig)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
