"""Checks create_under_load.sh (see the script's header): while hapsim-load
drove DEVICES sessions (24 by default, fewer where 24 fill the core), the most expensive accepted sessions were created without
any device's force model getting older than the watchdog's warning age, and a
request beyond the limits was refused with INVALID_ARGUMENT naming the
parameter."""
import json
import sys

from checks import check, ctl_sessions, exit_code, finish, read_text

work, server_rc = sys.argv[1], int(sys.argv[2])
WARN_AGE_MS = 20.0  # hapsim-load's --watchdog-warn-ms default (the model-age bound under load)
CREATED = {"acupuncture": "worst-acupuncture", "tissue_cost": "worst-tissue-cost", "tissue_grid": "worst-tissue-grid"}
GRPC_INVALID_ARGUMENT = 3


def text(name):
    return read_text(work, name)


def sessions(listing):
    return ctl_sessions(work, listing)


times = {}
for line in text("times.txt").splitlines():
    key, value = line.split()
    times[key] = float(value)
DEVICES = int(times["devices"])
print(f"     the class: {DEVICES} devices, {times.get('class_share', float('nan')):.2f} of the server's core before the creations")

# The load ran, all its devices streamed before the creations and it was
# still running after them.
check(exit_code(work, "load") == 0, "hapsim-load exits 0" + ("" if exit_code(work, "load") == 0 else
                                                       f" (got {exit_code(work, 'load')}: {text('load.err')[-300:]})"))
streaming = int(times.get("streaming", 0))
check(streaming == DEVICES, f"all {DEVICES} devices streamed before the creations ({streaming})")
check(times.get("load_running_after_creations") == 1, "hapsim-load was still running after the creations")

# The creations.
for name, session in CREATED.items():
    took = times[f"{name}_end"] - times[f"{name}_start"]
    printed = text(f"{name}.out").split()
    ok = exit_code(work, name) == 0 and printed[:1] == [session]
    check(ok, f"create {session} succeeds under load in {took:.2f} s"
          + ("" if ok else f" (rc {exit_code(work, name)}: {(text(f'{name}.out') + text(f'{name}.err')).strip()[-200:]!r})"))
during = sessions("during.txt")
for name, session in CREATED.items():
    info = ctl_sessions(work, f"{name}.info")
    ticks = int(info.get(session, {}).get("ticks", 0))
    check(ticks > 0, f"{session} ticks ({ticks} ticks 50 ms after its creation; then closed again)")

# The refusal.
refused = text("refused.err")
check(exit_code(work, "refused") != 0 and f"({GRPC_INVALID_ARGUMENT})" in refused and "shf_lmax" in refused,
      f"shf_lmax=30 is refused with INVALID_ARGUMENT naming the parameter: {refused.strip()!r}")
check("too-deep" not in during, "the refused session does not exist")
check(not any(s in during for s in CREATED.values()), "the created sessions were closed again")

# Every device's force models stayed fresh.
report = json.load(open(f"{work}/load.json"))
devices = report["per_device"]
check(len(devices) == DEVICES, f"{DEVICES} devices reported (got {len(devices)})")
worst = max(devices, key=lambda d: d["model_age_ms"]["max"]) if devices else None
if worst:
    print(f"     worst model age {worst['model_age_ms']['max']:.3f} ms (device {worst['device_id']}, "
          f"{worst['session']}); round trip p99 {report['total']['round_trip_ms']['p99']:.3f} ms, "
          f"max {report['total']['round_trip_ms']['max']:.3f} ms")
for d in devices:
    name = f"device {d['device_id']} ({d['session']})"
    age = d["model_age_ms"]
    check(d["models_received"] > 0 and age["count"] > 0, f"{name} received models ({d['models_received']})")
    check(age["max"] <= WARN_AGE_MS, f"{name}: model age max {age['max']:.3f} ms <= {WARN_AGE_MS:.0f} ms")
    check(d["watchdog_warnings"] == 0 and d["watchdog_fades"] == 0 and d["watchdog_disarms"] == 0,
          f"{name}: no watchdog warning, fade or disarm "
          f"({d['watchdog_warnings']}/{d['watchdog_fades']}/{d['watchdog_disarms']})")
servo = report["servo_thread"]["lateness_ms"]
print(f"     load servo thread lateness p99 {servo['p99']:.3f} / max {servo['max']:.3f} ms")
late = sum(s.get("late_ticks", 0) for s in report.get("server_sessions", []))
ticks = sum(s.get("ticks", 0) for s in report.get("server_sessions", []))
worst_late = max((s.get("max_tick_lateness_ms", 0.0) for s in report.get("server_sessions", [])), default=0.0)
print(f"     server: {late} late ticks of {ticks} in the load's sessions, worst tick lateness {worst_late:.3f} ms")
check(server_rc == 0, f"the server exits 0 on SIGTERM (got {server_rc})")
finish()
