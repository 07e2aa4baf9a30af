"""Checks two_devices.sh: one bridge process, two devices, two sessions."""
import re
import sys

from checks import check, finish, read_text

work = sys.argv[1]
bridge = read_text(work, "bridge.out")
server = read_text(work, "server.out")
blocks = re.split(r"(?=bridge: device \S+, session )", bridge)[1:]
check(len(blocks) == 2, f"the bridge reports two devices ({len(blocks)})")
for block, session in zip(blocks, ("t1", "t2")):
    check(f"session {session}\n" in block, f"device {session}: its report names its session")
    received = int(re.search(r"force models received (\d+)", block).group(1))
    ticks = int(re.search(r"\((\d+) ticks\)", block).group(1))
    check(received >= 0.9 * ticks, f"device {session}: a model back for >= 90 % of its {ticks} ticks ({received})")
    others = int(re.search(r"models for other sessions or devices (\d+)", block).group(1))
    check(others == 0, f"device {session}: no model of the other session reached it ({others})")
    peak = float(re.search(r"force peak ([\d.]+) N", block).group(1))
    check(peak > 0.3, f"device {session}: pressed 5 mm into its tissue, force peak {peak:.3f} N > 0.3 N")
for session in ("t1", "t2"):
    m = re.search(rf"session {session} \(tissue_block\): ticks (\d+) \(device-clocked (\d+)\)", server)
    check(m is not None and int(m.group(2)) >= 1500,
          f"session {session} was clocked by its device ({m.group(2) if m else '?'} device-clocked ticks)")
m = re.search(r"other-device (\d+)", server)
check(m is not None and int(m.group(1)) == 0, "no pose reached the other device's session")
finish()
