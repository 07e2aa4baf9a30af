#!/usr/bin/python3
"""Checks of classroom.sh: class view, roles, TLS, scores, metrics."""
import os
import re
import sys

from checks import check, finish

work, server_rc = sys.argv[1], int(sys.argv[2])


def read(name):
    path = os.path.join(work, name)
    return open(path).read() if os.path.exists(path) else ""


def rc(name):
    return int(read(name + ".rc").strip() or "-1")


check(server_rc == 0, f"server exited cleanly (rc {server_rc})")
check(rc("watch") == 0, f"instructor's watch ran (rc {rc('watch')}: {read('watch.err').strip()[:200]})")

# Blocks: "class acu-101  update N  (...)", a header, one row per session.
blocks = [b for b in read("watch.out").split("\n\n") if b.startswith("class acu-101")]
check(len(blocks) >= 40, f"{len(blocks)} class-view updates in 6 s at 10 Hz (want >= 40)")
sessions = [f"t{k}" for k in range(1, 9)]
seen_device, max_depth, last_events = {}, {}, {}
for b in blocks:
    for line in b.splitlines()[2:]:
        f = line.split()
        if len(f) < 12 or f[0] not in sessions:
            continue
        s = f[0]
        seen_device[s] = seen_device.get(s, False) or f[3] == "yes"
        max_depth[s] = max(max_depth.get(s, 0.0), float(f[5]))
        last_events[s] = int(f[10])
for s in sessions:
    check(s in last_events, f"{s} listed in the class view")
    check(seen_device.get(s, False), f"{s}: device streaming seen")
    check(max_depth.get(s, 0.0) > 1.0, f"{s}: tip depth reached {max_depth.get(s, 0.0):.2f} mm (> 1 mm)")
    check(last_events.get(s, 0) >= 2, f"{s}: {last_events.get(s, 0)} events reported (>= 2: contact, puncture...)")
punctures = len(re.findall(r"puncture@", read("watch.out")))
check(punctures > 0, f"puncture events shown in the recent-events column ({punctures} times)")

check(rc("observer_watch") == 0, "observer may watch the class")
if os.path.exists(f"{work}/console.rc"):  # built with the viewer GUI
    console = open(f"{work}/console.out").read()
    m = re.search(r"viewer: class acu-101, updates (\d+), sessions (\d+)", console)
    check(rc("console") == 0 and m is not None and int(m.group(1)) >= 20 and int(m.group(2)) == 8,
          f"the observer's class console got the class stream ({m.group(0) if m else console.strip()!r})")
    m = re.search(r"viewer: session t2, frames (\d+)", console)
    check(m is not None and int(m.group(1)) > 50, "the console watched t2's frames")
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from png_image import pixel, read_png
    image = read_png(f"{work}/console.png")
    colours = {pixel(image, x, y) for x in range(0, 1280, 16) for y in range(0, 720, 16)}
    check(len(colours) > 50, f"the console picture is not blank ({len(colours)} colours on a 16 px grid)")
    first = open(f"{work}/console_first.out").read()
    m = re.search(r"viewer: session (\S*), frames (\d+)", first)
    check(rc("console_first") == 0 and m is not None and m.group(1) == "t1" and int(m.group(2)) > 50,
          f"a console without --session opened the class's first trainee ({m.group(0) if m else first.strip()!r})")
check(rc("observer_reset") != 0 and "(7)" in read("observer_reset.err"),
        f"observer reset refused with PERMISSION_DENIED: {read('observer_reset.err').strip()}")
check(rc("trainee_join") == 0 and "dds_partition=hapsim_s_t1" in read("trainee_join.out"),
        f"trainee joins its own session: {read('trainee_join.out').strip().splitlines()[:1]}")
check(rc("trainee_other") != 0 and "(7)" in read("trainee_other.err"),
        f"trainee may not view another's session: {read('trainee_other.err').strip()}")
check(rc("no_token") != 0 and "(16)" in read("no_token.err"),
        f"no token: UNAUTHENTICATED: {read('no_token.err').strip()}")
check(rc("plain_tcp") != 0 and "(14)" in read("plain_tcp.err"),
        f"plain TCP to the TLS port refused: {read('plain_tcp.err').strip()[:120]}")

# Two raters of t1: the hand-computed two-rater example, mean f = 6.790.
m = re.search(r"^t1 experts=2 score=([0-9.]+)", read("scores.out"), re.M)
check(m is not None and abs(float(m.group(1)) - 6.790) < 1e-3,
        f"t1 scored from its own two raters: {m.group(0) if m else read('scores.out')[:200]}")

metrics = read("metrics.txt")
denied = re.search(r'hapsim_auth_failures_total\{reason="permission_denied"\} (\d+)', metrics)
unauth = re.search(r'hapsim_auth_failures_total\{reason="unauthenticated"\} (\d+)', metrics)
# Exactly the observer's reset and the trainee's look at t2: the consoles
# made no call the class refuses.
check(denied is not None and int(denied.group(1)) == 2, f"metrics count permission_denied: {denied.group(0) if denied else 'missing'} (2 refused on purpose)")
check(unauth is not None and int(unauth.group(1)) >= 1, f"metrics count unauthenticated: {unauth.group(0) if unauth else 'missing'}")
# Trials: the CSV the instructor exported after resetting t1.
import csv
import io
rows = list(csv.DictReader(io.StringIO(read("trials.csv"))))
check(rc("trials") == 0 and len(rows) >= 9, f"trials exported: {len(rows)} rows (rc {rc('trials')})")
t1 = [r for r in rows if r["session"] == "t1" and r["end"] == "reset"]
check(len(t1) == 1, f"t1 has one trial ended by the reset ({len(t1)})")
if t1:
    r = t1[0]
    check(abs(float(r["max_depth_mm"]) - 12.0) < 0.1, f"t1 trial max depth {r['max_depth_mm']} mm (script: 12 mm)")
    check(r["target_depth_mm"] == "10.000" and abs(float(r["depth_error_mm"]) - 2.0) < 0.1,
          f"t1 depth error {r['depth_error_mm']} mm against the 10 mm target")
    check("skin" in r["layers_pierced"].split("+") and int(r["punctures"]) >= 1,
          f"t1 pierced {r['layers_pierced']} ({r['punctures']} punctures)")
    check("skin=" in r["peak_force_by_layer_N"] and float(r["peak_force_N"]) > 1.0,
          f"t1 peak forces: {r['peak_force_N']} N, by layer {r['peak_force_by_layer_N']}")
    check(r["score"] != "" and abs(float(r["score"]) - 6.79) < 1e-3, f"t1 trial carries its score {r['score']}")
for k in range(2, 9):
    mine = [r for r in rows if r["session"] == f"t{k}"]
    check(any(int(r["punctures"]) > 0 for r in mine), f"t{k} has a trial with punctures")
check(rc("observer_trials") == 0, "observer may read the class's trials")
finish()
