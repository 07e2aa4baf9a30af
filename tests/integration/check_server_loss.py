"""Checks server_loss.sh: after the last force model, the commanded force is
zero from (last model + 100 ms) on, never grows after the server died, and
the watchdog disarmed exactly once."""
import csv
import re
import sys

from checks import check, finish

work = sys.argv[1]


rows = list(csv.DictReader(open(f"{work}/trace.csv")))
force = lambda r: (float(r["fx_N"]) ** 2 + float(r["fy_N"]) ** 2 + float(r["fz_N"]) ** 2) ** 0.5
# Ticks whose model is fresh (< 1 ms old) show the server still alive; the
# last of them is (within 1 ms) when the last model arrived.
alive = [i for i, r in enumerate(rows) if 0.0 <= float(r["model_age_ms"]) < 1.0]
check(len(alive) > 500, f"the server answered for a while before dying ({len(alive)} fresh ticks)")
last = alive[-1]
t_last = float(rows[last]["t_s"])
check(force(rows[last]) > 0.2, f"the device was pressing when the server died ({force(rows[last]):.3f} N)")
after = rows[last + 1:]
check(len(after) > 400, f"the bridge kept running after the loss ({len(after)} ticks)")
late = [r for r in after if float(r["t_s"]) >= t_last + 0.101]
check(bool(late) and max(force(r) for r in late) == 0.0,
      f"force is exactly zero from 100 ms after the last model on (max {max((force(r) for r in late), default=1):.3g} N)")
grows = sum(1 for a, b in zip(after, after[1:]) if force(b) > force(a) + 1e-12)
check(grows == 0, f"force never grows after the last model ({grows} rising ticks)")
zero_at = next((float(r["t_s"]) for r in after if force(r) == 0.0), None)
if zero_at is not None:
    print(f"     force reached zero {1e3 * (zero_at - t_last):.1f} ms after the last model")
check(rows[-1]["watchdog"] == "disarmed", f"watchdog ends disarmed (got {rows[-1]['watchdog']})")
m = re.search(r"disarms (\d+)", open(f"{work}/bridge.out").read())
check(m is not None and int(m.group(1)) == 1, "the watchdog disarmed exactly once")
finish()
