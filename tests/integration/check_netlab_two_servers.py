"""Checks netlab_two_servers.sh: on a site of two servers with one
directory, clients on a third host find and use a session on either server
whichever they ask; when one server dies, its sessions are reported
unavailable by name and the other server's sessions run on."""
import re
import sys

from checks import check, ctl_sessions, exit_code, finish, read_text

work = sys.argv[1]


def fields(name):
    """hapsim-ctl locate output -> {field: value}"""
    line = read_text(work, f"{name}.out").strip()
    return dict(f.split("=", 1) for f in line.split() if "=" in f)


def number(text, pattern):
    m = re.search(pattern, text)
    return float(m.group(1)) if m else -1.0


# Before: each trainee asked the server that does not run its session.
b1 = fields("locate_b1")
check(exit_code(work, "locate_b1") == 0 and b1.get("server") == "srvb" and b1.get("address") == "10.77.0.2:50051"
      and b1.get("on_this_server") == "no" and b1.get("class") == "lab-b",
      f"srva says b1 runs on srvb ({b1})")
a1 = fields("locate_a1")
check(exit_code(work, "locate_a1") == 0 and a1.get("server") == "srva" and a1.get("on_this_server") == "no",
      f"srvb says a1 runs on srva ({a1})")
wrong = read_text(work, "locate_b1_wrong_token.err")
check(exit_code(work, "locate_b1_wrong_token") != 0 and "server srvb refused" in wrong,
      f"a1's token may not learn where b1 is: srvb refuses it ({wrong.strip()[:100]})")

# b1 used through srva: the bridge joined it on srvb and felt the tissue; the viewer streamed it.
bridge_b1 = read_text(work, "bridge_b1.out")
bridge_b1_log = read_text(work, "bridge_b1.log")
check(exit_code(work, "bridge_b1") == 0, f"b1's bridge exited 0 ({exit_code(work, 'bridge_b1')})")
check("session b1 is on srvb (10.77.0.2:50051): joined" in bridge_b1_log, "b1's bridge located b1 on srvb and joined")
models_b1 = number(bridge_b1, r"force models received (\d+)")
peak_b1 = number(bridge_b1, r"force peak ([\d.]+) N")
# Deadband defaults: a pose or model goes out on a felt change or every 25 ms (>= 100 in 2.5 s).
check(models_b1 >= 90 and peak_b1 > 0.3, f"b1's bridge got force models from srvb ({models_b1:.0f}, peak {peak_b1} N)")
srvb_instance = re.search(r"server instance ([0-9a-f]{16})", read_text(work, "srvb.log")).group(1)
check(f"following server {srvb_instance}" in bridge_b1, f"b1's bridge followed srvb's instance {srvb_instance}")
info_b1 = ctl_sessions(work, "info_b1.out").get("b1", {})
poses_b1 = int(info_b1.get("poses_received", "0"))
check(poses_b1 >= 90 and float(info_b1.get("peak_tool_force_n", "0")) > 0.3,
      f"hapsim-ctl info b1, asked of srva, answered from srvb: {poses_b1} poses, "
      f"peak {info_b1.get('peak_tool_force_n')} N")
viewer_b1 = read_text(work, "viewer_b1.out")
frames_b1 = number(viewer_b1, r"frames (\d+)")
check(exit_code(work, "viewer_b1") == 0 and frames_b1 >= 60,
      f"b1's viewer, pointed at srva, streamed from srvb ({frames_b1:.0f} frames in 2.5 s)")
check("session b1 is on srvb (10.77.0.2:50051): connecting there" in read_text(work, "viewer_b1.log"),
      "b1's viewer said where it connected")

# After srvb died: its session is unavailable, named; a1 runs on.
after = read_text(work, "locate_b1_after.err")
check(exit_code(work, "locate_b1_after") != 0 and "(14)" in after and "srvb (10.77.0.2:50051)" in after,
      f"after srvb died, locating b1 is UNAVAILABLE naming srvb ({after.strip()[:160]})")
info_after = read_text(work, "info_b1_after.err")
check(exit_code(work, "info_b1_after") != 0 and "srvb" in info_after,
      f"hapsim-ctl info b1 says srvb did not answer ({info_after.strip()[:120]})")
viewer_after = read_text(work, "viewer_b1_after.log")
check(exit_code(work, "viewer_b1_after") == 1 and "UNAVAILABLE" in viewer_after and "srvb" in viewer_after,
      f"a viewer of b1 stops with the reason ({viewer_after.strip()[:160]})")
a1_after = fields("locate_a1_after")
check(exit_code(work, "locate_a1_after") == 0 and a1_after.get("on_this_server") == "yes",
      f"a1 is still found on srva ({a1_after})")
bridge_a1 = read_text(work, "bridge_a1.out")
check(exit_code(work, "bridge_a1") == 0, f"a1's bridge ran to its end ({exit_code(work, 'bridge_a1')})")
check("session a1 is on srva (10.77.0.1:50051): joined" in read_text(work, "bridge_a1.log"),
      "a1's bridge, pointed at srvb, joined a1 on srva")
fades = number(bridge_a1, r"fades (\d+)")
check(fades == 0, f"a1's stylus never faded when srvb died (fades {fades:.0f})")
viewer_a1 = read_text(work, "viewer_a1.out")
sim = re.search(r"sim time ([\d.]+) s \(first frame at ([\d.]+) s\)", viewer_a1)
span = float(sim.group(1)) - float(sim.group(2)) if sim else 0.0
check(exit_code(work, "viewer_a1") == 0 and span >= 7.0,
      f"a1's viewer streamed to its end across srvb's death (sim time span {span:.2f} s of 8)")
before = ctl_sessions(work, "info_a1_before.out").get("a1", {})
later = ctl_sessions(work, "info_a1_after.out").get("a1", {})
ticks_before, ticks_after = int(before.get("ticks", "0")), int(later.get("ticks", "0"))
check(ticks_after > ticks_before + 3000, f"a1 kept ticking on srva ({ticks_before} -> {ticks_after})")
check(exit_code(work, "server_a") == 0, f"srva stopped cleanly ({exit_code(work, 'server_a')})")
finish()
