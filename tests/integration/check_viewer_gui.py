"""Checks of integration.viewer_gui: pictures judged against the camera
model (png_image.project, written independently of the viewer's C++)."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import check, finish  # noqa: E402
from png_image import patch_difference, pixel, project, read_png  # noqa: E402

work, camera = sys.argv[1], [float(v) for v in sys.argv[2].split(",")]
os.chdir(work)
target, distance, yaw, pitch, fov = camera[:3], camera[3], camera[4], camera[5], camera[6]
W, H = 640, 480
BACKGROUND = (33, 38, 46)  # the renderer's clear colour (0.13, 0.15, 0.18)


def to_px(p):
    return project(p, target, distance, yaw, pitch, fov, W, H)


before, after = read_png("before.png"), read_png("after.png")
check(before[0] == W and before[1] == H and after[0] == W, "pictures are 640x480")

# Not blank, and the tissue in its part colours (skin over fat over muscle:
# reddish, red > green > blue) covers a good part of the view.
for name, image in (("before", before), ("after", after)):
    reddish = background = 0
    for y in range(0, H, 4):
        for x in range(0, W, 4):
            r, g, b = pixel(image, x, y)
            if (r, g, b) == BACKGROUND:
                background += 1
            elif r > g + 15 and g >= b - 10:
                reddish += 1
    total = (W // 4) * (H // 4)
    check(reddish > 0.3 * total, f"{name}: tissue colours cover {100 * reddish / total:.0f} % of the view (> 30 %)")
    check(background < 0.6 * total, f"{name}: background is {100 * background / total:.0f} % (< 60 %: not blank)")

# The needle where the known pose puts it: tip at (4, 0, +3) mm before and
# (4, 0, -1.5) mm during the press, shaft straight up (+z). Steel is grey-blue
# (blue >= red), unlike any tissue colour.
for name, image, tip_z in (("before", before, 3e-3), ("after", after, -1.5e-3)):
    steel = 0
    for up in (4e-3, 8e-3, 12e-3):
        x, y = to_px((0.004, 0.0, tip_z + up))
        # the shaft is ~2 px wide here: take the bluest pixel of a 5x5 patch
        best = max((pixel(image, x + dx, y + dy) for dx in range(-2, 3) for dy in range(-2, 3)),
                   key=lambda p: p[2] - p[0])
        if best[2] >= best[0] and best[2] > 110:
            steel += 1
    check(steel == 3, f"{name}: the needle shaft is drawn at its projected pose ({steel}/3 points steel)")

# The dimple, on pictures of the tissue alone (tool and arrow hidden, so
# only the surface can differ): around the entry point the picture changes,
# 12 mm away it does not.
before_tissue, after_tissue = read_png("before_tissue.png"), read_png("after_tissue.png")
near = to_px((0.004, 0.0, 0.0))
far = to_px((0.004 - 0.012, 0.010, 0.0))
d_near = patch_difference(before_tissue, after_tissue, near[0], near[1], 8)
d_far = patch_difference(before_tissue, after_tissue, far[0], far[1], 8)
check(d_near > 2.0, f"the dimple region changed: mean |diff| {d_near:.1f} levels (> 2)")
check(d_far < 0.5, f"12 mm away nothing changed: mean |diff| {d_far:.2f} levels (< 0.5)")

# The window lived through a lost frame, a server restart and a closed session.
# Pacing without vsync: one draw per new frame at most, never above 60/s;
# a paused session draws at the 4 Hz idle rate (+ the first frames).
for name, most in (("paced_live", 3 * 60 + 3), ("paced_paused", 3 * 4 + 6)):
    m = re.search(r"frames (\d+), drawn (\d+)", open(f"{name}.out").read())
    frames, drawn = (int(m.group(1)), int(m.group(2))) if m else (-1, -1)
    print(f"{name}: {frames} frames received, {drawn} drawn in 3 s without vsync")
    check(m is not None and 0 < drawn <= most, f"{name}: drawn {drawn} <= {most}")
    if name == "paced_live":
        check(drawn <= frames + 13, f"{name}: drawn {drawn} <= frames {frames} + the idle refreshes (12) + 1")

out = open("survive.out").read()
log = open("survive.log").read()
m = re.search(r"reconnects (\d+)", out)
check(m is not None and int(m.group(1)) >= 1, f"the viewer reconnected ({m.group(1) if m else 'no'} reconnects)")
check("refused" in log, "the lost frame was detected and the stream resynced")
check(re.search(r"lost: .*(NOT_FOUND|not found|ended)", log) is not None,
      "the closed session was reported")
survived = read_png("survived.png")
check(survived[0] == 800, "the window still drew its last picture (800x600)")
panel = pixel(survived, 20, 20)
check(panel != BACKGROUND, f"the panels are drawn at the top-left {panel}")
finish()
