#!/usr/bin/python3
"""The tables of README.md and docs/, regenerated from the program's own runs (numbers from
runs, never retyped).

    tools/docs/tables.py NAME BINARY [--work DIR] [--write] [--docs-root DIR] [--cases NAME...]
    tools/docs/tables.py all BINARY [--work DIR] [--write] [--docs-root DIR]

NAME, the table:
    stability     the stability suite: each case of data/cases/stability/ as shipped (--check)
                  and with contact off
    micro         the micro-scenes (`stress --json`): contact on, verified, off
    profile       the broadphase profile (bars-impact, 300 steps, every method)
    ccd           the exact CCD's answers and mean time a query on the shared degenerate set
                  (FCL's beside them) and on the queries of real steps (the paper's cylinders,
                  edge–edge and the verification on, every query of their first 40 steps)
    verify        the step verification on small cases, each row with --check
    verify-full   the shipped contact cases at full size with the verification, every step
                  (long: ~30 min on 2 cores)
    threads       thread scaling: bars, cylinders (edge–edge on), Hertz and ball-plate in full on
                  1 and 2 threads (--cases: only the cases whose file names contain one of these)
    mpi           distributed runs: each case as one process (1 and 2 threads) and under mpirun
                  on 2 ranks of 1 thread; weak scaling of the Taylor rod
    whipple       the Whipple shield's coarse runs (the test's) beside Christiansen's critical
                  diameter
    whipple-mesh  the shipped Whipple shield on two meshes, and its default cells as the whole
                  shield with uniform plates, on 2 threads: measures, run times
    whipple-hole  the bumper's hole at 8 µs on those and a fourth (3 cells through the
                  bumper), 2 threads
    strength      the strength laws side by side: the aluminium Taylor rod and the 6061-T6 plate
                  impact's precursor (HEL) under each law, one thread
    taylor-tests  every Taylor test of data/validation/taylor-tests.csv under each metal's
                  default law and Johnson–Cook (`tetcontact campaign
                  data/cases/taylor.yaml`, a campaign per law, the cores at once): per material
                  and law the errors of the final length and the footprint; the figure
                  data/figures/taylor-lf.png (Lf/L0 against speed); the computed outlines of
                  the digitised rods, each law's footprint and mean |Δr| / R0, and their
                  figure data/figures/taylor-profiles.png (~80 min on 2 cores)
    taylor-temper the cold work of House et al.'s copper (library entry ofhc-copper-house):
                  found by bisection on every other one of their rods under the default law,
                  checked against the library's value, then the entry on the fitting and the
                  held-out rods under each law, beside plain ofhc-copper (~10 min on 2 cores)
    whipple-shots the normal-incidence shots of three shields of data/validation/whipple-shots.csv
                  whose shots straddle the limit (`campaign data/cases/whipple.yaml`, the
                  cores at once), the engine's verdicts and Christiansen's against the
                  measured ones per configuration, and the engine's ballistic limit
                  (`tetcontact limit`) of each shield at 3, 5 and 7 km/s;
                  data/figures/whipple-*.png (~60 min on 2 cores)
    whipple-shots-sph the same shots with SPH debris, crushed cells converted at half the
                  first step: per configuration the engine's and the equation's right calls,
                  and the engine's wrong calls on each side (no limit search; ~90 min on 2
                  cores)
    whipple-refined   sixteen of those shots (the 6061-T6 shield's) on the shipped mesh and with
                  the rear wall's cells three times finer: each verdict and the wall's thickness
                  left (~35 min on 2 cores)
    whipple-refined-sph ten of them (5.5–6.9 km/s) with SPH debris, crushed cells converted at
                  half the first step (as whipple-shots-sph; ~90 min on 2 cores, the shipped
                  mesh's runs reused from a whipple-shots-sph campaign of the same build)
    whipple-defaults  the same sixteen shots at the shipped mesh with each setting a
                  hypervelocity user chooses changed alone (average nodal pressure off, erosion
                  at 20 % and 5 % of the first step, the sphere 12 cells across, ductile
                  failure in the wall only, fragments as clusters, no ductile damage at the
                  failure strain's floor, the wall's ductile failure with clusters): verdicts
                  right, verdicts changed, the wall's thickness left, the parts' ductile
                  failures (at the floor / all), the cost (~60 min on 2 cores)
    whipple-wall  eight of those shots on rear walls of 2, 6 and 12 cells through, the wall's
                  ductile damage at the failure strain's floor off: whether the verdict
                  converges as the wall is refined (~70 min on 2 cores)
    whipple-tear  the sixteen shots with the run going on 15 µs (shipped) and 60 µs after the
                  debris reaches the wall, the latter also without ductile damage at the floor:
                  verdicts, thickness left, the wall's bulge at the end (~16 min on 2 cores)
    whipple-debris the sixteen shots with the debris as point masses (shipped), as SPH
                  particles (fracture.debris: sph), and as SPH particles with crushed cells
                  converted at 50 % of the first step: verdicts, thickness left, the contact
                  work's share of the initial energy (~45 min on 2 cores)
    whipple-sph-faces the sixteen shots with SPH debris meeting the bodies' faces through
                  its kernel (fracture.sph.faces: kernel, the default; the whipple-debris
                  table's SPH column met them by contact), and the same with crushed cells
                  converted at 50 % of the first step: verdicts, thickness left, the contact
                  work's share of the initial energy (~50 min on 2 cores)
    whipple-erosion-reference the sixteen shots with SPH debris, crushed cells converted at
                  half the model's first step and at half each body's own
                  (fracture.erosion_reference): verdicts, thickness left, steps (~40 min on 2
                  cores)
    whipple-sph-step the sixteen shots with SPH debris, crushed cells converted at half the
                  first step, the particles' stable step at the shipped factor and at twice it
                  (fracture.sph.step_factor 0.6 and 1.2): verdicts, thickness left, steps and
                  the largest balance error (~35 min on 2 cores)
    whipple-tillotson the seven of those shots at 6 km/s and above with SPH debris, every body
                  with the library's Mie–Grüneisen EOS (shipped) and with Tillotson's:
                  verdicts, thickness left, the debris cloud's speed, steps and the largest
                  balance error (~25 min on 2 cores)
    hugoniot      the library's aluminium equations of state on their Hugoniot against the
                  measured shock states of data/validation/aluminium-hugoniot.csv, per
                  pressure band (no runs: the EOS's closed form, which the engine reproduces)
    all           every table above, in that order (hours on 2 cores)

Without --write each table is printed, row by row as it is measured. With --write it also
replaces the block between the lines

    <!-- BEGIN generated: NAME -->
    <!-- END generated: NAME -->

in README.md or docs/**/*.md (under --docs-root, default the repository) with one line naming
the machine and the build that measured it (CPU model and core count from /proc/cpuinfo; the
program's --version; compiler and build type from the build folder's CMake files; the git
commit) and the table. The markers are looked up before any run: a table whose BEGIN or END
marker is missing, or appears twice (in one file or in two), is refused with exit code 2, the
file named. Runs go to --work (default a temporary folder). Exit code 0, 1 when a run fails, 2
on bad input."""
import argparse
import csv
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from tools.common import christiansen  # noqa: E402
from tools.common import summary_keys as K  # noqa: E402
from tools.common.summary_keys import get  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NAMES = ["stability", "micro", "profile", "ccd", "verify", "verify-full", "threads", "mpi",
         "whipple", "whipple-mesh", "whipple-hole", "strength", "taylor-tests", "taylor-temper",
         "whipple-shots", "whipple-shots-sph", "whipple-refined", "whipple-refined-sph",
         "whipple-defaults", "whipple-wall", "whipple-tear", "whipple-debris", "whipple-sph-faces",
         "whipple-erosion-reference", "whipple-sph-step", "whipple-tillotson", "hugoniot"]


def g(x):
    """A measured number, short: two significant digits, or a compact exponent."""
    if x is None:
        return "–"
    if x == 0 or 0.01 <= abs(x) < 1000:
        return f"{x:.2g}"
    return f"{x:.1e}".replace("e-0", "e-").replace("e+0", "e")


def run(binary, case, out, extra):
    """Runs a case (`extra`: more arguments); its summary.json and the exit code."""
    cmd = [binary, "run", case, "--quiet", "--force", "--out", out] + extra
    r = subprocess.run(cmd, capture_output=True, text=True)
    path = os.path.join(out, "summary.json")
    if not os.path.exists(path):
        sys.exit(f"{case}: no summary ({r.stderr.strip()})")
    with open(path) as f:
        return json.load(f), r.returncode


def sets(values):
    """--set KEY=VALUE for each value."""
    return [a for kv in values for a in ("--set", kv)]


def bound(s, name):
    """The bound of the case's `expect:` entry `name`, or None."""
    for e in s.get(K.EXPECT[0], []):
        if e[K.NAME] == name:
            return e[K.BOUND]
    return None


def measures(s):
    """The case's `reference:` measures by name."""
    return {r[K.NAME]: r[K.MEASURED] for r in get(s, K.REFERENCES)}


def missed(s):
    """'pass', or the bounds and references the run missed, in bold."""
    out = [f"{e[K.NAME]} {g(e[K.MEASURED])} > {g(e[K.BOUND])}"
           for e in s.get(K.EXPECT[0], []) if not e[K.PASS]]
    out += [f"{r[K.NAME]} {g(r[K.MEASURED])}" for r in s.get(K.REFERENCES[0], [])
            if r.get(K.PASS) is False]
    return "pass" if not out else "**" + "; ".join(out) + "**"


# stability ---------------------------------------------------------------------------------------
WHAT = {
    "touching-coincident": "Al blocks over coincident faces at t = 0, 10 m/s",
    "touching-gap0": "staggered meshes (4×4 / 5×5), gap 0",
    "touching-ulp": "gap 1 ulp of 0.01 m (1.7e-18 m)",
    "touching-1e-12": "gap 1e-12 m",
    "sliver-contact": "steel block on an Al slab of one layer of 10 × 10 × 0.2 mm hexes "
                      "(aspect ≥ 50), 50 m/s",
    "plate-one-element": "steel sphere on an Al plate one element thick, 300 m/s",
    "grazing-1deg": "Al block onto an Al plate at 1°, 200 m/s",
    "stiff-on-soft": "tungsten alloy on E = 0.2 GPa, ρ = 1500 (stiffness ratio 1.8e3, "
                     "density 12), 100 m/s",
    "tiny-step": "the touching blocks with cfl 5e-6: τ = 1.0e-12 s",
    "hypervelocity": "Al sphere on an Al plate at 7 km/s (M0 = 1.34), fracture, particles, "
                     "erosion",
    "spinning": "free Al cylinder at 20,000 rad/s for 0.8 rad",
}
STABILITY_HEADER = [
    "| case | what | steps, min τ | momentum | energy (bound) | depth/h (bound), nodes "
    "inside, crossings | safeguards | contact off: depth/h, `--check` |",
    "|---|---|---|---|---|---|---|---|"]


def stability_row(name, on, code, off, code_off):
    """One case: `on` the summary as shipped (exit `code`), `off` with contact off (or None)."""
    pen = "–"
    if get(on, K.MAX_DEPTH_OVER_H) is not None and off is not None:
        pen = (f"{g(get(on, K.MAX_DEPTH_OVER_H))} ({g(bound(on, K.EXPECT_DEPTH))}), "
               f"{get(on, K.MAX_NODES_INSIDE)}, {get(on, K.MAX_CROSSINGS)}")
        if K.has(on, K.PARTICLES_INSIDE_AT_END):
            pen += f"; {get(on, K.PARTICLES_INSIDE_AT_END)} particles inside"
    sg = "–"
    if get(on, K.SAFEGUARDS_ERODED) is not None:
        sg = (f"{get(on, K.SAFEGUARDS_ERODED):,} eroded, "
              f"{get(on, K.SAFEGUARDS_PARTICLES_MOVED_OUT):,} moved out")
    offc = "–"
    if off is not None:
        fails = code_off == 1 and not get(off, K.EXPECT_PASS)
        offc = f"{g(get(off, K.MAX_DEPTH_OVER_H))}, {'fails' if fails else 'PASSES'}"
    steps = f"{get(on, K.STEPS):,}, {g(get(on, K.TIME_STEP_MIN))} s"
    return (f"| `{name}` | {WHAT.get(name, '')} | {steps} | {g(get(on, K.MOMENTUM_ERROR))} | "
            f"{g(get(on, K.ENERGY_BALANCE_ERROR_MAX))} ({g(bound(on, K.EXPECT_ENERGY))}) | "
            f"{pen} | {sg} | {offc} |" + ("" if code == 0 else " **check failed**"))


def stability(binary, work, opts):
    yield from STABILITY_HEADER
    for name in WHAT:
        case = os.path.join(ROOT, "data/cases/stability", name + ".yaml")
        on, code = run(binary, case, os.path.join(work, name), ["--check"])
        off, code_off = None, None
        if any(m.startswith("broadphase:") for m in get(on, K.MODULES)):
            off, code_off = run(binary, case, os.path.join(work, name + "-off"),
                                ["--check", "--set", "contact.enabled=false"])
        yield stability_row(name, on, code, off, code_off)


