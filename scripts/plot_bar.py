#!/usr/bin/env python3
"""Plots the strain along the bi-material bar (the paper's Figure 2) from gradmpm's CSVs.

Usage: plot_bar.py BAR_CSV POINTS_CSV OUT_PNG [TITLE]
  BAR_CSV     nodal values (bar.csv): x, strain_classical, strain_gradient, strain_exact, ...
  POINTS_CSV  material-point values (bar_points.csv): x, strain_classical, ...
The classical strain is drawn from the points, where it is exact and shows the jump;
the gradient strain from the nodes, with the closed-form solution dashed.
gradmpm embeds this script and runs it after a bar case; it also runs on its own.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no data rows")
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    nodes = read_columns(sys.argv[1])
    points = read_columns(sys.argv[2])
    title = sys.argv[4] if len(sys.argv) > 4 else "Bi-material bar"

    fig, ax = plt.subplots(figsize=(7.0, 4.2), dpi=120)
    order = sorted(range(len(points["x"])), key=lambda i: points["x"][i])
    ax.step([points["x"][i] for i in order], [points["strain_classical"][i] for i in order],
            where="mid", color="0.35", lw=1.6, label="classical (at points)")
    ax.plot(nodes["x"], nodes["strain_gradient"], color="tab:red", lw=2.0,
            label="gradient (at nodes)")
    ax.plot(nodes["x"], nodes["strain_exact"], color="k", lw=1.0, ls="--",
            label="closed form")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("axial strain [-]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(sys.argv[3], format="png")


if __name__ == "__main__":
    main()
