"""What the tools share: summary.json / history.csv key names, Christiansen's equations.

Importing it (every tool does, before any third-party module) makes a missing third-party
module a plain message naming the Debian package that has it, with exit code 2, instead of a
traceback: Debian's python3 with its packages is what the tools run under, and another python3
on the PATH (a virtual environment, a conda one) often lacks them."""
import os
import sys

# The Debian package of each third-party module the tools import.
DEBIAN_PACKAGES = {"numpy": "python3-numpy", "vtk": "python3-vtk9", "vtkmodules": "python3-vtk9",
                   "matplotlib": "python3-matplotlib"}


def _missing_module(kind, value, tb):
    top = (getattr(value, "name", None) or "").split(".")[0]
    if isinstance(value, ModuleNotFoundError) and top in DEBIAN_PACKAGES:
        package = DEBIAN_PACKAGES[top]
        tool = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "python3"
        sys.stderr.write(
            f"{tool}: error: this python3 ({sys.executable}) has no module '{top}': install "
            f"Debian's {package} (apt-get install {package}; `make run` installs it when run as "
            f"root), or run the tool with /usr/bin/python3\n")
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(2)
    sys.__excepthook__(kind, value, tb)


sys.excepthook = _missing_module
