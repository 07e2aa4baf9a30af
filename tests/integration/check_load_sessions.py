"""Checks load_sessions.sh: hapsim-load's 16-device run (load.json, the
server's listing), its creation failures, and the server after a load
generator was killed (see the script's header)."""
import json
import re
import sys

from checks import check, ctl_sessions, exit_code, finish, read_text

work, server_rc = sys.argv[1], int(sys.argv[2])


def text(name):
    return read_text(work, name)


def sessions(listing):
    return ctl_sessions(work, listing)


# 1. Sixteen devices for 4 s.
check(exit_code(work, "load") == 0, f"hapsim-load exits 0 (got {exit_code(work, 'load')}: {text('load.err')[-300:]})")
report = json.load(open(f"{work}/load.json"))
devices = report["per_device"]
check(len(devices) == 16, f"16 devices reported (got {len(devices)})")
for d in devices:
    name = f"device {d['device_id']} ({d['session']})"
    check(d["models_received"] > 0 and d["last_echo_seq"] > d["first_echo_seq"],
          f"{name} received models with advancing echoed seqs "
          f"({d['models_received']} models, seq {d['first_echo_seq']} -> {d['last_echo_seq']})")
    check(d["echo_regressions"] == 0, f"{name}: no echoed-seq regression ({d['echo_regressions']})")
    check(d["watchdog_disarms"] == 0, f"{name}: no watchdog disarm ({d['watchdog_disarms']})")
    check(d["pose_rate_hz"] > 500, f"{name}: poses at about the servo rate ({d['pose_rate_hz']:.0f} Hz)")
total = report["total"]
print(f"     total: round trip p50 {total['round_trip_ms']['p50']:.3f} / p99 {total['round_trip_ms']['p99']:.3f} / "
      f"max {total['round_trip_ms']['max']:.3f} ms, model age p99 {total['model_age_ms']['p99']:.3f} ms, "
      f"watchdog warnings {total['watchdog_warnings']}, fades {total['watchdog_fades']}")
listed = sessions("list.txt")
for i in range(16):
    s = listed.get(f"load-{i}", {})
    check(re.fullmatch(r"\d+", s.get("late_ticks", "")) is not None,
          f"hapsim-ctl list reports late_ticks for load-{i} ({s.get('late_ticks')})")
server = {s["session_id"]: s for s in report.get("server_sessions", [])}
check(len(server) == 16 and all("late_ticks" in s for s in server.values()),
      f"the JSON carries the server's late_ticks of all 16 sessions ({len(server)} reported)")
late = sum(s.get("late_ticks", 0) for s in server.values())
ticks = sum(s.get("ticks", 0) for s in server.values())
print(f"     server: {late} late ticks of {ticks}")

# 2. Creation failures.
check(exit_code(work, "dup") != 0 and "ALREADY_EXISTS" in text("dup.err") and "load-0" in text("dup.err"),
      f"creating an existing session fails with the server's error: {text('dup.err').strip()!r}")
check(exit_code(work, "scene") != 0 and "no_such_scene" in text("scene.err") and "cannot create" in text("scene.err"),
      f"an unknown scene fails with the server's error: {text('scene.err').strip()!r}")
after_failures = sessions("after_failures.txt")
check(exit_code(work, "partial") != 0 and "load-3" in text("partial.err") and "fresh-a" not in after_failures,
      "a failed creation closes the sessions created before it (fresh-a is gone)")
check(not any(k.startswith("nosuch-") for k in after_failures), "no session is left from the unknown scene")

# 3. A killed load generator.
alive, after_kill = sessions("alive.txt"), sessions("after_kill.txt")
for i in range(4):
    s, gone = alive.get(f"killed-{i}", {}), after_kill.get(f"killed-{i}", {})
    check(s.get("device_streaming") == "1" and s.get("owning_device_id") == str(2000 + i),
          f"killed-{i} is driven by device {2000 + i} while the generator runs "
          f"(device_streaming={s.get('device_streaming')}, owning_device_id={s.get('owning_device_id')})")
    check(gone.get("device_streaming") == "0",
          f"killed-{i} reports device_streaming=0 after the pose timeout (got {gone.get('device_streaming')})")
check(exit_code(work, "health") == 0 and text("health.out").strip() == "SERVING", "the server stays SERVING after the kill")
ticks_before = int(alive.get("load-0", {}).get("ticks", 0))
ticks_after = int(after_kill.get("load-0", {}).get("ticks", 0))
check(ticks_after > ticks_before, f"other sessions keep ticking after the kill (load-0: {ticks_before} -> {ticks_after})")

# 4. Closed at exit.
check(exit_code(work, "closed") == 0 and not any(k.startswith("closed-") for k in sessions("after_close.txt")),
      "without --keep-sessions the generator's sessions are closed at exit")
check(server_rc == 0, f"the server exits 0 on SIGTERM (got {server_rc})")
finish()