# micro -------------------------------------------------------------------------------------------
MICRO_HEADER = [
    "| micro-scene | steps | pass | momentum error | energy balance | max depth / h (bound) | "
    "nodes inside | edge crossings | verified (the default): nodes inside / crossings, pass | "
    "contact off: depth / h, pass |",
    "|---|---|---|---|---|---|---|---|---|---|"]


def micro_row(name, s, v, o):
    """One scene of `stress --json`: `s` unverified, `v` verified, `o` contact off."""
    b = next((e[K.BOUND] for e in s[K.SCENE_EXPECT] if e[K.NAME] == K.EXPECT_DEPTH), None)
    return (f"| {name} | {s[K.SCENE_STEPS]} | {'yes' if s[K.SCENE_PASS] else 'NO'} | "
            f"{g(s[K.SCENE_MOMENTUM_ERROR])} | {g(s[K.SCENE_BALANCE_ERROR])} | "
            f"{g(s[K.SCENE_DEPTH_OVER_H])} ({g(b)}) | {s[K.SCENE_NODES_INSIDE]} | "
            f"{s[K.SCENE_CROSSINGS]} | {v[K.SCENE_NODES_INSIDE]} / {v[K.SCENE_CROSSINGS]}, "
            f"{'yes' if v[K.SCENE_PASS] else 'NO'} | {g(o[K.SCENE_DEPTH_OVER_H])}, "
            f"{'yes' if o[K.SCENE_PASS] else 'no'} |")


def micro(binary, work, opts):
    res = {}
    for label, extra in (("on", ["--set", "contact.verify=false"]), ("verify", []),
                         ("off", ["--set", "contact.enabled=false"])):
        r = subprocess.run([binary, "stress", "--count", "10", "--json"] + extra,
                           capture_output=True, text=True)
        if r.returncode not in (0, 1) or not r.stdout.strip():
            sys.exit(f"stress --json {' '.join(extra)}: exit {r.returncode}: {r.stderr.strip()}")
        res[label] = {s[K.NAME]: s for s in json.loads(r.stdout)[K.STRESS_SCENES]}
    yield from MICRO_HEADER
    for name, s in res["on"].items():
        yield micro_row(name, s, res["verify"][name], res["off"][name])


# profile -----------------------------------------------------------------------------------------
PROFILE_HEADER = [
    "| method | primitives | candidates/step | contacts/step | candidates/all pairs | build ms | "
    "query ms | step ms | broadphase share | contact share |",
    "|---|---|---|---|---|---|---|---|---|---|"]


def profile_row(m):
    """One broadphase method of `profile --json`."""
    sec = m[K.PROFILE_SECONDS]
    return (f"| {m[K.PROFILE_METHOD]} | {int(m[K.PROFILE_PRIMITIVES]):,} | "
            f"{m[K.PROFILE_CANDIDATES]:.1f} | {m[K.PROFILE_CONTACTS]:.1f} | "
            f"{g(m[K.PROFILE_PRUNING])} | {sec[K.PROFILE_BUILD] * 1e3:.3f} | "
            f"{sec[K.PROFILE_QUERY] * 1e3:.3f} | {sec[K.PROFILE_STEP] * 1e3:.3f} | "
            f"{100 * m[K.PROFILE_BROADPHASE_SHARE]:.1f} % | "
            f"{100 * m[K.PROFILE_CONTACT_SHARE]:.1f} % |")


