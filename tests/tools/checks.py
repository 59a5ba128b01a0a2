"""The scripted tests' one assertion: check(cond, what) prints FAIL lines and counts them."""
import sys

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def finish(name, detail=""):
    """Prints the verdict and exits 1 when any check failed."""
    print("%s: %s%s" % (name, "FAILED" if failures else "passed", detail))
    sys.exit(1 if failures else 0)
