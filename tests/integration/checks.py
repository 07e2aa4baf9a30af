"""Shared by the end-to-end check scripts: print each check as ok/FAIL and
exit non-zero if any failed."""
import sys

_failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        _failures.append(what)


def finish():
    print(f"{len(_failures)} failed")
    sys.exit(1 if _failures else 0)