def profile(binary, work, opts):
    r = subprocess.run([binary, "profile", os.path.join(ROOT, "data/cases/bars-impact.yaml"),
                        "--steps", "300", "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"profile: exit {r.returncode}: {r.stderr.strip()}")
    yield from PROFILE_HEADER
    for m in json.loads(r.stdout):
        yield profile_row(m)


# ccd ---------------------------------------------------------------------------------------------
CCD_HEADER = [
    "| query set | type | queries | collisions | false positives / negatives | mean time a "
    "query | FCL 0.7: collisions, false positives / negatives, mean time |",
    "|---|---|---|---|---|---|---|"]
CCD_REAL_STEPS = 40  # steps of the cylinders whose queries are timed


def ccd_rows(what, result):
    """The two rows (edge–edge, vertex–face) of one `ccd --json --fcl` result."""
    for kind, label in (("ee", "edge–edge"), ("vf", "vertex–face")):
        r = result[kind]
        f = r[K.CCD_FCL]
        truth = K.CCD_FALSE_POSITIVES in r
        ours = (f"**{r[K.CCD_FALSE_POSITIVES]} / {r[K.CCD_FALSE_NEGATIVES]}**" if truth
                else "– (no ground truth)")
        theirs = (f"{f[K.CCD_COLLISIONS]:,}, "
                  + (f"{f[K.CCD_FALSE_POSITIVES]} / {f[K.CCD_FALSE_NEGATIVES]}, " if truth else "")
                  + f"{f[K.CCD_MEAN_NS]:.0f} ns")
        yield (f"| {what} | {label} | {r[K.CCD_QUERIES]:,} | {r[K.CCD_COLLISIONS]:,} | {ours} | "
               f"**{r[K.CCD_MEAN_NS]:.0f} ns** | {theirs} |")


def ccd_json(binary, path):
    r = subprocess.run([binary, "ccd", path, "--fcl", "--quiet", "--json"], capture_output=True,
                       text=True)
    if r.returncode != 0:
        sys.exit(f"ccd {path}: exit {r.returncode}: {r.stderr.strip()}")
    return json.loads(r.stdout)


def ccd(binary, work, opts):
    """The shared set, then the queries of the cylinders' first steps (recorded by `profile
    --ccd-queries`)."""
    os.makedirs(work, exist_ok=True)
    yield from CCD_HEADER
    yield from ccd_rows("shared degenerate set (`data/ccd/handcrafted.txt`)",
                        ccd_json(binary, os.path.join(ROOT, "data/ccd/handcrafted.txt")))
    queries = os.path.join(work, "cylinders-queries.txt")
    r = subprocess.run([binary, "profile", os.path.join(ROOT, "data/cases/cylinders.yaml"),
                        "--broadphase", "grid", "--steps", str(CCD_REAL_STEPS), "--set",
                        "contact.edge_edge=true", "--set", "contact.verify=true",
                        "--ccd-queries", queries, "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"profile: exit {r.returncode}: {r.stderr.strip()}")
    yield from ccd_rows(f"the cylinders' first {CCD_REAL_STEPS} steps (contact detection and "
                        "the verification)", ccd_json(binary, queries))
    os.remove(queries)


# threads -----------------------------------------------------------------------------------------
UNVERIFIED = ["contact.verify=false", "contact.edge_edge=false"]
THREAD_CASES = [  # each case run in full on 1 and 2 threads, the verification off
    ("bars", "data/cases/bars-impact.yaml", UNVERIFIED),
    ("cylinders, edge–edge on", "data/cases/cylinders.yaml",
     ["contact.edge_edge=true", "contact.verify=false"]),
    ("Hertz", "data/cases/hertz-spheres.yaml", UNVERIFIED),
    ("ball-plate", "data/cases/ball-plate.yaml", UNVERIFIED),
]
THREADS_HEADER = [
    "| case | tets | steps | wall, 1 thread | wall, 2 threads | speed-up | stage shares at 1 "
    "thread | stage shares at 2 threads |",
    "|---|---|---|---|---|---|---|---|"]


def stage_shares(summary):
    """The stages' shares of the wall time: 'elements 60 %, contact 30 %, ...'."""
    t = get(summary, K.TIMINGS)
    wall = get(summary, K.WALL_SECONDS)
    groups = {"elements": [K.STAGE_ELEMENTS], "contact": K.CONTACT_STAGES,
              "particles": K.PARTICLE_STAGES, "output": [K.STAGE_OUTPUT],
              "balance": [K.STAGE_BALANCE]}
    parts = []
    for name, stages in groups.items():
        sec = sum(t.get(s, 0.0) for s in stages)
        if sec > 0:
            parts.append(f"{name} {100 * sec / wall:.0f} %")
    return ", ".join(parts)


def threads_row(name, one, two):
    """One case on 1 thread (`one`) and 2 (`two`)."""
    w1, w2 = get(one, K.WALL_SECONDS), get(two, K.WALL_SECONDS)
    return (f"| {name} | {get(one, K.MESH_TETS):,} | {get(one, K.STEPS):,} | {w1:.1f} s | "
            f"{w2:.1f} s | {w1 / w2:.2f}× | {stage_shares(one)} | {stage_shares(two)} |")


def threads(binary, work, opts):
    yield from THREADS_HEADER
    for name, case, keys in THREAD_CASES:
        if opts.cases and not any(o in case for o in opts.cases):
            continue
        summaries = {}
        for n in (1, 2):
            s, code = run(binary, os.path.join(ROOT, case),
                          os.path.join(work, f"{os.path.basename(case)}-{n}"),
                          ["--threads", str(n)] + sets(keys))
            if code != 0:
                sys.exit(f"{case} on {n} threads: exit {code}")
            summaries[n] = s
        if get(summaries[1], K.STEPS) != get(summaries[2], K.STEPS):
            sys.exit(f"{case}: different step counts on 1 and 2 threads")
        yield threads_row(name, summaries[1], summaries[2])


# mpi ---------------------------------------------------------------------------------------------
MPI_CASES = [
    ("Taylor rod on a wall (ANP)", "data/cases/taylor-copper.yaml", ["end_time=20.0e-6"]),
    ("bars", "data/cases/bars-impact.yaml", ["contact.verify=false", "contact.edge_edge=false"]),
    ("cylinders, edge–edge on, coarse", "data/cases/cylinders.yaml",
     ["contact.verify=false", "bodies.0.mesh.cylinder.cells_across=8", "bodies.0.mesh.cylinder.cells_axial=8",
      "bodies.1.mesh.cylinder.cells_across=4", "bodies.1.mesh.cylinder.cells_axial=4"]),
    ("cylinders, edge–edge and verification on, coarse", "data/cases/cylinders.yaml",
     ["contact.verify=true",
      "bodies.0.mesh.cylinder.cells_across=8", "bodies.0.mesh.cylinder.cells_axial=8",
      "bodies.1.mesh.cylinder.cells_across=4", "bodies.1.mesh.cylinder.cells_axial=4"]),
]
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"]
MPI_HEADER = [
    "| case (fastest of 3) | tets | steps | 1 process, 1 thread | 1 process, 2 threads | "
    "2 ranks × 1 thread | elements: 1 thread / 2 ranks | verify: 1 thread / 2 ranks | "
    "communication (2 ranks) | same result |",
    "|---|---|---|---|---|---|---|---|---|---|"]
WEAK_HEADER = [
    "| weak scaling (fastest of 3) | tets | steps | wall | elements | communication | "
    "efficiency |",
    "|---|---|---|---|---|---|---|"]


def mpi_row(name, a, b, c):
    """One case: `a` one process on 1 thread, `b` on 2 threads, `c` 2 ranks of 1 thread."""
    ta, tc = get(a, K.TIMINGS), get(c, K.TIMINGS)
    same = all(a[k] == c[k] for k in K.RESULT_BLOCKS)
    verify = (f"{ta[K.STAGE_VERIFY]:.1f} s / {tc[K.STAGE_VERIFY]:.1f} s"
              if K.STAGE_VERIFY in ta else "–")
    return (f"| {name} | {get(a, K.MESH_TETS):,} | {get(a, K.STEPS):,} | "
            f"{get(a, K.WALL_SECONDS):.1f} s | {get(b, K.WALL_SECONDS):.1f} s | "
            f"{get(c, K.WALL_SECONDS):.1f} s | "
            f"{ta[K.STAGE_ELEMENTS]:.1f} s / {tc[K.STAGE_ELEMENTS]:.1f} s | {verify} | "
            f"{get(c, K.COMMUNICATION_SECONDS):.2f} s | {'yes' if same else 'NO'} |")


def weak_row(label, wall, rs, base, independent):
    """One weak-scaling row: the fastest round's wall time and summaries (two for the pair of
    independent processes), against the 1-rank run's `base` wall time."""
    r = rs[0]
    tets = f"{get(r, K.MESH_TETS):,}" if len(rs) == 1 else f"2 × {get(r, K.MESH_TETS):,}"
    comm = "–" if independent else f"{get(r, K.COMMUNICATION_SECONDS):.2f} s"
    elements = max(get(x, K.TIMINGS)[K.STAGE_ELEMENTS] for x in rs)
    return (f"| {label} | {tets} | {get(r, K.STEPS):,} | {wall:.1f} s | {elements:.1f} s | "
            f"{comm} | {base / wall * 100:.0f} % |")


def mpi(binary, work, opts):
    """Each case as one process on 1 and 2 threads and on 2 ranks of 1 thread (mpirun), the
    fastest of 3 runs each (this machine's run to run spread is ±20 %)."""
    yield from MPI_HEADER
    for name, case, keys in MPI_CASES:
        runs = {}
        for label, launcher, n in (("1x1", [], 1), ("1x2", [], 2), ("2x1", MPIRUN, 1)):
            out = os.path.join(work, f"{os.path.basename(case)}-{label}")
            cmd = launcher + [binary, "run", os.path.join(ROOT, case), "--quiet", "--force",
                              "--threads", str(n), "--out", out] + sets(keys)
            for _ in range(3):
                subprocess.run(cmd, check=True)
                with open(os.path.join(out, "summary.json")) as f:
                    r = json.load(f)
                if label not in runs or get(r, K.WALL_SECONDS) < get(runs[label], K.WALL_SECONDS):
                    runs[label] = r
        yield mpi_row(name, runs["1x1"], runs["1x2"], runs["2x1"])
    # Weak scaling: the Taylor rod on 1 rank, and twice as long (twice the tets, the same cells)
    # on 2 ranks, 1 thread each; and the machine's own ceiling: the 1-rank run twice at once as
    # two independent processes (no communication: what two busy cores give when they share the
    # machine's caches and memory). Each the fastest of 3 rounds.
    yield ""
    yield from WEAK_HEADER
    taylor = os.path.join(ROOT, "data/cases/taylor-copper.yaml")

    def command(out, height="32.4e-3", cells=40, z="16.2e-3"):
        return [binary, "run", taylor, "--quiet", "--force", "--threads", "1", "--out", out,
                "--set", "end_time=20.0e-6", "--set", f"bodies.0.mesh.cylinder.height={height}",
                "--set", f"bodies.0.mesh.cylinder.cells_axial={cells}",
                "--set", f"bodies.0.transform.0.translate=[0,0,{z}]"]

    def summary(out):
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)

    best = {}
    for _ in range(3):
        runs = {}
        subprocess.run(command(os.path.join(work, "weak-1")), check=True)
        runs["one"] = [summary(os.path.join(work, "weak-1"))]
        subprocess.run(MPIRUN + command(os.path.join(work, "weak-2"), "64.8e-3", 80, "32.4e-3"),
                       check=True)
        runs["two"] = [summary(os.path.join(work, "weak-2"))]
        outs = [os.path.join(work, f"weak-alone-{i}") for i in range(2)]
        procs = [subprocess.Popen(command(out)) for out in outs]
        if any(p.wait() != 0 for p in procs):
            sys.exit("weak scaling: a run failed")
        runs["pair"] = [summary(out) for out in outs]
        for k, rs in runs.items():
            wall = max(get(r, K.WALL_SECONDS) for r in rs)
            if k not in best or wall < best[k][0]:
                best[k] = (wall, rs)
    base = best["one"][0]
    for k, label in (("one", "Taylor rod, 1 rank"), ("two", "Taylor rod, 2 ranks"),
                     ("pair", "the 1-rank run twice at once, independent (the machine's "
                              "ceiling)")):
        yield weak_row(label, best[k][0], best[k][1], base, k == "pair")


# verify, verify-full -----------------------------------------------------------------------------
VERIFY_ROWS = [  # (what, case, --set values)
    ("cubes-edge, every step", "data/cases/cubes-edge.yaml",
     ["contact.verify=true", "diagnostics.every_step=true"]),
    ("cubes-edge, edge–edge off, every step", "data/cases/cubes-edge.yaml",
     ["contact.verify=false", "contact.edge_edge=false", "diagnostics.every_step=true"]),
    ("cubes-edge, edge–edge off, every step", "data/cases/cubes-edge.yaml",
     ["contact.verify=true", "contact.edge_edge=false", "diagnostics.every_step=true"]),
    ("micro coincident-faces, every step", "data/cases/micro/coincident-faces.yaml",
     ["contact.verify=true", "diagnostics.every_step=true"]),
    ("bars-impact, edge–edge off", "data/cases/bars-impact.yaml",
     ["contact.verify=false", "contact.edge_edge=false"]),
    ("bars-impact, edge–edge off", "data/cases/bars-impact.yaml",
     ["contact.verify=true", "contact.edge_edge=false"]),
    ("bars-impact, edge–edge off, separation 0", "data/cases/bars-impact.yaml",
     ["contact.verify=true", "contact.edge_edge=false", "contact.separation=0"]),
    ("bars-impact, edge–edge on", "data/cases/bars-impact.yaml",
     ["contact.verify=true", "contact.edge_edge=true"]),
    ("staggered-patch, edge–edge on", "data/cases/staggered-patch.yaml",
     ["contact.verify=true", "contact.edge_edge=true"]),
    ("touching-gap0, edge–edge on", "data/cases/stability/touching-gap0.yaml",
     ["contact.verify=true", "contact.edge_edge=true"]),
] + [
    (what, case, keys + [f"contact.verify={on}", "diagnostics.every_step=true"])
    for what, case, keys in [
        ("cylinders (edge–edge on), coarse (8 / 4 across), every step", "data/cases/cylinders.yaml",
         ["bodies.0.mesh.cylinder.cells_across=8", "bodies.0.mesh.cylinder.cells_axial=8",
          "bodies.1.mesh.cylinder.cells_across=4", "bodies.1.mesh.cylinder.cells_axial=4"]),
        ("spall-plate, edge–edge on, every step", "data/cases/spall-plate.yaml",
         ["contact.edge_edge=true"]),
        ("taylor-symmetric, edge–edge on, coarse (6 across), to 10 µs, every step",
         "data/cases/taylor-symmetric.yaml",
         ["contact.edge_edge=true", "end_time=10.0e-6", "bodies.0.mesh.cylinder.cells_across=6",
          "bodies.0.mesh.cylinder.cells_axial=30", "bodies.1.mesh.cylinder.cells_across=6",
          "bodies.1.mesh.cylinder.cells_axial=30"]),
    ]
    for on in ("false", "true")
]
VERIFY_HEADER = [
    "| case | verify | crossings / nodes inside | checks | failing pairs (steps) | step cuts | "
    "steps with zones: zones (translated / frozen) | verify stage / run |",
    "|---|---|---|---|---|---|---|---|"]
FULL_CASES = ["cubes-edge", "two-blocks-msh", "plate-impact-1d", "staggered-patch",
              "bars-impact", "spall-plate", "taylor-copper", "cylinders", "ball-plate",
              "taylor-symmetric", "hertz-spheres"]
VERIFY_FULL_HEADER = [
    "| case | crossings / nodes inside | checks | momentum | energy | failing pairs (steps) | "
    "step cuts | steps with zones: zones (translated / frozen) | verify stage / run |",
    "|---|---|---|---|---|---|---|---|---|"]


def cuts(s):
    """The steps the verification had taken again with half their step."""
    return f"{get(s, K.VERIFY_STEP_CUTS):,}"


def zones(s):
    """'steps: zones (translated / frozen)' of the verification."""
    return (f"{get(s, K.VERIFY_STEPS_WITH_ZONES)}: {get(s, K.VERIFY_IMPACT_ZONES)} "
            f"({get(s, K.VERIFY_TRANSLATED_ZONES)} / {get(s, K.VERIFY_FROZEN_ZONES)})")


def failing(s):
    """'pairs (steps of all)' the verification found failing after the passes."""
    return (f"{get(s, K.VERIFY_FAILED_AFTER_PASSES):,} ({get(s, K.VERIFY_STEPS_FAILED)} of "
            f"{get(s, K.STEPS)})")


def verify_row(what, s):
    """One row of the step verification's table; the verification off when the summary has
    none."""
    where = (f"at all {get(s, K.PENETRATION_SAMPLES)} steps"
             if get(s, K.PENETRATION_MEASURED_AT) == "every step" else "at the frames")
    pen = f"{get(s, K.MAX_CROSSINGS)} / {get(s, K.MAX_NODES_INSIDE)} {where}"
    on = K.has(s, K.VERIFICATION)
    wall = get(s, K.WALL_SECONDS)
    cost = (f"{get(s, K.TIMINGS).get(K.STAGE_VERIFY, 0):.3g} s / {wall:.3g} s" if on
            else f"— / {wall:.3g} s")
    return (f"| {what} | {'on' if on else 'off'} | {pen} | {missed(s)} | "
            f"{failing(s) if on else '—'} | {cuts(s) if on else '—'} | "
            f"{zones(s) if on else '—'} | {cost} |")


def verify(binary, work, opts):
    yield from VERIFY_HEADER
    for k, (what, case, keys) in enumerate(VERIFY_ROWS):
        s, _ = run(binary, os.path.join(ROOT, case), os.path.join(work, f"row{k}"),
                   ["--check"] + sets(keys))
        yield verify_row(what, s)


def verify_full_row(name, s):
    """One shipped case at full size, verified, measured after every step."""
    return (f"| {name} | {get(s, K.MAX_CROSSINGS)} / {get(s, K.MAX_NODES_INSIDE)} at all "
            f"{get(s, K.PENETRATION_SAMPLES)} steps | {missed(s)} | "
            f"{g(get(s, K.MOMENTUM_ERROR))} | {g(get(s, K.ENERGY_BALANCE_ERROR_MAX))} | "
            f"{failing(s)} | {cuts(s)} | {zones(s)} | "
            f"{get(s, K.TIMINGS).get(K.STAGE_VERIFY, 0):.3g} s / {get(s, K.WALL_SECONDS):.3g} s |")


def verify_full(binary, work, opts):
    """Every shipped case with contact, full size, edge–edge on, verification on, measured
    after every step."""
    yield from VERIFY_FULL_HEADER
    for name in FULL_CASES:
        s, _ = run(binary, os.path.join(ROOT, "data/cases", name + ".yaml"),
                   os.path.join(work, name),
                   ["--check"] + sets(["contact.edge_edge=true", "contact.verify=true",
                                       "diagnostics.every_step=true"]))
        yield verify_full_row(name, s)


# strength ----------------------------------------------------------------------------------------
LAWS = ["bilinear", "johnson_cook", "steinberg_guinan"]
LAW_NAMES = {"bilinear": "bilinear (perfectly plastic at Y0)", "johnson_cook": "Johnson–Cook",
             "steinberg_guinan": "Steinberg–Guinan"}
HEL_MEASURED = 0.64e9     # Pa, the plate impact's measured precursor (± 0.07 GPa)
ROD_LENGTH0 = 23.47e-3    # m, the aluminium Taylor rod's length and radius before impact
ROD_RADIUS0 = 3.81e-3
STRENGTH_HEADER = [
    "| law | Taylor rod: steps | smallest step / first | step falls reported | L (mm), L/L0 | "
    "footprint radius (mm), R/R0 | energy balance | wall time | HEL (GPa), vs 0.64 ± 0.07 "
    "measured |",
    "|---|---|---|---|---|---|---|---|---|"]


def strength_row(law, rod, plate):
    """One strength law: the Taylor rod's summary and the plate impact's."""
    b = get(rod, K.BODIES)[0]
    length = b[K.BBOX_MAX][2] - b[K.BBOX_MIN][2]
    radius = 0.5 * (b[K.BBOX_MAX][0] - b[K.BBOX_MIN][0])
    hel = measures(plate)[K.HEL]
    err = hel / HEL_MEASURED - 1.0
    return (f"| {LAW_NAMES.get(law, law)} | {get(rod, K.STEPS):,} | "
            f"{get(rod, K.TIME_STEP_MIN) / get(rod, K.TIME_STEP_FIRST):.3f} | "
            f"{len(get(rod, K.TIME_STEP_COLLAPSES))} | {length * 1e3:.2f}, "
            f"{length / ROD_LENGTH0:.3f} | {radius * 1e3:.2f}, {radius / ROD_RADIUS0:.2f} | "
            f"{g(get(rod, K.ENERGY_BALANCE_ERROR))} | {get(rod, K.WALL_SECONDS):.1f} s | "
            f"{hel / 1e9:.3f} ({err * 100:+.1f} %) |")


def strength(binary, work, opts):
    """Each strength law on the aluminium Taylor rod and on the plate impact's precursor."""
    yield from STRENGTH_HEADER
    for law in LAWS:
        extra = ["--set", f"materials.al.strength={law}", "--threads", "1"]
        rod, _ = run(binary, os.path.join(ROOT, "data/cases/taylor-aluminium.yaml"),
                     os.path.join(work, f"rod-{law}"), extra)
        plate, _ = run(binary, os.path.join(ROOT, "data/cases/plate-impact-1d.yaml"),
                       os.path.join(work, f"plate-{law}"), extra)
        yield strength_row(law, rod, plate)


# taylor-tests ------------------------------------------------------------------------------------
VALIDATION = os.path.join(ROOT, "data", "validation")
TAYLOR_LAWS = [  # (the campaign's folder, its label, --set and --rows)
    ("default", "the library's default law", [], None),
    ("johnson_cook", "Johnson–Cook", ["materials.rod.strength=johnson_cook"], None),
]
TAYLOR_HEADER = [
    "| material (default law) | law | tests | Lf: median, 90 % within, largest \\|ΔLf/Lf\\| | "
    "within 5 % | below 400 K: tests, median, 90 % within | footprint: median \\|Δ\\| (tests) | "
    "steps, most | run time (sum) |",
    "|---|---|---|---|---|---|---|---|---|"]


def abs_stats(errors):
    """(median, 90th percentile by nearest rank) of |errors|, as campaign's statistics."""
    a = sorted(abs(e) for e in errors)
    n = len(a)
    if n == 0:
        return None, None
    median = a[n // 2] if n % 2 else 0.5 * (a[n // 2 - 1] + a[n // 2])
    return median, a[max(1, -(-9 * n // 10)) - 1]
DEFAULT_LAW = {"Al 6061-T6": "Steinberg–Guinan", "Cu ETP": "Steinberg–Guinan",
               "Cu OFHC": "Steinberg–Guinan", "Steel 4340": "Johnson–Cook"}


def pct(x):
    return "–" if x is None else f"{100 * x:.1f} %"


def taylor_rows(folder, label):
    """(material, row) per material of one campaign folder (its statistics.json and runs)."""
    with open(os.path.join(folder, "statistics.json")) as f:
        stats = json.load(f)
    with open(os.path.join(folder, "predictions.csv")) as f:
        rows = list(csv.DictReader(f))
    length, foot = stats["comparisons"][0], stats["comparisons"][1]
    for material, st in length["groups"].items():
        mine = [r for r in rows if r["material"] == material]
        steps = []
        for r in mine:
            with open(os.path.join(folder, "runs", r["folder"], "summary.json")) as f:
                steps.append(get(json.load(f), K.STEPS))
        seconds = sum(float(r["wall_seconds"] or 0) for r in mine)
        cold = [float(r["error:final length"]) for r in mine
                if r["error:final length"] and float(r["parameters.T0"]) < 400.0]
        cold_median, cold_p90 = abs_stats(cold)
        ft = foot["groups"][material]
        yield material, (f"{label} | {st['compared']} | {pct(st['median_abs_error'])}, "
                         f"{pct(st['p90_abs_error'])}, {pct(st['max_abs_error'])} | "
                         f"{pct(st['within_tolerance'])} | {len(cold)}, {pct(cold_median)}, "
                         f"{pct(cold_p90)} | {pct(ft['median_abs_error'])} "
                         f"({ft['compared']}) | {max(steps):,} | {seconds:.0f} s |")


def taylor_campaign(binary, out, keys, rows=None):
    """The Taylor campaign of the shared tests into `out` with --set `keys` (on `rows`, a --rows
    expression, or all): its predictions."""
    cmd = [binary, "campaign", os.path.join(ROOT, "data/cases/taylor.yaml"),
           os.path.join(VALIDATION, "taylor-tests.csv"), "--quiet", "--out", out] + sets(keys) \
        + (["--rows", rows] if rows else [])
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"tables.py: error: {' '.join(cmd)}: exit {r.returncode}\n{r.stderr}")
    with open(os.path.join(out, "predictions.csv")) as f:
        return list(csv.DictReader(f))


def taylor_tests(binary, work, opts):
    """Every shared Taylor test under each law (a campaign each), and the figure."""
    table = os.path.join(VALIDATION, "taylor-tests.csv")
    if not os.path.isfile(table):
        raise SystemExit(f"tables.py: error: {table}: no such file (the shared Taylor tests)")
    yield from TAYLOR_HEADER
    folders = []
    for name, label, keys, rows in TAYLOR_LAWS:
        out = os.path.join(work, "taylor-" + name)
        taylor_campaign(binary, out, keys, rows)
        folders.append((out, label))
    by_material = {}
    for out, label in folders:
        for material, row in taylor_rows(out, label):
            by_material.setdefault(material, []).append(row)
    for material in sorted(by_material):
        for k, row in enumerate(by_material[material]):
            name = f"{material} ({DEFAULT_LAW.get(material, '?')})" if k == 0 else ""
            yield f"| {name} | {row}"
    figure = os.path.join(ROOT, "data", "figures", "taylor-lf.png")
    subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tools/post/plot_taylor.py")]
                   + [f for f, _ in folders[:2]] + ["--label", folders[0][1], "--label",
                                                   folders[1][1], "--out", figure], check=True,
                   capture_output=True)
    yield from taylor_outlines(folders)


def taylor_outlines(folders):
    """The computed outlines of the digitised rods (tools/post/taylor_profiles.py), a row per
    rod with each law's footprint and mean |Δr| / R0, and the figure of them."""
    from tools.post import taylor_profiles as tp
    index = os.path.join(VALIDATION, "taylor-profiles.csv")
    profiles = tp.checked_profiles(index, os.path.join(VALIDATION, "taylor-tests.csv"),
                                   os.path.join(VALIDATION, "taylor-profiles"))
    table = tp.rows(profiles, [f for f, _ in folders])
    labels = [label for _, label in folders]
    yield ""
    yield ("| digitised outline | test | footprint radius (mm): measured; "
           + ", ".join(labels) + " | mean (largest) \\|Δr\\| / R0: " + ", ".join(labels) + " |")
    yield "|---|---|---|---|"
    for name, test, outline, results in table:
        bottom = min(z for _, z in outline)
        foot = max(r for r, z in outline if z == bottom)
        feet = ", ".join(f"{computed_foot:.2f}" for _, computed_foot, _, _ in results)
        shapes = ", ".join(f"{100 * mean:.1f} % ({100 * largest:.0f} %)"
                           for _, _, mean, largest in results)
        yield (f"| `{name}` | {test['material']}, {test['source'].split(' (')[0]}, "
               f"{test['U0_m_s']} m/s, {test['T0_K']} K | {foot:.2f}; {feet} | {shapes} |")
    tp.plot(table, labels, os.path.join(ROOT, "data", "figures", "taylor-profiles.png"))


# taylor-temper -----------------------------------------------------------------------------------
TEMPER_PROGRAMME = ("Cu OFHC", "House et al. 1995")  # the material and source of the fitted rods
TEMPER_ENTRY = "ofhc-copper-house"  # the library's entry for them
TEMPER_BRACKET = (0.0, 0.6)  # the cold work searched, ε̄p0
TEMPER_TOLERANCE = 0.01  # the bracket's width at which the search stops
TEMPER_HEADER = [
    "| rods | law | ε̄p0 | tests | Lf: median, 90 % within, largest \\|ΔLf/Lf\\| | mean ΔLf/Lf | "
    "footprint: median \\|Δ\\|, mean Δ |",
    "|---|---|---|---|---|---|---|"]


def library_value(name, key):
    """A number of a library entry, read from its `key:` line in data/materials.yaml."""
    entry = None
    with open(os.path.join(ROOT, "data", "materials.yaml")) as f:
        for line in f:
            if re.match(r"^[a-z0-9-]+:", line):
                entry = line.split(":")[0]
            elif entry == name and line.strip().startswith(key + ":"):
                return float(line.split(":")[1].split("#")[0])
    raise SystemExit(f"tables.py: error: data/materials.yaml: entry {name} has no {key}")


def numbers(rows):
    """Row numbers as a --rows expression."""
    return ",".join(str(r) for r in rows)


def temper_row(rods, law, eps, predictions):
    """One campaign's errors: the final length's and the footprint's."""
    length = [float(r["error:final length"]) for r in predictions]
    foot = [float(r["error:footprint radius"]) for r in predictions if r["error:footprint radius"]]
    median, p90 = abs_stats(length)
    foot_median, _ = abs_stats(foot)
    return (f"| {rods} | {law} | {eps} | {len(length)} | {pct(median)}, {pct(p90)}, "
            f"{pct(max(abs(e) for e in length))} | {100 * statistics.mean(length):+.1f} % | "
            f"{pct(foot_median)}, {100 * statistics.mean(foot):+.1f} % |")


def taylor_temper(binary, work, opts):
    """The cold work of House et al.'s copper (their temper is not stated): ε̄p0 found by
    bisection, under copper's default law, so that the mean ΔLf/Lf of every other one of their
    rods (the first, the third, ...) vanishes; then the library's entry for them, which must
    hold that value, on those rods and on the others, under the default law and Johnson–Cook."""
    with open(os.path.join(VALIDATION, "taylor-tests.csv")) as f:
        table = list(csv.DictReader(line for line in f if not line.startswith("#")))
    rods = [k + 1 for k, r in enumerate(table) if (r["material"], r["source"]) == TEMPER_PROGRAMME]
    if not rods:
        raise SystemExit(f"tables.py: error: taylor-tests.csv: no rods of {TEMPER_PROGRAMME}")
    fit, held = rods[0::2], rods[1::2]

    def mean_error(eps):
        out = os.path.join(work, f"temper-fit-{eps:.4f}")
        predictions = taylor_campaign(binary, out, [f"materials.rod.initial_plastic_strain={eps}"],
                                      numbers(fit))
        return statistics.mean(float(r["error:final length"]) for r in predictions)

    lo, hi = TEMPER_BRACKET
    f_lo, f_hi = mean_error(lo), mean_error(hi)
    searched = [(lo, f_lo), (hi, f_hi)]
    if not (f_lo < 0.0 < f_hi):
        raise SystemExit(f"tables.py: error: the mean ΔLf/Lf at ε̄p0 = {lo} and {hi} "
                         f"({f_lo:+.4f}, {f_hi:+.4f}) do not bracket zero")
    while hi - lo > TEMPER_TOLERANCE:
        mid = 0.5 * (lo + hi)
        f_mid = mean_error(mid)
        searched.append((mid, f_mid))
        lo, hi = (mid, hi) if f_mid < 0.0 else (lo, mid)
    f_a, f_b = dict(searched)[lo], dict(searched)[hi]
    fitted = lo - f_a * (hi - lo) / (f_b - f_a)  # the root, linear inside the last bracket
    shipped = library_value(TEMPER_ENTRY, "initial_plastic_strain")
    if abs(shipped - fitted) > TEMPER_TOLERANCE:
        raise SystemExit(f"tables.py: error: data/materials.yaml: {TEMPER_ENTRY}'s "
                         f"initial_plastic_strain {shipped} is not the fit's {fitted:.3f}")
    yield ("The search (ε̄p0: mean ΔLf/Lf of the fitting rods): "
           + ", ".join(f"{e:.4g}: {100 * f:+.2f} %" for e, f in sorted(searched))
           + f"; the root {fitted:.3f}, the library's entry `{TEMPER_ENTRY}` {shipped:g}.")
    yield ""
    yield from TEMPER_HEADER
    for label, which in ((f"fitting: {len(fit)} (rows {fit[0]}, {fit[1]}, … {fit[-1]})", fit),
                         (f"held out: {len(held)} (rows {held[0]}, {held[1]}, … {held[-1]})",
                          held)):
        for law, keys in (("Steinberg–Guinan (default)", []),
                          ("Johnson–Cook", ["materials.rod.strength=johnson_cook"])):
            tag = "sg" if not keys else "jc"
            # The entry without its cold work is `ofhc-copper`, the entry it derives from.
            before = taylor_campaign(binary, os.path.join(work, f"temper-{tag}-{which[0]}-ofhc"),
                                     keys + ["materials.rod.initial_plastic_strain=0"],
                                     numbers(which))
            after = taylor_campaign(binary, os.path.join(work, f"temper-{tag}-{which[0]}"), keys,
                                    numbers(which))
            yield temper_row(label, law, "0 (`ofhc-copper`)", before)
            yield temper_row("", "", f"{shipped:g} (`{TEMPER_ENTRY}`)", after)


# hugoniot ----------------------------------------------------------------------------------------
HUGONIOT_ENTRIES = ["al6061-t6", "al2024-t4", "al1100-o", "al7075-t6"]
HUGONIOT_BANDS = [(0, 20), (20, 50), (50, 120), (120, 250)]  # GPa


def library_eos(name):
    """(ρ0, c0, s) of a library entry's Mie–Grüneisen EOS, read from data/materials.yaml's
    one-line `eos:` of that entry."""
    entry = None
    with open(os.path.join(ROOT, "data", "materials.yaml")) as f:
        for line in f:
            if re.match(r"^[a-z0-9-]+:", line):
                entry = line.split(":")[0]
            elif entry == name and line.strip().startswith("density:"):
                rho = float(line.split(":")[1].split("#")[0])
            elif entry == name and line.strip().startswith("eos:"):
                c0 = float(re.search(r"c0: *([0-9.e+-]+)", line).group(1))
                s = float(re.search(r"\bs: *([0-9.e+-]+)", line).group(1))
                return rho, c0, s
    raise SystemExit(f"tables.py: error: data/materials.yaml: no Mie–Grüneisen entry {name}")


def hugoniot(binary, work, opts):
    """The library's aluminium EOS on its Hugoniot, p = ρ0 c0² η / (1 − s η)² (what the engine
    computes: Material.MieGruneisenReproducesItsHugoniot), against each measured shock state."""
    path = os.path.join(VALIDATION, "aluminium-hugoniot.csv")
    with open(path, newline="\n") as f:
        lines = [x.replace("\r", "") for x in f if x.strip() and not x.startswith("#")]
    shocks = [(float(r[0]), float(r[1]), r[2]) for r in csv.reader(lines) if r[0] != "V_over_V0"]
    sources = sorted({src for _, _, src in shocks})
    yield ("| library entry | measured | " + " | ".join(
        f"{lo}–{hi} GPa: points, median and largest error" for lo, hi in HUGONIOT_BANDS) + " |")
    yield "|---|---|" + "---|" * len(HUGONIOT_BANDS)
    for name in HUGONIOT_ENTRIES:
        rho, c0, s = library_eos(name)
        for k, src in enumerate(sources):
            cells = []
            for lo, hi in HUGONIOT_BANDS:
                errors = [rho * c0 * c0 * (1 - v) / (1 - s * (1 - v)) ** 2 / 1e9 / p - 1
                          for v, p, x in shocks if x == src and lo <= p < hi]
                if not errors:
                    cells.append("–")
                    continue
                worst = max(errors, key=abs)
                cells.append(f"{len(errors)}: {100 * statistics.median(errors):+.1f} %, "
                             f"largest {100 * worst:+.1f} %")
            yield f"| {name if k == 0 else ''} | {src} | " + " | ".join(cells) + " |"


# whipple-shots -----------------------------------------------------------------------------------
WHIPPLE_SHOTS = [  # (folder, --rows): normal shots of shields whose shots straddle the limit
    ("al6061-0.79mm", "angle=0;standoff=5.08;bumper_mat=AA6061-T6;bumper_thick=0.07874;"
                      "wall_mat=AA6061-T6"),
    ("al2024-0.81mm", "angle=0;standoff=5.08;bumper_mat=AA2024-T3;bumper_thick=0.081;"
                      "wall_mat=AA2024-T3;wall_thick=0.635"),
    ("al1100-0.64mm", "angle=0;standoff=5.08;bumper_mat=AA1100-O;bumper_thick=0.064;"
                      "wall_mat=AA7075-T6;wall_thick=1.27"),
]


def whipple_shot_campaigns(binary, work, prefix, sets):
    """A campaign of data/cases/whipple.yaml per shield of WHIPPLE_SHOTS (the cores at once),
    with these --set lines: the campaigns' folders, the runs' own seconds added up."""
    table = os.path.join(VALIDATION, "whipple-shots.csv")
    if not os.path.isfile(table):
        raise SystemExit(f"tables.py: error: {table}: no such file (the shared Whipple shots)")
    folders, seconds = [], 0.0
    for name, rows in WHIPPLE_SHOTS:
        out = os.path.join(work, prefix + name)
        cmd = [binary, "campaign", os.path.join(ROOT, "data/cases/whipple.yaml"), table,
               "--quiet", "--out", out, "--rows", rows]
        for x in sets:
            cmd += ["--set", x]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"tables.py: error: {' '.join(cmd)}: exit {r.returncode}\n{r.stderr}")
        with open(os.path.join(out, "predictions.csv")) as f:
            seconds += sum(float(x["wall_seconds"] or 0) for x in csv.DictReader(f))
        folders.append(out)
    return table, folders, seconds


def whipple_shots(binary, work, opts):
    """The shots of WHIPPLE_SHOTS (a campaign each, the cores at once), scored against the
    Christiansen equation per configuration; the figures into data/figures."""
    table, folders, seconds = whipple_shot_campaigns(binary, work, "whipple-", [])
    limits_csv = os.path.join(work, "whipple-limits.csv")
    limit_lines, limit_seconds = whipple_limits(binary, work, table, limits_csv)
    r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tools/post/whipple_scores.py"),
                        table] + folders + ["--markdown", "--figures",
                                            os.path.join(ROOT, "data", "figures"),
                                            "--limits", limits_csv],
                       capture_output=True, text=True, check=True)
    yield from r.stdout.splitlines()
    yield ""
    yield f"The runs' own times added up: {seconds / 60:.0f} min (one thread each)."
    yield ""
    yield from limit_lines
    yield ""
    yield (f"The searches' runs' own times added up: {limit_seconds / 60:.0f} min (one thread "
           f"each, the cores at once).")


# whipple-shots-sph: the same shots with SPH debris, crushed cells converted at half the first
# step (the sixteen shots' measured choice, whipple-sph-faces); the engine's wrong calls on each
# side beside its score. No limit search: with SPH debris its runs cost about seven times the
# point masses' (the 66 shots: 179 min against 25), some 8 hours for their 67 minutes.
WHIPPLE_SHOTS_SPH_SETS = ["fracture.debris=sph", "fracture.erosion_step_ratio=0.5"]


def whipple_shots_sph(binary, work, opts):
    """The shots of WHIPPLE_SHOTS with WHIPPLE_SHOTS_SPH_SETS, scored against the Christiansen
    equation per configuration, with the engine's wrong calls on each side; the figures into the
    work folder."""
    table, folders, seconds = whipple_shot_campaigns(binary, work, "whipple-sph-",
                                                     WHIPPLE_SHOTS_SPH_SETS)
    r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tools/post/whipple_scores.py"),
                        table] + folders + ["--markdown", "--errors", "--figures",
                                            os.path.join(work, "whipple-sph-figures")],
                       capture_output=True, text=True, check=True)
    yield from r.stdout.splitlines()
    yield ""
    yield (f"The runs' own times added up: {seconds / 60:.0f} min (one thread each, with "
           f"{', '.join('`--set ' + x + '`' for x in WHIPPLE_SHOTS_SPH_SETS)}).")


