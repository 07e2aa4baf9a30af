"""Shared by the end-to-end check scripts: print each check as ok/FAIL and
exit non-zero if any failed."""
import re
import sys

_failures = []
_host_stalls = []

# Exit code of a run that failed while the host itself was stalled: the test
# runner (retry_on_host_stall.sh) runs such a test once more.
HOST_STALLED_EXIT = 75


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        _failures.append(what)


def note_servo_stalls(out, who, limit_ms=10.0):
    """Evidence that the host, not hapsim, took the CPU away: a bridge's own
    1 kHz servo that did not run for LIMIT_MS (ten periods). Its report line
    'period jitter p50 a / p99 b / max c ms' gives the longest wait."""
    found = re.search(r"period jitter p50 [\d.]+ / p99 [\d.]+ / max ([\d.]+) ms", out)
    if found and float(found.group(1)) > limit_ms:
        what = f"{who}'s servo waited {found.group(1)} ms (> {limit_ms} ms) for the CPU"
        print("host stall: " + what)
        _host_stalls.append(what)


def finish():
    print(f"{len(_failures)} failed")
    if _failures and _host_stalls:
        # Timing checks measured the host's stall, not the code: say so and
        # let the runner try once more (a second failure fails the test).
        print(f"failed on a stalled host ({'; '.join(_host_stalls)}): exit {HOST_STALLED_EXIT}")
        sys.exit(HOST_STALLED_EXIT)
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
