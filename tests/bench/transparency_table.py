"""Haptic transparency of one or many bridge runs, from their traces.

For each run directory (trace.csv, bridge.out, condition) it compares, tick
by tick, the force the bridge commanded (fx..fz: after the local model and
the safety chain) with the force the physics computed for the same pose
(phys_fx..: the model that echoes the pose, evaluated at it). Ticks where
neither force exceeds 1 % of the physics peak (free space) are left out of
the error. Prints a markdown table; with --json, one object per run.

  transparency_table.py RUNS_DIR [--json FILE]
  transparency_table.py --trace TRACE.csv   (one trace, figures on stdout)
"""
import csv
import json
import math
import os
import re
import sys


def load_trace(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.append((
                (float(r["x_m"]), float(r["y_m"]), float(r["z_m"])),
                (float(r["fx_N"]), float(r["fy_N"]), float(r["fz_N"])),
                (float(r["phys_fx_N"]), float(r["phys_fy_N"]), float(r["phys_fz_N"])),
                int(r["echo_pose_seq"]), r["watchdog"]))
    return rows


def norm(v):
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def transparency(rows):
    """Figures of one trace (forces in N, work in mJ, errors in % of the physics peak)."""
    known = [r for r in rows if not math.isnan(r[2][0])]
    peak = max((norm(r[2]) for r in known), default=0.0)
    if peak <= 0.0:
        return None
    errors = [norm([r[1][i] - r[2][i] for i in range(3)]) for r in known
              if max(norm(r[1]), norm(r[2])) > 0.01 * peak]
    rms = math.sqrt(sum(e * e for e in errors) / len(errors)) if errors else 0.0
    # Force steps where a new model took over (the echoed seq changed).
    steps = [norm([rows[k][1][i] - rows[k - 1][1][i] for i in range(3)])
             for k in range(1, len(rows)) if rows[k][3] != rows[k - 1][3]]
    # Work done on the hand: positive means the device gave energy.
    work_rendered = work_physics = 0.0
    for k in range(len(rows) - 1):
        dx = [rows[k + 1][0][i] - rows[k][0][i] for i in range(3)]
        work_rendered += sum(rows[k][1][i] * dx[i] for i in range(3))
        if not math.isnan(rows[k][2][0]):
            work_physics += sum(rows[k][2][i] * dx[i] for i in range(3))
    watchdog = {}
    for r in rows:
        watchdog[r[4]] = watchdog.get(r[4], 0) + 1
    return {
        "physics_peak_N": peak,
        "rendered_peak_N": max(norm(r[1]) for r in rows),
        "rms_error_pct": 100.0 * rms / peak,
        "max_error_pct": 100.0 * max(errors, default=0.0) / peak,
        "max_model_step_pct": 100.0 * max(steps, default=0.0) / peak,
        "work_rendered_mJ": 1e3 * work_rendered,
        "work_physics_mJ": 1e3 * work_physics,
        "ticks_compared": len(errors),
        "ticks_not_fresh": sum(n for s, n in watchdog.items() if s != "fresh"),
    }


def bridge_figures(text):
    figures = {}
    m = re.search(r"round trip p50 ([\d.]+) / p99 ([\d.]+)", text)
    if m:
        figures["rtt_p50_ms"], figures["rtt_p99_ms"] = float(m.group(1)), float(m.group(2))
    m = re.search(r"model age p50 [\d.]+ / p99 ([\d.]+)", text)
    if m:
        figures["model_age_p99_ms"] = float(m.group(1))
    m = re.search(r"physics age p50 [\d.]+ / p99 ([\d.]+)", text)
    if m:
        figures["physics_age_p99_ms"] = float(m.group(1))
    m = re.search(r"warnings (\d+), fades (\d+)", text)
    d = re.search(r"disarms (\d+)", text)
    if m and d:
        figures["warn_fade_disarm"] = f"{m.group(1)}/{m.group(2)}/{d.group(1)}"
    m = re.search(r"passivity corrected (\d+) \(bounded (\d+), uncorrected (\d+)\)", text)
    if m:
        figures["passivity_corrected"], figures["passivity_uncorrected"] = int(m.group(1)), int(m.group(3))
    m = re.search(r"poses sent (\d+)(?: \([^)]*\))?; force models received (\d+)", text)
    if m:
        figures["poses"], figures["models"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"regressions \d+, unused (\d+)\)", text)
    if m and "models" in figures:
        unused = int(m.group(1))
        figures["models_unused_pct"] = 100.0 * unused / max(1, unused + figures["models"])
    return figures


def run_figures(directory):
    with open(os.path.join(directory, "condition")) as f:
        name, scene, *link = f.read().split()
    figures = {"run": name, "scene": scene, "link": link[0] if link else ""}
    figures.update(bridge_figures(open(os.path.join(directory, "bridge.out")).read()))
    viewer_out = os.path.join(directory, "viewer.out")
    if os.path.exists(viewer_out):
        v = open(viewer_out).read()
        frames = re.search(r"frames (\d+)", v)
        times = re.search(r"sim time ([\d.]+) s \(first frame at ([\d.]+) s\)", v)
        if frames and times and float(times.group(1)) > float(times.group(2)):
            # Frames per second of session time once streaming (after connecting: a few round trips).
            figures["viewer_fps"] = (int(frames.group(1)) - 1) / (float(times.group(1)) - float(times.group(2)))
    server_out = os.path.join(directory, "server.out")
    m = re.search(r"poses unused (\d+)", open(server_out).read()) if os.path.exists(server_out) else None
    if m and figures.get("poses"):
        figures["poses_unused_pct"] = 100.0 * int(m.group(1)) / figures["poses"]
    t = transparency(load_trace(os.path.join(directory, "trace.csv")))
    if t:
        figures.update(t)
    return figures


def link_key(link):
    """Sorts links by delay, then jitter, then loss."""
    values = dict(item.split("=") for item in link.split(",") if "=" in item)
    return tuple(float(values.get(k, 0)) for k in ("delay_ms", "jitter_ms", "loss"))


def fmt(value, digits=1):
    return "-" if value is None else f"{value:.{digits}f}"


def main(argv):
    if argv[1] == "--trace":
        print(json.dumps(transparency(load_trace(argv[2])), indent=2))
        return
    runs = sorted((run_figures(os.path.join(argv[1], d)) for d in os.listdir(argv[1])),
                  key=lambda r: (link_key(r["link"]), r["scene"]))
    print("| link (trainee, one-way) | scene | round trip p50/p99 ms | model gap / physics age p99 ms | warn/fade/disarm | "
          "physics peak N | RMS error % | max error % | largest step at a model % | work on the hand rendered/physics mJ | "
          "passivity corrected/uncorrected | poses / models unused % | viewer frames/s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['link']} | {r['scene']} | {fmt(r.get('rtt_p50_ms'), 2)}/{fmt(r.get('rtt_p99_ms'), 2)} | "
              f"{fmt(r.get('model_age_p99_ms'), 2)} / {fmt(r.get('physics_age_p99_ms'), 1)} | "
              f"{r.get('warn_fade_disarm', '-')} | "
              f"{fmt(r.get('physics_peak_N'), 3)} | {fmt(r.get('rms_error_pct'))} | {fmt(r.get('max_error_pct'))} | "
              f"{fmt(r.get('max_model_step_pct'))} | {fmt(r.get('work_rendered_mJ'), 2)}/{fmt(r.get('work_physics_mJ'), 2)} | "
              f"{r.get('passivity_corrected', '-')}/{r.get('passivity_uncorrected', '-')} | "
              f"{fmt(r.get('poses_unused_pct'))} / {fmt(r.get('models_unused_pct'))} | {fmt(r.get('viewer_fps'))} |")
    if len(argv) > 3 and argv[2] == "--json":
        with open(argv[3], "w") as f:
            json.dump(runs, f, indent=2)


if __name__ == "__main__":
    main(sys.argv)
