"""Shared by the end-to-end check scripts: print each check as ok/FAIL and
exit non-zero if any failed."""
import glob
import os
import re
import sys

_failures = []
_work_dirs = []  # every directory read_text read from: where the run's outputs are
_noted_stalls = []  # host stalls a check script saw in its own instruments (note_host_stall)

# Exit code of a run that failed while the host itself was stalled: the test
# runner (retry_on_host_stall.sh) runs such a test once more.
HOST_STALLED_EXIT = 75


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        _failures.append(what)


def _servo_stalls(limit_ms=10.0):
    """Evidence that the host, not hapsim, took the CPU away during the run: a
    bridge's or hapsim-load's own 1 kHz servo that waited more than LIMIT_MS
    (ten periods), from their reports ('period jitter p50 a / p99 b / max c
    ms', 'servo thread: ... lateness p50 a / p99 b / max c ms') in the run's
    outputs (every *.out and *.log under the directories read_text read)."""
    pattern = re.compile(r"(?:period jitter|lateness) p50 [\d.]+ / p99 [\d.]+ / max ([\d.]+) ms")
    stalls = []
    for work in _work_dirs:
        for path in sorted(glob.glob(os.path.join(work, "**", "*.out"), recursive=True) +
                           glob.glob(os.path.join(work, "**", "*.log"), recursive=True)):
            try:
                with open(path, errors="replace") as f:
                    text = f.read(4 << 20)
            except OSError:
                continue
            waits = [float(m) for m in pattern.findall(text)]
            if waits and max(waits) > limit_ms:
                stalls.append(f"{os.path.relpath(path, work)}: a servo waited {max(waits)} ms (> {limit_ms} ms)")
    return stalls


def note_host_stall(evidence):
    """Another sign that the host withheld the CPU during the run, seen by the
    check script itself (say, a real-time test instrument that ran late)."""
    _noted_stalls.append(evidence)


def finish():
    print(f"{len(_failures)} failed")
    stalls = (_servo_stalls() + _noted_stalls) if _failures else []
    if stalls:
        # Timing checks measured the host's stall, not the code: say so and
        # let the runner try once more (a second failure fails the test).
        print(f"failed on a stalled host ({'; '.join(stalls)}): exit {HOST_STALLED_EXIT}")
        sys.exit(HOST_STALLED_EXIT)
    sys.exit(1 if _failures else 0)


def read_text(work, name):
    if work not in _work_dirs:
        _work_dirs.append(work)
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


if __name__ == "__main__":
    # `checks.py stalled WORK_DIR`: lib.sh's finish_checks asks whether a
    # failed bash-checked run was on a stalled host (exit 75) or not (exit 1).
    if len(sys.argv) == 3 and sys.argv[1] == "stalled":
        _work_dirs.append(sys.argv[2])
        stalls = _servo_stalls()
        if stalls:
            print(f"failed on a stalled host ({'; '.join(stalls)}): exit {HOST_STALLED_EXIT}")
            sys.exit(HOST_STALLED_EXIT)
        sys.exit(1)
    sys.exit("usage: checks.py stalled WORK_DIR")
