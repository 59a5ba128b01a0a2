"""Every command line of the manual holds: each ```sh block of README.md, docs/ and
data/*/README.md, each `tetcontact ...` quoted in their prose, and each tool's usage in
docs/guide/commands.md's table.

Run as far as a test affords (test_every_line_with_a_case_runs): each `run` line on a shipped case
(also under `mpirun`) and each run of each `sweep` line, set up and stepped ten steps
(solver.max_steps); each `profile` line over five steps; each `limit` line with `--check`; each
`ccd` line on a shipped query set as given. Checked without running the long work:

- `build/tetcontact run CASE [--set ...]` (also under `mpirun`): the case and its overrides pass
  `tetcontact check` (the file, the keys, the meshes, the first step); its other options are
  the run command's.
- `build/tetcontact campaign ...`: run with `--check` (every row makes a valid case; nothing
  runs).
- `limit`, `sweep` and the other commands: the case, when they name one, passes `check` with
  the command's `--set`s, and every option the line gives is one the command lists in its
  `--help`.
- `/usr/bin/python3 tools/...py ...` and the table's `tools/...py ...`: the script exists, every
  option is in its `--help`, and the line gives at least the positional arguments its usage
  requires.
- `make TARGET`: the Makefile has the target.

A command of a block that names a placeholder (CASE.yaml, DIR, ...) instead of a file is checked
for its options only."""
import csv
import glob
import json
import os
import re
import shlex
import subprocess

import pytest

from conftest import PYTHON, ROOT

DOCS = ([os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "**", "*.md"),
                                                             recursive=True))
        + sorted(glob.glob(os.path.join(ROOT, "data", "*", "README.md"))))


def unbracket(word):
    """A synopsis's word without the brackets that mark it optional ("[--set" → "--set",
    "x=30]" → "x=30"); a value's own brackets stay ("symmetry=[]")."""
    while word.startswith("[") and word.count("[") > word.count("]"):
        word = word[1:]
    while word.endswith("]") and word.count("]") > word.count("["):
        word = word[:-1]
    return word


def sh_commands():
    """(file, line, argv) of every command in the ```sh blocks, continuations joined, comments
    dropped."""
    out = []
    for path in DOCS:
        lines = open(path).read().splitlines()
        inside, start, pending = False, 0, ""
        for i, line in enumerate(lines, 1):
            if line.strip().startswith("```"):
                inside = line.strip() == "```sh" and not inside
                pending = ""
                continue
            if not inside:
                continue
            text = pending + line
            if text.rstrip().endswith("\\"):
                pending = text.rstrip()[:-1] + " "
                start = start or i
                continue
            pending = ""
            # A synopsis marks what is optional with brackets: the words without them.
            argv = [unbracket(w) for w in shlex.split(text, comments=True)]
            argv = [w for w in argv if w and w != "|"]
            if argv:
                out.append((os.path.relpath(path, ROOT), start or i, argv))
            start = 0
    return out


def table_tools():
    """(file, line, argv) of each tool usage in the first column of commands.md's tool table."""
    path = os.path.join(ROOT, "docs", "guide", "commands.md")
    out = []
    for i, line in enumerate(open(path).read().splitlines(), 1):
        m = re.match(r"\| `(tools/[^`]+\.py[^`]*)` \|", line)
        if m:
            usage = m.group(1).replace("\\|", "|")
            out.append(("docs/guide/commands.md", i, shlex.split(usage)))
    return out


def inline_commands():
    """(file, line, argv) of each `tetcontact SUB ...` quoted in the prose."""
    out = []
    pattern = re.compile(r"`((?:build/)?tetcontact [a-z]+[^`]*)`")
    for path in DOCS:
        for i, line in enumerate(open(path).read().splitlines(), 1):
            for m in pattern.finditer(line):
                argv = [unbracket(w) for w in shlex.split(m.group(1))]
                argv = [w for w in argv if w and w != "|"]
                if argv[0] == "tetcontact":
                    argv[0] = "build/tetcontact"
                out.append((os.path.relpath(path, ROOT), i, argv))
    return out


COMMANDS = sh_commands() + inline_commands()


def is_placeholder(arg):
    """CASE.yaml, DIR, TABLE.csv, my-case.yaml, …: a name the reader substitutes (a case of the
    manual's own is under data/)."""
    stem = os.path.basename(arg).split(".")[0]
    return stem.isupper() or "…" in arg or "..." in arg or not arg.startswith("data/")


def options(argv):
    return [a.split("=")[0] for a in argv if a.startswith("--")]


def sets(argv):
    """The --set overrides of a line, but a placeholder's (KEY=VALUE)."""
    return [a for k, a in zip(argv, argv[1:]) if k == "--set" and not a.split("=")[0].isupper()]


def help_text(cmd):
    r = subprocess.run(cmd + ["--help"], capture_output=True, text=True, cwd=ROOT)
    return r.stdout + r.stderr


