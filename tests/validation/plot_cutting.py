#!/usr/bin/python3
"""Figure for docs/validation.md#cutting from `hapsim-validate cutting` output:
the wound's width over time (the paper's Fig. 6 measurement).
Usage: plot_cutting.py OUT_DIR PNG  (needs Debian's python3-matplotlib)"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = list(csv.DictReader(open(f"{sys.argv[1]}/width_time.csv")))
fig, ax = plt.subplots(figsize=(7, 3.6))
for key, label in [("width_mid_mm", "middle (x = 0), D = 0.1 N·s/m (scene default)"),
                   ("width_q1_mm", "x = -5 mm"), ("width_q3_mm", "x = +5 mm"),
                   ("width_mid_table1_D_mm", "middle, Table 1's D = 3 N·s/m per node")]:
    pts = [(float(r["t_s"]), float(r[key])) for r in rows if r[key]]
    ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, lw=1.2,
            ls="--" if "table1" in key else "-")
ax.axvspan(0.225, 1.225, color="0.9", label="blade cutting (20 mm at 20 mm/s)")
ax.set_xlabel("time [s]")
ax.set_ylabel("distance between paired lip nodes [mm]")
ax.legend(fontsize=7, loc="lower right")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
