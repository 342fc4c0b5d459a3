#!/usr/bin/env python3
"""Terzaghi's isochrones from the coupled u-p MPM against the series solution
(examples/consolidation_1d.toml, docs/pore-pressure.md).

    /usr/bin/python3 scripts/plot_consolidation.py TRACKED_POINTS_CSV OUT_PNG

The example's column: H = 1, c_v = 1 (the time is T_v), p_0 = q m_v / (m_v + n / K_f);
p(z, T) = sum_m 2 p_0 / M sin(M z / H) exp(-M^2 T), M = pi (2 m + 1) / 2, z from the
drained top.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

H, Q, E, N, KF = 1.0, 1.0e4, 1.0e7, 0.4, 2.2e9
P0 = Q * (1 / E) / (1 / E + N / KF)
TIMES = [0.01, 0.05, 0.1, 0.2, 0.5, 1.0]


def series(z, T):
    p = 0.0
    for m in range(400):
        M = math.pi * (2 * m + 1) / 2
        p += 2 / M * math.sin(M * z / H) * math.exp(-M * M * T)
    return p


def main(tracked, out):
    rows = {}
    with open(tracked) as f:
        for r in csv.DictReader(f):
            rows.setdefault(float(r["time"]), []).append((float(r["x"]), float(r["p"])))
    fig, ax = plt.subplots(figsize=(5.5, 5))
    for k, T in enumerate(TIMES):
        t = min(rows, key=lambda s: abs(s - T))
        pts = sorted(rows[t])
        colour = f"C{k}"
        ax.plot([p / P0 for _, p in pts], [H - x for x, _ in pts], "o", ms=3, color=colour)
        zs = [H * i / 200 for i in range(201)]
        ax.plot([series(z, T) for z in zs], zs, "-", lw=1, color=colour, label=f"$T_v$ = {T:g}")
    ax.invert_yaxis()
    ax.set_xlabel("$p / p_0$")
    ax.set_ylabel("depth below the drained top $z / H$")
    ax.set_title("Terzaghi consolidation: MPM (dots), series (lines)")
    ax.legend(loc="lower left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