def check_case(binary, case, overrides, where):
    r = subprocess.run([binary, "check", case] + [x for s in overrides for x in ("--set", s)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, f"{where}: tetcontact check {case}: {r.stderr}"


def required_positionals(usage_line, script):
    """The positional arguments a tool's usage line requires, and whether it takes more (a
    `...` or an optional one)."""
    words = usage_line.split(script, 1)[1].split()
    required, more = 0, False
    depth = 0
    for w in words:
        if w.startswith("["):
            depth += w.count("[")
        if depth == 0 and not w.startswith("-") and not w.startswith("("):
            required += 1
            more = more or w.endswith("...")
        if w.startswith("-") and depth == 0:
            break
        depth -= w.count("]")
        if depth < 0:
            depth = 0
    return required, more


def check_tool(argv, where):
    script = next(a for a in argv if a.endswith(".py"))
    path = os.path.join(ROOT, script)
    assert os.path.isfile(path), f"{where}: {script}: no such tool"
    text = help_text([PYTHON, path])
    for o in options(argv):
        assert o in text, f"{where}: {script} lists no option {o} in its --help"
    name = os.path.basename(script)
    usage = next((line for line in text.splitlines() if line.strip().startswith(name + " ")), None)
    if usage is None:
        return
    required, _ = required_positionals(usage, name)
    given = 0
    for a in argv[argv.index(script) + 1:]:
        if a.startswith("-"):
            break
        given += 1
    assert given >= required, (f"{where}: {' '.join(argv)} gives {given} positional arguments, "
                               f"{name}'s usage requires {required}: {usage.strip()}")


def test_the_manual_has_commands():
    """The scan sees the manual's blocks (a broken scan would check nothing)."""
    tetcontact = [c for c in COMMANDS if "build/tetcontact" in c[2]]
    assert len(tetcontact) >= 40, len(tetcontact)
    assert len(table_tools()) >= 10


@pytest.mark.parametrize("where,line,argv", COMMANDS, ids=[f"{f}:{n}" for f, n, _ in COMMANDS])
def test_every_command_line_holds(binary, where, line, argv):
    where = f"{where}:{line}"
    if "build/tetcontact" in argv:
        argv = argv[argv.index("build/tetcontact"):]
        if len(argv) < 2 or argv[1].startswith("-"):
            return  # --help, --version
        sub, rest = argv[1], argv[2:]
        listed = help_text([binary, sub])
        assert "Usage: tetcontact " + sub in listed, f"{where}: no command '{sub}'"
        for o in options(rest):
            assert o in listed, f"{where}: tetcontact {sub} has no option {o}"
        case = next((a for a in rest if a.endswith(".yaml")), None)
        if case and not is_placeholder(case) and sub in ("run", "check", "limit", "sweep",
                                                          "campaign", "profile"):
            assert os.path.isfile(os.path.join(ROOT, case)), f"{where}: {case}: no such case"
            table = next((a for a in rest if a.endswith(".csv")), "TABLE.csv")
            if sub == "campaign" and is_placeholder(table):
                check_case(binary, case, sets(rest), where)
            elif sub == "campaign":
                r = subprocess.run([binary, sub] + rest + ["--check"], capture_output=True,
                                   text=True, cwd=ROOT)
                assert r.returncode == 0, f"{where}: campaign --check: {r.stderr}"
                assert "checked" in r.stdout, (table, r.stdout)
            else:
                check_case(binary, case, sets(rest), where)
    elif any(a.endswith(".py") and a.startswith("tools/") for a in argv):
        check_tool(argv, where)
    elif argv[0] == "make":
        makefile = open(os.path.join(ROOT, "Makefile")).read()
        for target in (a for a in argv[1:] if "=" not in a and not a.startswith("-")):
            assert re.search(rf"^{re.escape(target)}:", makefile, re.M), \
                f"{where}: the Makefile has no target {target}"


@pytest.mark.parametrize("where,line,argv", table_tools(),
                         ids=[f"{f}:{n}" for f, n, _ in table_tools()])
def test_every_tool_usage_in_the_table_holds(where, line, argv):
    check_tool([a for a in argv if a not in ("(or", ")")], f"{where}:{line}")


def without(argv, flags, valued):
    """argv without the flags in `flags` and the options in `valued` with their values."""
    kept, k = [], 0
    while k < len(argv):
        if argv[k] in valued:
            k += 2
            continue
        if argv[k] not in flags:
            kept.append(argv[k])
        k += 1
    return kept


def top_level_values(values):
    """How many values a --vary list gives: its commas outside brackets and braces, plus one."""
    depth, n = 0, 1
    for ch in values:
        depth += ch in "[{"
        depth -= ch in "]}"
        n += ch == "," and depth == 0
    return n


def has_placeholder(argv):
    """A line a reader completes (N, DIR, KEY=VALUE, ...): its options are checked, not run."""
    return any(a in ("N", "DIR", "...", "…") or a.split("=")[0].isupper() for a in argv)


RUNS_ITS_CASE = ("run", "sweep", "profile", "limit")

RUN_LINES = [(f, n, a) for f, n, a in COMMANDS
             if "build/tetcontact" in a
             and a[a.index("build/tetcontact") + 1:][:1] in [[c] for c in RUNS_ITS_CASE]
             and any(x.endswith(".yaml") and not is_placeholder(x) for x in a)
             and "--restart" not in a and not has_placeholder(a[a.index("build/tetcontact"):])]


def test_the_manual_has_lines_that_run():
    subs = [a[a.index("build/tetcontact") + 1] for _, _, a in RUN_LINES]
    assert subs.count("run") >= 15 and subs.count("sweep") >= 4 and subs.count("limit") >= 2 \
        and subs.count("profile") >= 1, subs


@pytest.mark.parametrize("where,line,argv", RUN_LINES, ids=[f"{f}:{n}" for f, n, _ in RUN_LINES])
def test_every_line_with_a_case_runs(binary, out, where, line, argv):
    """Each `run`, `sweep`, `profile` and `limit` line of the manual runs on its case with its
    overrides, threads and processes, as far as a test can afford: a run or each run of a sweep
    set up and stepped ten steps (solver.max_steps: the run then stops as failed, saying so),
    writing its frames, history and summary; a profile over five steps; a search with `--check`
    (each case it starts from checked as `check` does; its runs take hours)."""
    where = f"{where}:{line}"
    launcher = []
    if argv[0] == "mpirun":  # under mpirun: its process count, as root and oversubscribed here
        launcher = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                    argv[argv.index("-np") + 1]]
    argv = argv[argv.index("build/tetcontact") + 1:]
    sub, rest = argv[0], argv[1:]
    result = os.path.join(out, sub)
    if sub == "limit":
        cmd = [binary, sub] + without(rest, ("--quiet",), ("--out",)) + ["--check"]
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 0 and "cases checked" in r.stdout, (
            f"{where}: {' '.join(cmd)}: exit {r.returncode}: {r.stdout}{r.stderr}")
        assert not os.path.exists(result)
        return
    if sub == "profile":
        cmd = [binary, sub] + without(rest, (), ("--steps", "--ccd-queries")) + [
            "--steps", "5", "--ccd-queries", os.path.join(out, "queries.txt")]
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 0, f"{where}: {' '.join(cmd)}: exit {r.returncode}: {r.stderr}"
        assert "method" in r.stdout and "grid" in r.stdout, r.stdout
        return
    cmd = launcher + [binary, sub] + without(rest, ("--force", "--check", "--quiet"), ("--out",)) \
        + ["--quiet", "--out", result, "--set", "solver.max_steps=10"]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    said = f"{where}: {' '.join(cmd)}: exit {r.returncode}: {r.stderr}"
    if sub == "sweep":  # exit 1: its runs stopped
        assert r.returncode == 1, said
        with open(os.path.join(result, "sweep.csv")) as f:
            rows = list(csv.DictReader(f))
        combinations = 1
        for k, a in zip(rest, rest[1:]):
            if k == "--vary":
                combinations *= top_level_values(a.split("=", 1)[1])
        assert len(rows) == combinations, (where, len(rows), combinations)
        for row in rows:
            assert row["status"].startswith("failed: max_steps (10) reached"), (where, row)
        return
    assert r.returncode == 1 and "max_steps (10) reached" in r.stderr, said
    with open(os.path.join(result, "summary.json")) as f:
        summary = json.load(f)
    assert summary["status"].startswith("failed: max_steps (10) reached"), (where, summary["status"])
    assert summary["steps"] == 10, (where, summary["steps"])
    frame = "frame_0000.pvtu" if launcher else "frame_0000.vtu"
    assert os.path.isfile(os.path.join(result, frame)), (where, frame)
    assert os.path.isfile(os.path.join(result, "history.csv")), where


CCD_LINES = [(f, n, a) for f, n, a in COMMANDS
             if "build/tetcontact" in a and a[a.index("build/tetcontact") + 1:][:1] == ["ccd"]
             and any(x.startswith("data/") for x in a)]


@pytest.mark.parametrize("where,line,argv", CCD_LINES, ids=[f"{f}:{n}" for f, n, _ in CCD_LINES])
def test_every_ccd_line_on_a_shipped_set_runs(binary, where, line, argv):
    """`ccd` on a query set of data/ runs as the manual gives it (seconds)."""
    assert CCD_LINES, "the manual runs the CCD on a shipped set"
    argv = argv[argv.index("build/tetcontact") + 1:]
    r = subprocess.run([binary] + argv, capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, f"{where}:{line}: exit {r.returncode}: {r.stderr}"
