"""Checks the outputs of end_to_end.sh (standard library only)."""
import csv
import re
import sys

from checks import check, finish

work, server_rc, bridge_rc, viewer_rc = sys.argv[1], *map(int, sys.argv[2:5])


def read(name):
    with open(f"{work}/{name}") as f:
        return f.read()


def obj_vertices(name):
    return [tuple(map(float, line.split()[1:4])) for line in read(name).splitlines() if line.startswith("v ")]


check(server_rc == 0, f"server exits 0 on SIGTERM (got {server_rc})")
check(bridge_rc == 0, f"bridge exits 0 on SIGTERM (got {bridge_rc})")
check(viewer_rc == 0, f"viewer exits 0 on SIGTERM (got {viewer_rc})")

bridge = read("bridge.out")
m = re.search(r"force models received (\d+) \(echoed pose seq (\d+) -> (\d+), regressions (\d+),", bridge)
check(m is not None, "bridge reports force models")
if m:
    received, first, last, regressions = map(int, m.groups())
    # The shipped deadband coding: a model when the force would feel different, else a keep-alive (40/s).
    check(received > 100, f"bridge received > 100 force models in ~3 s (got {received})")
    check(last > first + 1000, f"echoed pose seq advances ({first} -> {last})")
    check(regressions == 0, f"echoed pose seq never goes back (regressions {regressions})")

# Force trace: pressing vs withdrawn.
rows = list(csv.DictReader(open(f"{work}/trace.csv")))
check(len(rows) > 2500, f"trace has a row per servo tick (got {len(rows)})")
force = lambda r: (float(r["fx_N"]) ** 2 + float(r["fy_N"]) ** 2 + float(r["fz_N"]) ** 2) ** 0.5
pressing = [force(r) for r in rows if r["phase"] in ("press", "hold") and float(r["z_m"]) < -0.002]
withdrawn = [force(r) for r in rows if r["phase"] == "withdraw" and float(r["z_m"]) > 0.001]
check(len(pressing) > 100 and min(pressing) > 0.05,
      f"force is nonzero while pressing deeper than 2 mm (min {min(pressing, default=0):.3f} N over {len(pressing)} ticks)")
check(len(withdrawn) > 50 and max(withdrawn) < 1e-3,
      f"force is ~0 once withdrawn above the surface (max {max(withdrawn, default=1):.2e} N over {len(withdrawn)} ticks)")
check(max(force(r) for r in rows) <= 2.5 + 1e-9, "commanded force never exceeds the 2.5 N clamp")

# Viewer mesh vs server snapshot.
viewer, server = obj_vertices("viewer.obj"), obj_vertices("server.obj")
check(len(viewer) == len(server) and len(viewer) > 0, f"same vertex count ({len(viewer)} vs {len(server)})")
if len(viewer) == len(server) and viewer:
    err = max(abs(a - b) for va, vb in zip(viewer, server) for a, b in zip(va, vb))
    check(err <= 0.5e-5 + 1e-9, f"viewer mesh equals server snapshot within half the 10 um quantum (max error {err:.2e} m)")
    dent = -min(v[2] for v in server)
    check(dent > 1e-3, f"the compared mesh is deformed by the held needle (deepest vertex {dent * 1e3:.2f} mm)")

v = read("viewer.out")
m = re.search(r"gaps (\d+), topology mismatches (\d+), malformed (\d+), resubscribes (\d+)", v)
check(m is not None and int(m.group(1)) == 1 and int(m.group(4)) == 1,
      "the injected frame loss was detected as one gap and healed by one resubscribe")
m = re.search(r"keyframes (\d+)", v)
check(m is not None and int(m.group(1)) == 2, "exactly two keyframes: the first and the resync")

finish()
