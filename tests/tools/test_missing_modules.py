"""A tool run under a python3 that lacks numpy, VTK or matplotlib says which Debian package to
install, with exit code 2, never a bare ModuleNotFoundError traceback (tools/common/__init__.py).
The python3 is Debian's with the module hidden: a sitecustomize.py on PYTHONPATH puts a finder
first on sys.meta_path that refuses it, as an interpreter without the package would."""
import os
import subprocess

import pytest

from conftest import PYTHON, tool

BLOCKER = '''import sys

class _Hide:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in {hidden!r}:
            raise ModuleNotFoundError("No module named " + repr(name), name=name)
        return None

sys.meta_path.insert(0, _Hide())
'''

# The tools that import a third-party module as they start, with what each needs first.
TOOLS = [("post/check_vtu.py", "numpy", "python3-numpy"),
         ("post/check_vtu.py", "vtk", "python3-vtk9"),
         ("post/section_png.py", "numpy", "python3-numpy"),
         ("post/sequence_png.py", "numpy", "python3-numpy"),
         ("post/ball_plate_report.py", "numpy", "python3-numpy"),
         ("dev/scale_frames.py", "vtk", "python3-vtk9")]


@pytest.mark.parametrize("path,hidden,package", TOOLS)
def test_a_missing_module_names_its_debian_package(tmp_path, path, hidden, package):
    (tmp_path / "sitecustomize.py").write_text(BLOCKER.format(hidden={hidden}))
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    r = subprocess.run([PYTHON, tool(path)], capture_output=True, text=True, env=env)
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr, r.stderr
    name = os.path.basename(path)
    assert f"{name}: error: this python3" in r.stderr, r.stderr
    assert f"has no module '{hidden}'" in r.stderr and f"apt-get install {package}" in r.stderr


def test_the_blocker_hides_the_module(tmp_path):
    """The check's own check: with the blocker, importing numpy fails as when it is missing."""
    (tmp_path / "sitecustomize.py").write_text(BLOCKER.format(hidden={"numpy"}))
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    r = subprocess.run([PYTHON, "-c", "import numpy"], capture_output=True, text=True, env=env)
    assert r.returncode == 1 and "ModuleNotFoundError" in r.stderr