# The engine's ballistic limit on each figure's shield: (the campaign's folder, the wall's cm,
# the search between these multiples of the equation's critical diameter). A search's cost grows
# with the diameter (the bumper's core is 4 d wide at fixed cells): the 6061-T6 and 2024-T3
# shields are searched up to 2.5 times their critical diameters (at most 11 and 19 mm, 61,000
# and 135,000 tets), the 1100-O bumper's up to 1.2 times its 8.6–13.9 mm (2.5 times would reach
# 35 mm, 650,000 tets a run).
WHIPPLE_LIMITS = [("al6061-0.79mm", "0.3175", (0.6, 2.5)),
                  ("al2024-0.81mm", "0.635", (0.6, 2.5)),
                  ("al1100-0.64mm", "1.27", (0.6, 1.2))]
WHIPPLE_LIMIT_SPEEDS = [3.0, 5.0, 7.0]  # km/s
WHIPPLE_LIMIT_HEADER = [
    "| shield | speed | equation's critical diameter | engine's limit: largest NP, smallest P | "
    "runs |",
    "|---|---|---|---|---|"]


def limit_search_sets(run_key):
    """The --set lines of a campaign run's run.key but the sphere's diameter and speed: the
    shield's configuration exactly as the campaign made it."""
    sets = []
    with open(run_key) as f:
        for x in f:
            if x.rstrip("\n") == "text":  # the case's and the library's text follow
                break
            if x.startswith("set "):
                sets.append(x[4:].rstrip("\n"))
    return [x for x in sets if not x.startswith(("parameters.d=", "parameters.v="))]


