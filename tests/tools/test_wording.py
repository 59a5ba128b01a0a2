"""The tools and their tests name their sources, not tracker numbers or shorthand: no issue
numbers, no working-period words, no numbered shorthand for the papers (Dobritsa et al. 2019 is
named instead). A random generator's seed ('--seed 7') is fine."""
import os
import re

from conftest import ROOT

# Built from pieces, so that this file does not match them itself.
PATTERNS = [r"(?i)\bissues? #?[0-9]", r"(?i)\bsess" + r"ions?\b",
            r"(?i)\bseed (document|paper|" + "0)", r"(?i)\bseeds? " + "0"]


def files():
    for top in ("tools", os.path.join("tests", "tools")):
        for folder, dirs, names in os.walk(os.path.join(ROOT, top)):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            for name in names:
                if not name.endswith((".pyc", ".png")):
                    yield os.path.join(folder, name)


def test_no_tracker_numbers_or_shorthand():
    found = []
    checked = 0
    for path in files():
        checked += 1
        for n, line in enumerate(open(path, encoding="utf-8"), 1):
            for p in PATTERNS:
                if re.search(p, line):
                    found.append(f"{os.path.relpath(path, ROOT)}:{n}: {line.strip()}")
    assert checked >= 25, checked  # the twelve tools, their tests, the package files
    assert not found, "\n".join(found)


def test_the_patterns_catch_what_they_should():
    I, S = "iss" + "ue", "se" + "ed"  # pieces, so that this file does not match itself
    bad = [f"({I} 18)", f"{I} 13: numbers", f"{I}s #4", "this sess" + "ion", f"{S} 0" + "00",
           f"{S} 0" + "01 §3", f"the {S} paper", f"{S}s 0" + "00 and 001"]
    for text in bad:
        assert any(re.search(p, text) for p in PATTERNS), text
    for text in ["--seed 7", "seed 15", "Dobritsa et al. (2019)", "an issue of the journal"]:
        assert not any(re.search(p, text) for p in PATTERNS), text
