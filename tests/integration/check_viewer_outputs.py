"""Checks viewer_outputs.sh: every file each viewer run was asked for exists
and holds what its format says."""
import os
import sys

from checks import check, finish

work = sys.argv[1]


def obj_counts(name):
    v = f = 0
    with open(f"{work}/{name}") as lines:
        for line in lines:
            v += line.startswith("v ")
            f += line.startswith("f ")
    return v, f


def nonempty(name):
    path = f"{work}/{name}"
    return os.path.exists(path) and os.path.getsize(path) > 0


for name in ("replay.png", "replay_plot.png", "live.png", "recorded.png"):
    ok = nonempty(name) and open(f"{work}/{name}", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    check(ok, f"{name} is a PNG")
for name in ("replay.obj", "live.obj", "replayed.obj"):
    v, f = obj_counts(name) if nonempty(name) else (0, 0)
    check(v > 100 and f > 100, f"{name}: {v} vertices, {f} faces")
check(nonempty("replay.glb") and open(f"{work}/replay.glb", "rb").read(4) == b"glTF", "replay.glb is binary glTF")
check(nonempty("recorded.vtk") and open(f"{work}/recorded.vtk").readline().startswith("# vtk DataFile"),
      "recorded.vtk is legacy VTK")
check(nonempty("live.frames"), "the stream was recorded alongside the picture and the export")


def obj_points(name):
    with open(f"{work}/{name}") as lines:
        return [tuple(map(float, line.split()[1:4])) for line in lines if line.startswith("v ")]


def vtk_points(name):
    words = open(f"{work}/{name}").read().split()
    at = words.index("POINTS")
    n = int(words[at + 1])
    values = list(map(float, words[at + 3:at + 3 + 3 * n]))
    return [tuple(values[i:i + 3]) for i in range(0, 3 * n, 3)]


# The recording replays into the very mesh its run exported (OBJ prints
# positions to 1e-9 m: the viewer's mesh is quantised to 1 um).
if nonempty("recorded.vtk") and nonempty("replayed.obj"):
    a, b = vtk_points("recorded.vtk"), obj_points("replayed.obj")
    worst = max((max(abs(p - q) for p, q in zip(u, v)) for u, v in zip(a, b)), default=float("inf"))
    check(len(a) == len(b) and worst < 1e-8,
          f"replaying the recording gives the exported mesh: {len(b)}/{len(a)} vertices, worst {worst:.1e} m")
check("off screen" in open(f"{work}/live.log").read(), "without a display the viewer said it draws off screen")
# The peak force: the counting viewer's, from its frames, against the server's own.
import re  # noqa: E402
viewer_peak = float(re.search(r"peak tool force ([\d.]+) N", open(f"{work}/counting.out").read()).group(1))
server_peak = float(re.search(r"peak_tool_force_n=([\d.]+)", open(f"{work}/info.txt").read()).group(1))
check(server_peak > 0.5, f"the needle punctured the skin (server peak {server_peak:.4f} N)")
check(abs(viewer_peak - server_peak) <= 0.0006,
      f"the frames carry the 1 kHz peak: viewer {viewer_peak:.3f} N, server {server_peak:.4f} N")
finish()