def whipple_limit_cell(lo, hi, status, at_lo="0", at_hi="1"):
    """The engine's bracket in mm: both ends found (NP at lo, P at hi; the other way round is
    said), or the side the limit lies beyond."""
    if status == "ok":
        if (at_lo, at_hi) != ("0", "1"):
            return f"{lo * 1e3:.2f}–{hi * 1e3:.2f} mm, reversed (P at {lo * 1e3:.2f} mm)"
        return f"{lo * 1e3:.2f}–{hi * 1e3:.2f} mm"
    if "not met at both ends" in status:
        return f"above {hi * 1e3:.2f} mm (NP at {lo * 1e3:.2f} and {hi * 1e3:.2f} mm)"
    if "met at both ends" in status:
        return f"below {lo * 1e3:.2f} mm (P at {lo * 1e3:.2f} and {hi * 1e3:.2f} mm)"
    return "not found: " + status


def whipple_limits(binary, work, table, out_csv):
    """The engine's ballistic limit (`tetcontact limit --find parameters.d`, to 15 %) of the
    shields of WHIPPLE_LIMITS at WHIPPLE_LIMIT_SPEEDS, each searched between its multiples of
    the equation's critical diameter; the brackets into out_csv (the table's units: cm, km/s) for
    whipple_scores.py --limits, and the markdown lines."""
    from tools.post import whipple_scores as ws
    shots = ws.read_table(table)
    lines, seconds = list(WHIPPLE_LIMIT_HEADER), 0.0
    rows = []
    for folder, wall, (f_lo, f_hi) in WHIPPLE_LIMITS:
        campaign = os.path.join(work, "whipple-" + folder)
        with open(os.path.join(campaign, "predictions.csv")) as f:
            first = next((x for x in csv.DictReader(f) if x["wall_thick"] == wall), None)
        if first is None:
            raise SystemExit(f"tables.py: error: {campaign}: no shot with wall_thick {wall} "
                             f"(WHIPPLE_LIMITS)")
        shot = dict(shots[int(first["row"]) - 1])
        sets = limit_search_sets(os.path.join(campaign, "runs", first["folder"], "run.key"))
        for v in WHIPPLE_LIMIT_SPEEDS:
            shot["velocity"] = str(v)
            cm = 0.01
            dc = christiansen.critical_diameter(
                v * 1000.0, float(shot["bumper_thick"]) * cm, float(shot["wall_thick"]) * cm,
                float(shot["standoff"]) * cm, rho_p=float(shot["proj_density"]) * 1000.0,
                rho_b=float(shot["bumper_density"]) * 1000.0,
                sigma_pa=float(shot["wall_yield"]) * christiansen.KSI)
            # A folder per search: its runs are this search's (a resumed one's too).
            out = os.path.join(work, f"limit-{folder}-{wall}-{v:g}-{f_lo:g}-{f_hi:g}")
            cmd = [binary, "limit", os.path.join(ROOT, "data/cases/whipple.yaml"), "--quiet",
                   "--find", "parameters.d", "--between", f"{f_lo * dc:.6g}", f"{f_hi * dc:.6g}",
                   "--criterion", "perforated:wall", "--tolerance", "0.15", "--out", out,
                   "--set", f"parameters.v={v * 1000.0:g}"]
            for x in sets:
                cmd += ["--set", x]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode not in (0, 1):
                raise SystemExit(f"tables.py: error: {' '.join(cmd)}: exit {r.returncode}\n"
                                 f"{r.stderr}")
            with open(os.path.join(out, "limit.csv")) as f:
                b = next(csv.DictReader(f))
            lo, hi = float(b[K.LIMIT_LO]), float(b[K.LIMIT_HI])
            for path in glob.glob(os.path.join(out, "runs", "*", "*", "summary.json")):
                with open(path) as f:  # run now or earlier: each run's own time
                    seconds += float(get(json.load(f), K.WALL_SECONDS))
            ends = (b["criterion_lo"], b["criterion_hi"])
            cell = whipple_limit_cell(lo, hi, b[K.LIMIT_STATUS], *ends)
            ok = b[K.LIMIT_STATUS] != "ok" or ends == ("0", "1")
            rows.append({**{k: shot[k] for k in ws.KEY}, "velocity": f"{v:g}",
                         "lo": f"{lo / cm:.6g}", "hi": f"{hi / cm:.6g}",
                         "status": b[K.LIMIT_STATUS] if ok else "reversed bracket"})
            lines.append(f"| {shot['bumper_mat']} {float(shot['bumper_thick']) * 10:g} mm, "
                         f"{float(shot['standoff']) * 10:g} mm, {shot['wall_mat']} "
                         f"{float(shot['wall_thick']) * 10:g} mm | {v:g} km/s | "
                         f"{dc * 1e3:.2f} mm | {cell} | "
                         f"{b['runs']} |")
    with open(out_csv + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=ws.KEY + ["velocity", "lo", "hi", "status"])
        w.writeheader()
        w.writerows(rows)
    os.replace(out_csv + ".tmp", out_csv)
    return lines, seconds


# whipple-refined ---------------------------------------------------------------------------------
# The 6061-T6 family's shots whose verdicts are checked on a finer wall: its seven NP shots
# (2.54–4.57 mm walls) and nine P shots of 2.29–3.17 mm walls at 2.5–6.9 km/s (the thinner
# walls' runs cost twice as much).
WHIPPLE_REFINED_ROWS = "302,383,521,591,693,715,817,847,306,307,424,444,542,557,821,858"
WHIPPLE_REFINED = [  # (folder, label, --set)
    ("shipped", "2 cells through", []),
    ("wall6", "6 cells through", ['parameters.hw="= tw / 6"']),
]
WHIPPLE_REFINED_HEADER = [
    "| row (line) | wall | speed | measured | equation | shipped: verdict (mass through), "
    "thickness left, wall mass to particles | wall 6 cells through: the same | run time "
    "(shipped, finer) |",
    "|---|---|---|---|---|---|---|---|"]


def whipple_campaign(binary, table_path, out, rows, sets):
    """`tetcontact campaign data/cases/whipple.yaml` on these rows of the shot table with these
    --set values, into `out`: {row: (its predictions.csv row, its summary)}."""
    if not os.path.isfile(table_path):
        raise SystemExit(f"tables.py: error: {table_path}: no such file (the shared Whipple shots)")
    cmd = [binary, "campaign", os.path.join(ROOT, "data/cases/whipple.yaml"), table_path,
           "--quiet", "--out", out, "--rows", rows]
    for x in sets:
        cmd += ["--set", x]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"tables.py: error: {' '.join(cmd)}: exit {r.returncode}\n{r.stderr}")
    runs = {}
    with open(os.path.join(out, "predictions.csv")) as f:
        for x in csv.DictReader(f):
            with open(os.path.join(out, "runs", x["folder"], "summary.json")) as g:
                runs[int(x["row"])] = (x, json.load(g))
    return runs


