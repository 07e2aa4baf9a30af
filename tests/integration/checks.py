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


def read_text(work, name):
    return open(f"{work}/{name}").read()


def exit_code(work, name):
    """The exit code a script stored in NAME.rc."""
    return int(read_text(work, f"{name}.rc"))


def ctl_sessions(work, listing):
    """hapsim-ctl list output in file LISTING -> {session id: {field: value}}"""
    table = {}
    for line in read_text(work, listing).splitlines():
        fields = line.split()
        if fields:
            table[fields[0]] = dict(f.split("=", 1) for f in fields[1:] if "=" in f)
    return table
