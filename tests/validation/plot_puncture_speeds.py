#!/usr/bin/python3
"""Figure for docs/validation.md#acupuncture from `hapsim-validate puncture`
output: force against depth for each insertion speed of the speed sweep
(default scene). Usage: plot_puncture_speeds.py OUT_DIR PNG
(needs Debian's python3-matplotlib)."""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
for speed in (2, 5, 10, 20):
    rows = list(csv.DictReader(open(f"{sys.argv[1]}/force_depth_{speed}mm_s.csv")))
    d = [float(r["depth_mm"]) for r in rows]
    f = [float(r["force_N"]) for r in rows]
    for ax in axes:
        ax.plot(d, f, lw=1.0, label=f"{speed} mm/s")
axes[0].set_xlim(-0.1, 1.2)
axes[0].set_title("skin and the top of the fat")
axes[1].set_xlim(0, 30)
axes[1].set_title("to 30 mm (muscle top at 9.2 mm)")
for ax in axes:
    ax.axhline(2.5, color="0.5", ls=":", lw=0.8)
    ax.set_xlabel("tip depth below the skin top [mm]")
    ax.set_ylabel("|force on the needle| [N]")
    ax.grid(alpha=0.3)
axes[1].legend(fontsize=7)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