def whipple_refined_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, wall mass turned into particles,
    run seconds) of one campaign run of the quarter model: the masses are the whole shield's
    (the mass through is measured so; the particles' are four times the quarter's)."""
    m = {x[K.NAME]: x[K.MEASURED] for x in get(s, K.REFERENCES)}
    eroded = sum(b["mass"] for b in get(s, K.FRACTURE_FROM_BODIES) if b["name"] == "wall")
    return (prediction["predicted:wall perforated"], m[K.MASS_THROUGH_WALL],
            m[K.WALL_THICKNESS_LEFT], 4.0 * eroded, float(prediction["wall_seconds"]))


def mg(kg):
    return f"{kg * 1e6:.1f} mg"


def whipple_refined_row(n, line, shot, equation, cells, fourth=mg):
    """One shot's row: `cells` its whipple_refined_cells (or whipple_tear_cells) on each mesh or
    setting, in the table's order; `fourth` shows each one's fourth number."""
    def mesh(verdict, through, left, x, _):
        shown = f"P ({mg(through)})" if verdict == "P" else verdict
        return f"{shown}, {left:.2f}, {fourth(x)}"
    return (f"| {n} ({line}) | {float(shot['wall_thick']) * 10:.2f} mm | "
            f"{float(shot['velocity']):.1f} km/s | {shot['result']} | {equation} | "
            + "".join(f"{mesh(*c)} | " for c in cells)
            + ", ".join(f"{c[4]:.0f} s" for c in cells) + " |")


def whipple_mesh_rows(binary, work, prefix, rows, meshes, of=whipple_refined_cells, fourth=mg):
    """The shots of `rows` (a --rows expression) on each mesh of `meshes` ((folder, label,
    --set)), a campaign each into work/prefix + folder: the table's rows (NP shots first, then by
    wall up and speed down: whipple_refined_row, each run's cells `of` its prediction and
    summary) and per shot (the measured verdict, the equation's, each mesh's)."""
    from tools.post import whipple_scores as ws
    table_path = os.path.join(VALIDATION, "whipple-shots.csv")
    runs = [whipple_campaign(binary, table_path, os.path.join(work, prefix + name), rows, sets)
            for name, _, sets in meshes]  # per mesh {row: (prediction row, summary)}
    table = ws.read_table(table_path)
    lines, verdicts = [], []
    for n in sorted(runs[0], key=lambda n: (table[n - 1]["result"], float(
            table[n - 1]["wall_thick"]), -float(table[n - 1]["velocity"]))):
        shot = table[n - 1]
        eq = ws.equation_says(shot)
        cells = [of(*r[n]) for r in runs]
        verdicts.append((shot["result"], eq, [c[0] for c in cells]))
        lines.append(whipple_refined_row(n, runs[0][n][0]["line"], shot, eq, cells, fourth))
    return lines, verdicts


def settings_header(settings, measures, times):
    """The header of a table of shots under several settings ((folder, label, --set)): each
    setting's `measures`, then the run times'."""
    return ["| row (line) | wall | speed | measured | equation | " + " | ".join(
        f"{label}: {measures}" for _, label, _ in settings) + f" | {times} |",
        "|---|---|---|---|---|" + "---|" * len(settings) + "---|"]


def whipple_refined(binary, work, opts, prefix="whipple-refined-", sets=(),
                    rows=WHIPPLE_REFINED_ROWS):
    """The shots of `rows` on the shipped mesh and with the rear wall's cells three times finer
    (6 through it instead of 2; the sphere and the bumper as shipped), with these --set lines on
    both: each verdict and the wall's thickness left beside the measured verdict and the
    equation's."""
    meshes = [(name, label, list(sets) + mesh) for name, label, mesh in WHIPPLE_REFINED]
    lines, verdicts = whipple_mesh_rows(binary, work, prefix, rows, meshes)
    yield from WHIPPLE_REFINED_HEADER
    yield from lines
    total = len(verdicts)
    eq = sum(e == m for m, e, _ in verdicts)
    shipped = sum(v[0] == m for m, _, v in verdicts)
    wall6 = sum(v[1] == m for m, _, v in verdicts)
    changed = sum(v[0] != v[1] for _, _, v in verdicts)
    yield ""
    yield (f"Right: the equation {eq} of {total}, the shipped mesh {shipped}, the finer wall "
           f"{wall6}; the verdict changes with the wall's refinement on {changed} of {total}.")


# With SPH debris, the ten of those shots at 5.5–6.9 km/s (four NP, six P): the speeds where the
# shipped wall's misses stop at half the wall. A finer wall's run took 6–40 minutes there on one
# thread beside other runs (the wall's eroded cells become particles): some four hours for all
# sixteen on 2 cores.
WHIPPLE_REFINED_SPH_ROWS = "302,383,521,591,306,307,424,444,542,557"


def whipple_refined_sph(binary, work, opts):
    """whipple_refined on WHIPPLE_REFINED_SPH_ROWS with SPH debris, crushed cells converted at half
    the first step (WHIPPLE_SHOTS_SPH_SETS: the shipped mesh's runs are the 66 shots' own)."""
    yield from whipple_refined(binary, work, opts, "whipple-refined-sph-", WHIPPLE_SHOTS_SPH_SETS,
                               WHIPPLE_REFINED_SPH_ROWS)


WHIPPLE_PARTS = ("projectile", "bumper", "wall")  # the shield's bodies, as whipple.yaml names them
WALL_ONLY_DUCTILE = ["materials.projectile.ductile_failure=false",
                     "materials.bumper.ductile_failure=false"]
WITHIN_FIT = [f"materials.{x}.ductile_failure_at_floor=false" for x in WHIPPLE_PARTS]

# The settings a hypervelocity user has to choose, each changed alone on the same sixteen shots at
# the shipped mesh (the mesh itself: whipple-refined).
WHIPPLE_DEFAULTS = [  # (folder, label, --set)
    ("shipped", "as shipped: average nodal pressure on, erosion at 10 % of the first step, "
                "sphere 8 cells across", []),
    ("anp-off", "average nodal pressure off", ["solver.average_nodal_pressure=false"]),
    ("erosion-0.2", "erosion at 20 % of the first step", ["fracture.erosion_step_ratio=0.2"]),
    ("erosion-0.05", "erosion at 5 % of the first step", ["fracture.erosion_step_ratio=0.05"]),
    ("sphere12", "sphere 12 cells across", ["parameters.np=12"]),
    ("wall-ductile-only", "ductile failure in the wall only (the sphere and the bumper fail by "
                          "spall and erosion)", WALL_ONLY_DUCTILE),
    ("clusters", "fragments as clusters (a failed cell joins a neighbour's particle that moves "
                 "with it)", ["fracture.fragments=clusters"]),
    ("clusters-sphere12", "fragments as clusters, sphere 12 cells across",
     ["fracture.fragments=clusters", "parameters.np=12"]),
    ("within-fit", "no ductile damage at the failure strain's floor (ductile failure only where "
                   "the set speaks; tension beyond it left to the spall strength)", WITHIN_FIT),
    ("wall-ductile-only-clusters", "ductile failure in the wall only, fragments as clusters",
     WALL_ONLY_DUCTILE + ["fracture.fragments=clusters"]),
]
WHIPPLE_DEFAULTS_HEADER = [
    "| setting | right (of the shots) | verdicts unlike the shipped | thickness left, mean: "
    "P shots, NP shots | wall mass to particles, all shots | the wall's momentum along the "
    "shot, all shots | largest fragment, median of the shots | cells failed ductilely, at the "
    "failure strain's floor / all, all shots: projectile, bumper, wall | run time: sum "
    "(largest) |",
    "|---|---|---|---|---|---|---|---|---|"]


def wall_momentum(s):
    """The whole rear wall's momentum along the shot (−z) at the end of a run, kg m/s."""
    wall = next(b for b in get(s, K.BODIES) if b["name"] == "wall")
    return -get(s, K.MESH_MULTIPLICITY) * wall["mass"] * wall["velocity"][2]


def whipple_defaults_row(label, shots):
    """One setting's row: `shots` a list of (measured verdict, the shipped run's verdict, this
    run's whipple_refined_cells, its wall_momentum, its largest fragment in kg, its
    ductile_parts)."""
    right = sum(cells[0] == measured for measured, _, cells, *_ in shots)
    unlike = sum(cells[0] != shipped for _, shipped, cells, *_ in shots)

    def mean_left(verdict):
        left = [cells[2] for measured, _, cells, *_ in shots if measured == verdict]
        return f"{statistics.mean(left):.2f}" if left else "–"
    eroded = sum(cells[3] for _, _, cells, *_ in shots)
    momentum = sum(x[3] for x in shots)
    largest = statistics.median(x[4] for x in shots)
    ductile = [tuple(map(sum, zip(*parts))) for parts in zip(*(x[5] for x in shots))]
    seconds = [cells[4] for _, _, cells, *_ in shots]
    return (f"| {label} | {right} of {len(shots)} | {unlike} | {mean_left('P')}, "
            f"{mean_left('NP')} | {eroded * 1e6:.1f} mg | {momentum:.2f} kg m/s | "
            f"{largest * 1e6:.2f} mg | {ductile_cell(ductile)} | {sum(seconds) / 60:.1f} min "
            f"({max(seconds):.0f} s) |")


def ductile_parts(s):
    """Per part of the shield (WHIPPLE_PARTS): (its cells failed by Johnson–Cook's ductile
    damage, of them those whose damage accrued mostly with the failure strain at its floor, the
    law's own value below it), the model's cells."""
    by = {b[K.NAME]: b for b in get(s, K.FRACTURE_FROM_BODIES)}
    return [(by[p][K.DUCTILE_FAILED], by[p][K.DUCTILE_FAILED_AT_FLOOR]) for p in WHIPPLE_PARTS]


def ductile_cell(parts):
    """'at the floor / all' for each part, in WHIPPLE_PARTS's order."""
    return ", ".join(f"{floor:,}/{failed:,}" for failed, floor in parts)


def largest_fragment(s):
    """The run's largest fragment through the bumper (the reference's measure), kg."""
    return next(x[K.MEASURED] for x in get(s, K.REFERENCES) if x[K.NAME] == K.LARGEST_FRAGMENT)


def whipple_defaults(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS as shipped and with each setting of WHIPPLE_DEFAULTS
    changed alone: per setting the verdicts right, those unlike the shipped, the wall's
    thickness left on the measured P and NP shots, and the cost."""
    from tools.post import whipple_scores as ws
    table_path = os.path.join(VALIDATION, "whipple-shots.csv")
    runs = {}  # folder → {row: (whipple_refined_cells, wall_momentum, largest_fragment,
    #                           ductile_parts)}
    for name, _, sets in WHIPPLE_DEFAULTS:
        out = os.path.join(work, "whipple-defaults-" + name)
        runs[name] = {n: (whipple_refined_cells(x, s), wall_momentum(s), largest_fragment(s),
                          ductile_parts(s))
                      for n, (x, s) in
                      whipple_campaign(binary, table_path, out, WHIPPLE_REFINED_ROWS, sets).items()}
    table = ws.read_table(table_path)
    yield from WHIPPLE_DEFAULTS_HEADER
    shipped = runs["shipped"]
    for name, label, _ in WHIPPLE_DEFAULTS:
        yield whipple_defaults_row(label, [(table[n - 1]["result"], shipped[n][0][0],
                                            *runs[name][n]) for n in sorted(shipped)])


# whipple-wall ------------------------------------------------------------------------------------
# Eight of the sixteen shots (four NP, four P; 3.0–6.9 km/s, 2.54–4.57 mm walls) on three
# rear-wall meshes, 2, 6 and 12 cells through it, with no ductile damage at the wall's failure
# strain's floor: whether the verdict converges as the wall is refined. The finer walls hold
# their cells uniform over a core 16 mm wide (the cloud's dense centre) instead of the
# standoff's width, and grow outside it as shipped.
WHIPPLE_WALL_ROWS = "383,591,693,817,307,444,542,821"
WALL_FINE = ["parameters.cw=16e-3"]
NO_FLOOR = ["materials.wall.ductile_failure_at_floor=false"]
WHIPPLE_WALL = [  # (folder, label, --set)
    ("wall2-nofloor", "2 through (the shipped mesh)", NO_FLOOR),
    ("wall6-nofloor", "6 through", ['parameters.hw="= tw / 6"'] + WALL_FINE + NO_FLOOR),
    ("wall12-nofloor", "12 through", ['parameters.hw="= tw / 12"'] + WALL_FINE + NO_FLOOR),
]
WHIPPLE_WALL_HEADER = settings_header(
    WHIPPLE_WALL, "verdict (mass through), thickness left, wall mass to particles",
    "run time (each mesh)")


def whipple_settings_rows(binary, work, prefix, rows, settings, header, of=whipple_refined_cells,
                          fourth=mg):
    """The table of the shots of `rows` under each of `settings` (whipple_mesh_rows, its cells
    `of` each run and `fourth` shown), then how many each setting gets right beside the
    equation."""
    lines, verdicts = whipple_mesh_rows(binary, work, prefix, rows, settings, of, fourth)
    yield from header
    yield from lines
    right = [sum(v[i] == m for m, _, v in verdicts) for i in range(len(settings))]
    yield ""
    yield (f"Right, of {len(verdicts)}: the equation {sum(e == m for m, e, _ in verdicts)}; "
           + ", ".join(f"{label} {k}" for (_, label, _), k in zip(settings, right)) + ".")


def whipple_wall(binary, work, opts):
    """The shots of WHIPPLE_WALL_ROWS on each rear-wall mesh of WHIPPLE_WALL: each verdict (and
    mass through), the wall's thickness left and its mass turned into particles beside the
    measured verdict and the equation's, and how many each mesh gets right."""
    yield from whipple_settings_rows(binary, work, "whipple-wall-", WHIPPLE_WALL_ROWS,
                                     WHIPPLE_WALL, WHIPPLE_WALL_HEADER)


# whipple-tear ------------------------------------------------------------------------------------
# How long the run goes on once the debris has reached the wall (`tear`): the sixteen shots with
# the shipped 15 µs, and with 60 µs, with and without ductile damage at the failure strain's
# floor. Beside each verdict the wall's bulge at the end: whether the wall was still moving
# when the shipped run stopped, and how far it went.
WHIPPLE_TEAR = [  # (folder, label, --set)
    ("tear15", "tear 15 µs (shipped)", []),
    ("tear60", "tear 60 µs", ["parameters.tear=60e-6"]),
    ("tear60-within-fit", "tear 60 µs, no ductile damage at the floor",
     ["parameters.tear=60e-6"] + WITHIN_FIT),
]
WHIPPLE_TEAR_HEADER = settings_header(
    WHIPPLE_TEAR, "verdict (mass through), thickness left, bulge", "run time (each setting)")


def whipple_tear_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, the wall's bulge in m, run
    seconds) of one campaign run."""
    m = {x[K.NAME]: x[K.MEASURED] for x in get(s, K.REFERENCES)}
    return (prediction["predicted:wall perforated"], m[K.MASS_THROUGH_WALL],
            m[K.WALL_THICKNESS_LEFT], m[K.WALL_BULGE], float(prediction["wall_seconds"]))


def mm(m):
    return f"{m * 1e3:.2f} mm"


def whipple_tear(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS with each `tear` of WHIPPLE_TEAR: each verdict (and mass
    through), the wall's thickness left and its bulge at the end beside the measured verdict and
    the equation's, and how many each setting gets right."""
    yield from whipple_settings_rows(binary, work, "whipple-tear-", WHIPPLE_REFINED_ROWS,
                                     WHIPPLE_TEAR, WHIPPLE_TEAR_HEADER, whipple_tear_cells, mm)


