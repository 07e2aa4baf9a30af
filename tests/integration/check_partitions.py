"""Checks tests/integration/partitions.sh's output (see that script)."""
import csv
import re
import sys
from pathlib import Path

from checks import check, finish

work = Path(sys.argv[1])


def field(text, pattern):
    m = re.search(pattern, text)
    return int(m.group(1)) if m else None


for name in ("a", "b"):
    out = (work / f"{name}.out").read_text()
    others = field(out, r"models for other sessions or devices (\d+)")
    received = field(out, r"force models received (\d+)")
    check(others == 0, f"bridge {name} received {others} models of another session (expected 0)")
    check(received is not None and received > 1000, f"bridge {name} received {received} of its own models")

# Bridge a: its session closed at ~2 s. Fresh models before, none after; the
# watchdog walks fresh -> warn -> fade -> disarmed and stays there.
rows = list(csv.DictReader(open(work / "a.csv")))
states = [r["watchdog"] for r in rows]
check("fresh" in states, "bridge a had fresh models before the close")
check(states[-1] == "disarmed", f"bridge a ends {states[-1]} after its session closed (expected disarmed)")
last_fresh = max(i for i, s in enumerate(states) if s == "fresh")
after = states[last_fresh + 1:]
check(all(s != "fresh" for s in after), "no fresh model reached bridge a after its session closed")
check("fading" in after and "disarmed" in after, "bridge a's watchdog faded and disarmed after the close")
first_disarmed = after.index("disarmed")
check(all(float(r["fx_N"]) == 0 and float(r["fy_N"]) == 0 and float(r["fz_N"]) == 0
          for r in rows[last_fresh + 1 + first_disarmed:]),
      "bridge a commands zero force once disarmed")
b_states = [r["watchdog"] for r in csv.DictReader(open(work / "b.csv"))]
check(b_states.count("disarmed") == 0, "bridge b never disarmed: closing room-a did not touch room-b")

ghost = (work / "ghost.log").read_text()
check("no server serves session 'nobody-here'" in ghost, "a bridge for an unserved session is told so")
sessions = (work / "sessions.txt").read_text()
check("room-a" not in sessions and "room-b" in sessions, "room-a closed, room-b still listed")
finish()
