"""Perceptual deadband coding, side by side with the every-tick stream.

For each scene, two bridge traces of the same scripted motion: `every`
(a pose and a model every tick) and `deadband` (bridge --pose-deadband-mm,
server --model-deadband). Per run: the share of servo ticks that sent a
pose and that received a model, overall and in steady contact (the
insertion's hold); and tick by tick, whether the force the deadband run
rendered is within the force JND of the every-tick run's: |F_db - F_every|
<= jnd x max(|F_every|, floor) (Weber fraction 7 %, floor 0.05 N), over the
ticks where either run pushes more than 1 % of its peak.

  deadband_table.py RUNS_DIR [--jnd 0.07] [--floor-n 0.05]
RUNS_DIR holds SCENE-every/trace.csv and SCENE-deadband/trace.csv.
"""
import csv
import math
import os
import sys


def load(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.append({
                "f": (float(r["fx_N"]), float(r["fy_N"]), float(r["fz_N"])),
                "phase": r["phase"],
                "pose_sent": int(r["pose_sent"]),
                "model_taken": int(r["model_taken"]),
            })
    return rows


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def shares(rows, phase=None):
    chosen = [r for r in rows if phase is None or r["phase"] == phase]
    if not chosen:
        return None, None
    return (100.0 * sum(r["pose_sent"] for r in chosen) / len(chosen),
            100.0 * sum(r["model_taken"] for r in chosen) / len(chosen))


def agreement(every, deadband, jnd, floor_n):
    n = min(len(every), len(deadband))
    peak = max(max(norm(r["f"]) for r in every[:n]), max(norm(r["f"]) for r in deadband[:n]))
    compared = within = 0
    worst = 0.0
    for k in range(n):
        a, b = every[k]["f"], deadband[k]["f"]
        if max(norm(a), norm(b)) <= 0.01 * peak:
            continue
        compared += 1
        diff = norm([a[i] - b[i] for i in range(3)])
        within += diff <= jnd * max(norm(a), floor_n)
        worst = max(worst, diff)
    return compared, (100.0 * within / compared if compared else 0.0), worst, peak


def fmt(v, digits=1):
    return "-" if v is None else f"{v:.{digits}f}"


def main(argv):
    runs_dir = argv[1]
    jnd = float(argv[argv.index("--jnd") + 1]) if "--jnd" in argv else 0.07
    floor_n = float(argv[argv.index("--floor-n") + 1]) if "--floor-n" in argv else 0.05
    scenes = sorted({d.rsplit("-", 1)[0] for d in os.listdir(runs_dir) if "-" in d})
    print("| scene | stream | poses sent % of ticks (all / steady contact) | models received % of ticks (all / steady "
          "contact) | ticks within the JND of every-tick % | largest difference N | peak N |")
    print("|---|---|---|---|---|---|---|")
    for scene in scenes:
        every = load(os.path.join(runs_dir, f"{scene}-every", "trace.csv"))
        deadband = load(os.path.join(runs_dir, f"{scene}-deadband", "trace.csv"))
        compared, within, worst, peak = agreement(every, deadband, jnd, floor_n)
        for name, rows in (("every tick", every), ("deadband", deadband)):
            pose_all, model_all = shares(rows)
            pose_hold, model_hold = shares(rows, "hold")
            agree = f"{within:.2f} ({compared} ticks)" if name == "deadband" else "-"
            print(f"| {scene} | {name} | {fmt(pose_all)} / {fmt(pose_hold)} | {fmt(model_all)} / {fmt(model_hold)} | "
                  f"{agree} | {fmt(worst, 3) if name == 'deadband' else '-'} | {peak:.3f} |")


if __name__ == "__main__":
    main(sys.argv)