# whipple-debris ----------------------------------------------------------------------------------
# What the debris is made of (fracture.debris): the sixteen shots with Dobritsa et al.'s point
# masses (shipped) and with SPH particles that keep their cells' material. Beside each verdict
# the share of the initial energy booked as contact work: the debris's exchanges with the wall
# and the bumper.
WHIPPLE_DEBRIS = [  # (folder, label, --set)
    ("points", "point masses (shipped)", []),
    ("sph", "SPH particles", ["fracture.debris=sph"]),
    ("sph-erosion-0.5", "SPH particles, crushed cells converted at 50 % of the first step",
     ["fracture.debris=sph", "fracture.erosion_step_ratio=0.5"]),
    ("kernel-erosion-0.75", "the same, converted at 75 % of the first step",
     ["fracture.debris=sph", "fracture.erosion_step_ratio=0.75"]),
]
WHIPPLE_DEBRIS_HEADER = settings_header(
    WHIPPLE_DEBRIS, "verdict (mass through), thickness left, contact work / initial energy",
    "run time (each setting)")


def whipple_debris_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, contact work over the initial
    energy, run seconds) of one campaign run."""
    m = {x[K.NAME]: x[K.MEASURED] for x in get(s, K.REFERENCES)}
    share = -get(s, K.ENERGY_CONTACT_WORK) / get(s, K.ENERGY_TOTAL_INITIAL)
    return (prediction["predicted:wall perforated"], m[K.MASS_THROUGH_WALL],
            m[K.WALL_THICKNESS_LEFT], share, float(prediction["wall_seconds"]))


def percent(x):
    return f"{100 * x:.0f} %"


def whipple_debris(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS with each debris of WHIPPLE_DEBRIS: each verdict (and
    mass through), the wall's thickness left and the contact work's share of the initial energy
    beside the measured verdict and the equation's, and how many each gets right."""
    yield from whipple_settings_rows(binary, work, "whipple-debris-", WHIPPLE_REFINED_ROWS,
                                     WHIPPLE_DEBRIS, WHIPPLE_DEBRIS_HEADER, whipple_debris_cells,
                                     percent)


# whipple-sph-faces -------------------------------------------------------------------------------
# SPH debris meeting the bodies' faces through its kernel (the particles' pressure and viscosity
# pass to the faces' nodes) on the sixteen shots; the whipple-debris table's SPH column is the
# same debris meeting the faces by contact.
WHIPPLE_SPH_FACES = [  # (folder, label, --set)
    ("kernel", "SPH particles, faces through the kernel", ["fracture.debris=sph"]),
    ("kernel-erosion-0.5", "the same, crushed cells converted at 50 % of the first step",
     ["fracture.debris=sph", "fracture.erosion_step_ratio=0.5"]),
    ("kernel-erosion-0.75", "the same, converted at 75 % of the first step",
     ["fracture.debris=sph", "fracture.erosion_step_ratio=0.75"]),
]
WHIPPLE_SPH_FACES_HEADER = settings_header(
    WHIPPLE_SPH_FACES, "verdict (mass through), thickness left, contact work / initial energy",
    "run time")


def whipple_sph_faces(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS with SPH debris meeting the faces through its kernel:
    each verdict (and mass through), the wall's thickness left and the contact work's share of
    the initial energy beside the measured verdict and the equation's."""
    yield from whipple_settings_rows(binary, work, "whipple-sph-faces-", WHIPPLE_REFINED_ROWS,
                                     WHIPPLE_SPH_FACES, WHIPPLE_SPH_FACES_HEADER,
                                     whipple_debris_cells, percent)


# whipple-erosion-reference -----------------------------------------------------------------------
# Crushed cells converted at half the first step, the whole model's (its smallest cell's: the
# sphere's) or each body's own (fracture.erosion_reference: body; the wall's cells, three to seven
# times the sphere's step, then convert at their own half): the sixteen shots with SPH debris.
WHIPPLE_EROSION_REFERENCE = [  # (folder, label, --set)
    ("model", "half the model's first step (the 66 shots' setting)", WHIPPLE_SHOTS_SPH_SETS),
    ("body", "half each body's own first step",
     WHIPPLE_SHOTS_SPH_SETS + ["fracture.erosion_reference=body"]),
]
WHIPPLE_EROSION_REFERENCE_HEADER = settings_header(
    WHIPPLE_EROSION_REFERENCE, "verdict (mass through), thickness left, steps", "run time")


def whipple_step_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, steps, run seconds) of one campaign
    run."""
    m = {x[K.NAME]: x[K.MEASURED] for x in get(s, K.REFERENCES)}
    return (prediction["predicted:wall perforated"], m[K.MASS_THROUGH_WALL],
            m[K.WALL_THICKNESS_LEFT], get(s, K.STEPS), float(prediction["wall_seconds"]))


def whipple_erosion_reference(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS with SPH debris, crushed cells converted at half the
    model's or each body's first step: each verdict (and mass through), the wall's thickness left
    and the steps beside the measured verdict and the equation's."""
    yield from whipple_settings_rows(binary, work, "whipple-erosion-reference-",
                                     WHIPPLE_REFINED_ROWS, WHIPPLE_EROSION_REFERENCE,
                                     WHIPPLE_EROSION_REFERENCE_HEADER, whipple_step_cells,
                                     lambda n: f"{n:,}")


# whipple-sph-step --------------------------------------------------------------------------------
# The SPH particles' own stable step, k h / (c + 1.2 (α c + β max μ)) times the cfl, sets nearly
# every step of a shot with SPH debris: the sixteen shots with crushed cells converted at half the
# first step (the 66 shots' setting), at the shipped k = 0.6 (0.14 h/c at rest) and at twice it.
WHIPPLE_SPH_STEP = [  # (folder, label, --set)
    ("factor-0.6", "step factor 0.6 (shipped)", WHIPPLE_SHOTS_SPH_SETS),
    ("factor-1.2", "step factor 1.2", WHIPPLE_SHOTS_SPH_SETS + ["fracture.sph.step_factor=1.2"]),
]
WHIPPLE_SPH_STEP_HEADER = settings_header(
    WHIPPLE_SPH_STEP, "verdict (mass through), thickness left, steps, largest balance error",
    "run time")


def whipple_sph_step_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, (steps, largest balance error), run
    seconds) of one campaign run."""
    verdict, through, left, steps, seconds = whipple_step_cells(prediction, s)
    return verdict, through, left, (steps, get(s, K.ENERGY_BALANCE_ERROR_MAX)), seconds


def steps_and_balance(x):
    return f"{x[0]:,}, {x[1]:.1e}"


def whipple_sph_step(binary, work, opts):
    """The shots of WHIPPLE_REFINED_ROWS with SPH debris at each step factor of WHIPPLE_SPH_STEP:
    each verdict (and mass through), the wall's thickness left, the steps and the largest balance
    error beside the measured verdict and the equation's."""
    yield from whipple_settings_rows(binary, work, "whipple-sph-step-", WHIPPLE_REFINED_ROWS,
                                     WHIPPLE_SPH_STEP, WHIPPLE_SPH_STEP_HEADER,
                                     whipple_sph_step_cells, steps_and_balance)


# whipple-tillotson -------------------------------------------------------------------------------
# The equation of state of expanded and hot debris: the shots of the sixteen at 6 km/s and above,
# with SPH debris, every body with its library entry's Mie–Grüneisen EOS (shipped) and with its
# Tillotson constants (eos: {type: tillotson}).
WHIPPLE_FAST_ROWS = "302,383,521,306,307,424,444"
WHIPPLE_TILLOTSON = [  # (folder, label, --set)
    ("mie-gruneisen", "Mie–Grüneisen (shipped)", ["fracture.debris=sph"]),
    ("tillotson", "Tillotson", ["fracture.debris=sph"]
     + [f"materials.{x}.eos.type=tillotson" for x in WHIPPLE_PARTS]),
]
WHIPPLE_TILLOTSON_HEADER = settings_header(
    WHIPPLE_TILLOTSON,
    "verdict (mass through), thickness left, cloud speed, steps, largest balance error",
    "run time (each EOS)")


def whipple_eos_cells(prediction, s):
    """(verdict, mass through the wall, wall thickness left, (the debris cloud's leading-edge
    speed, steps, the largest balance error), run seconds) of one campaign run."""
    m = {x[K.NAME]: x[K.MEASURED] for x in get(s, K.REFERENCES)}
    return (prediction["predicted:wall perforated"], m[K.MASS_THROUGH_WALL],
            m[K.WALL_THICKNESS_LEFT],
            (m[K.DEBRIS_SPEED], get(s, K.STEPS), get(s, K.ENERGY_BALANCE_ERROR_MAX)),
            float(prediction["wall_seconds"]))


def speed_steps_balance(x):
    return f"{x[0] / 1e3:.2f} km/s, {x[1]:,}, {g(x[2])}"


def whipple_tillotson(binary, work, opts):
    """The shots of WHIPPLE_FAST_ROWS with SPH debris under each EOS of WHIPPLE_TILLOTSON: each
    verdict (and mass through), the wall's thickness left, the cloud's speed, the steps and the
    largest balance error beside the measured verdict and the equation's, and how many each
    gets right."""
    yield from whipple_settings_rows(binary, work, "whipple-tillotson-", WHIPPLE_FAST_ROWS,
                                     WHIPPLE_TILLOTSON, WHIPPLE_TILLOTSON_HEADER,
                                     whipple_eos_cells, speed_steps_balance)


# whipple, whipple-mesh, whipple-hole -------------------------------------------------------------
WHIPPLE_COARSE = ["parameters.hb=1.0e-3", "parameters.hw=2.0e-3", "parameters.np=6",
                  "parameters.tear=5.0e-6"]
WHIPPLE_ROWS = [  # (what, --set values): the test's two shields
    ("2 mm wall, 15 mm behind", ["parameters.S=15e-3", "parameters.tw=2e-3", "parameters.ww=30e-3"]),
    ("8 mm wall, 30 mm behind", ["parameters.S=30e-3", "parameters.tw=8e-3"]),
]
WHIPPLE_HEADER = [
    "| shield (4 mm sphere, 6.5 km/s, 1 mm bumper) | d / d_c (Christiansen) | steps, wall time | "
    "hole | leading edge | cone half-angle | debris (particles) | largest fragment | wall "
    "perforated: mass through | energy balance |",
    "|---|---|---|---|---|---|---|---|---|---|"]


def perforated(m):
    return (f"{'yes' if m[K.WALL_PERFORATED] else 'no'}: "
            f"{m[K.MASS_THROUGH_WALL] * 1e6:.1f} mg")


def whipple_row(what, s):
    """One shield: the run beside Christiansen's critical diameter for its parameters."""
    p = get(s, K.PARAMETERS)  # whipple.yaml's parameters, by their names there
    dc = christiansen.critical_diameter(p["v"], p["tb"], p["tw"], p["S"], theta_deg=p["theta"])
    m = measures(s)
    return (f"| {what} | {p['d'] / dc:.2f} ({p['d'] * 1e3:g} / {dc * 1e3:.2f} mm) | "
            f"{get(s, K.STEPS):,}, {get(s, K.WALL_SECONDS):.0f} s | "
            f"{m[K.HOLE_DIAMETER] * 1e3:.1f} mm | {m[K.DEBRIS_SPEED]:,.0f} m/s | "
            f"{m[K.DEBRIS_CONE_ANGLE]:.0f}° | {m[K.DEBRIS_MASS] * 1e3:.3f} g "
            f"({m[K.DEBRIS_PARTICLE_MASS] * 1e3:.3f} g) | {m[K.LARGEST_FRAGMENT] * 1e6:.2f} mg | "
            f"{perforated(m)} | {g(get(s, K.ENERGY_BALANCE_ERROR))} |")


def whipple(binary, work, opts):
    """The Whipple shield's coarse runs against Christiansen's critical diameter."""
    yield from WHIPPLE_HEADER
    for k, (what, keys) in enumerate(WHIPPLE_ROWS):
        s, _ = run(binary, os.path.join(ROOT, "data/cases/whipple.yaml"),
                   os.path.join(work, f"whipple{k}"), sets(WHIPPLE_COARSE + keys))
        yield whipple_row(what, s)


WHIPPLE_MESHES = [  # (what, --set values): the shipped shield on three meshes, the same geometry
    ("coarse: 1 cell through each plate, sphere 6 across",
     ["parameters.hb=1.0e-3", "parameters.hw=2.0e-3", "parameters.np=6"]),
    ("default: 2 through each plate, 8 across (quarter, graded plates)", []),
    ("the same cells, whole shield, uniform plates",
     ["symmetry=[]", "parameters.cb=24e-3", "parameters.cw=60e-3"]),
]
WHIPPLE_HOLE_MESHES = WHIPPLE_MESHES + [  # and a fourth: three cells through the bumper
    ("fine: 3 through the bumper (2 through the wall), 12 across",
     ["parameters.hb=0.333e-3", "parameters.np=12"]),
]
WHIPPLE_MESH_HEADER = [
    "| mesh | tets | steps, wall time (2 threads) | hole | leading edge | cone half-angle | "
    "debris | wall perforated: mass through | cells failed (ductile) | of them at the failure "
    "strain's floor / all: projectile, bumper, wall | energy balance |",
    "|---|---|---|---|---|---|---|---|---|---|---|"]
WHIPPLE_HOLE_HEADER = [
    "| mesh | tets | steps, wall time (2 threads) | hole at 8 µs | leading edge | "
    "cells failed (ductile) | of them at the failure strain's floor / all: projectile, bumper, "
    "wall | energy balance |",
    "|---|---|---|---|---|---|---|---|"]


def whipple_mesh_row(what, s):
    m = measures(s)
    return (f"| {what} | {get(s, K.MESH_TETS):,} | {get(s, K.STEPS):,}, "
            f"{get(s, K.WALL_SECONDS):.0f} s | {m[K.HOLE_DIAMETER] * 1e3:.1f} mm | "
            f"{m[K.DEBRIS_SPEED]:,.0f} m/s | {m[K.DEBRIS_CONE_ANGLE]:.0f}° | "
            f"{m[K.DEBRIS_MASS] * 1e3:.3f} g | {perforated(m)} | "
            f"{get(s, K.FRACTURE_DUCTILE_FAILED):,} | {ductile_cell(ductile_parts(s))} | "
            f"{g(get(s, K.ENERGY_BALANCE_ERROR))} |")


def whipple_hole_row(what, s):
    m = measures(s)
    return (f"| {what} | {get(s, K.MESH_TETS):,} | {get(s, K.STEPS):,}, "
            f"{get(s, K.WALL_SECONDS):.0f} s | {m[K.HOLE_DIAMETER] * 1e3:.1f} mm | "
            f"{m[K.DEBRIS_SPEED]:,.0f} m/s | {get(s, K.FRACTURE_DUCTILE_FAILED):,} | "
            f"{ductile_cell(ductile_parts(s))} | {g(get(s, K.ENERGY_BALANCE_ERROR))} |")


def whipple_runs(binary, work, meshes, extra, prefix):
    """The Whipple case once per mesh (2 threads, `extra` --set values): (label, summary)."""
    for k, (what, keys) in enumerate(meshes):
        s, _ = run(binary, os.path.join(ROOT, "data/cases/whipple.yaml"),
                   os.path.join(work, f"{prefix}{k}"), ["--threads", "2"] + sets(extra + keys))
        yield what, s


def whipple_mesh(binary, work, opts):
    """The shipped Whipple shield on three meshes: the measures and the run time of each."""
    yield from WHIPPLE_MESH_HEADER
    for what, s in whipple_runs(binary, work, WHIPPLE_MESHES, [], "mesh"):
        yield whipple_mesh_row(what, s)


def whipple_hole(binary, work, opts):
    """The bumper's hole at 8 µs (the debris has just reached the wall) on four meshes."""
    yield from WHIPPLE_HOLE_HEADER
    for what, s in whipple_runs(binary, work, WHIPPLE_HOLE_MESHES, ["parameters.end=8.0e-6"],
                                "hole"):
        yield whipple_hole_row(what, s)


TABLES = {"stability": stability, "micro": micro, "profile": profile, "ccd": ccd, "verify": verify,
          "verify-full": verify_full, "threads": threads, "mpi": mpi, "whipple": whipple,
          "whipple-mesh": whipple_mesh, "whipple-hole": whipple_hole, "strength": strength,
          "taylor-tests": taylor_tests, "taylor-temper": taylor_temper, "whipple-shots": whipple_shots,
          "whipple-shots-sph": whipple_shots_sph,
          "whipple-refined": whipple_refined, "whipple-refined-sph": whipple_refined_sph,
          "whipple-defaults": whipple_defaults,
          "whipple-wall": whipple_wall, "whipple-tear": whipple_tear,
          "whipple-debris": whipple_debris, "whipple-sph-faces": whipple_sph_faces,
          "whipple-erosion-reference": whipple_erosion_reference,
          "whipple-sph-step": whipple_sph_step,
          "whipple-tillotson": whipple_tillotson,
          "hugoniot": hugoniot}
assert list(TABLES) == NAMES


# The machine and the build -----------------------------------------------------------------------
def cpu(cpuinfo="/proc/cpuinfo"):
    """(CPU model, core count) from /proc/cpuinfo: its first model name, its processor
    entries."""
    model, cores = None, 0
    with open(cpuinfo) as f:
        for line in f:
            key, _, value = line.partition(":")
            key = key.strip()
            if key == "processor":
                cores += 1
            elif key in ("model name", "Model", "Hardware") and model is None:
                model = " ".join(value.split())
    return model or "an unknown CPU", cores


def cmake_build(build_dir):
    """(compiler, build type) from a CMake build folder: CMakeCache.txt's CMAKE_BUILD_TYPE and
    CMakeFiles/<version>/CMakeCXXCompiler.cmake's compiler id and version; 'unknown' for what is
    not there."""
    build_type, compiler = "unknown", "unknown compiler"
    cache = os.path.join(build_dir, "CMakeCache.txt")
    if os.path.isfile(cache):
        m = re.search(r"^CMAKE_BUILD_TYPE:\w+=(.*)$", open(cache).read(), re.M)
        if m and m.group(1).strip():
            build_type = m.group(1).strip()
    for path in sorted(glob.glob(os.path.join(build_dir, "CMakeFiles", "*", "CMakeCXXCompiler.cmake"))):
        text = open(path).read()
        cid = re.search(r'^set\(CMAKE_CXX_COMPILER_ID "([^"]*)"\)', text, re.M)
        ver = re.search(r'^set\(CMAKE_CXX_COMPILER_VERSION "([^"]*)"\)', text, re.M)
        if cid:
            compiler = cid.group(1) + (" " + ver.group(1) if ver else "")
    return compiler, build_type


def git_commit(source):
    """The source tree's commit (short), '+ local changes' when tracked files differ from it."""
    try:
        head = subprocess.run(["git", "-C", source, "rev-parse", "--short=10", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", source, "status", "--porcelain",
                                "--untracked-files=no"], capture_output=True, text=True,
                               check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + (" + local changes" if dirty else "")


def machine_line(name, binary, cpuinfo="/proc/cpuinfo", build_dir=None, source=ROOT):
    """The line above a generated table: what measured it and how to make it again."""
    model, cores = cpu(cpuinfo)
    try:
        version = subprocess.run([binary, "--version"], capture_output=True,
                                 text=True).stdout.strip().splitlines()[0]
    except (OSError, IndexError):
        version = "tetcontact (no --version)"
    compiler, build_type = cmake_build(build_dir or os.path.dirname(os.path.abspath(binary)))
    return (f"Measured on {model} ({cores} cores) with {version} ({compiler}, {build_type} "
            f"build, commit {git_commit(source)}); made by `tools/docs/tables.py {name} BINARY "
            f"--write`.")


# The generated blocks ----------------------------------------------------------------------------
class MarkerError(Exception):
    """A table's markers missing or twice; the message names the file."""


def markers(name):
    return f"<!-- BEGIN generated: {name} -->", f"<!-- END generated: {name} -->"


def doc_files(root):
    """README.md and every docs/**/*.md under `root`."""
    files = [os.path.join(root, "README.md")]
    files += sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True))
    return [f for f in files if os.path.isfile(f)]


def locate(name, root):
    """The one file holding the table's BEGIN and END markers, each once, BEGIN first;
    MarkerError otherwise."""
    begin, end = markers(name)
    holders = []
    for path in doc_files(root):
        text = open(path, encoding="utf-8").read()
        nb, ne = text.count(begin), text.count(end)
        if nb or ne:
            holders.append(path)
            if nb > 1 or ne > 1:
                raise MarkerError(f"{path}: {begin if nb > 1 else end} appears "
                                  f"{max(nb, ne)} times")
            if nb == 0:
                raise MarkerError(f"{path}: {end} without {begin}")
            if ne == 0:
                raise MarkerError(f"{path}: {begin} without {end}")
            if text.index(end) < text.index(begin):
                raise MarkerError(f"{path}: {end} comes before {begin}")
    if not holders:
        raise MarkerError(f"{os.path.join(root, 'README.md')} and {os.path.join(root, 'docs')}"
                          f"/**/*.md: no {begin}")
    if len(holders) > 1:
        raise MarkerError(f"{' and '.join(holders)}: {begin} appears in {len(holders)} files")
    return holders[0]


def replace_block(text, name, body):
    """The text with the lines between the table's markers replaced by `body` (the markers'
    lines kept). The markers must be there once each (locate checks)."""
    begin, end = markers(name)
    i = text.index(begin) + len(begin)
    j = text.index(end)
    line_start = text.rfind("\n", 0, j) + 1  # whatever precedes END on its line stays
    return text[:i] + "\n" + body.rstrip("\n") + "\n\n" + text[line_start:]


def write_block(name, body, root):
    """Rewrites the table's block in the one file holding it (through a temporary file);
    returns that file."""
    path = locate(name, root)
    text = open(path, encoding="utf-8").read()
    new = replace_block(text, name, body)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(new)
    os.replace(tmp, path)
    return path


def block(name, binary, lines, **machine):
    """The block's contents: the machine line, a blank line, the table."""
    return machine_line(name, binary, **machine) + "\n\n" + "\n".join(lines)


def make(name, binary, work, opts):
    """Runs one table, printing each line as it comes; returns its lines."""
    lines = []
    print(f"## {name}", flush=True)
    for line in TABLES[name](binary, os.path.join(work, name), opts):
        print(line, flush=True)
        lines.append(line)
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("table", choices=NAMES + ["all"])
    ap.add_argument("binary")
    ap.add_argument("--work", help="keep the runs here (default: a temporary folder)")
    ap.add_argument("--write", action="store_true",
                    help="rewrite the table's generated block in README.md or docs/")
    ap.add_argument("--docs-root", default=ROOT,
                    help="the folder holding README.md and docs/ (default: the repository)")
    ap.add_argument("--cases", nargs="*", help="threads: only the cases whose file names "
                    "contain one of these")
    a = ap.parse_args(argv)
    names = NAMES if a.table == "all" else [a.table]
    if a.write:  # every marker checked before the first run
        try:
            for name in names:
                locate(name, a.docs_root)
        except MarkerError as e:
            print(f"tables.py: error: {e}", file=sys.stderr)
            return 2
    binary = os.path.abspath(a.binary)
    if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
        print(f"tables.py: error: {a.binary}: no such program", file=sys.stderr)
        return 2
    work = a.work or tempfile.mkdtemp(prefix="tables-")
    for name in names:
        lines = make(name, binary, work, a)
        if a.write:
            path = write_block(name, block(name, binary, lines), a.docs_root)
            print(f"written: {name} in {path}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
