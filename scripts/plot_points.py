#!/usr/bin/env python3
"""Scatter plot of the material points of a 2D gradmpm run, coloured by a field.

Usage: plot_points.py POINTS_FINAL_CSV OUT_PNG [FIELD] [TITLE]
  FIELD: a column of points_final.csv (default syy: vertical Cauchy stress).
Points are drawn at their current positions (x, y); a light copy at their original
positions (X, Y) shows the deformation. For 3D fields use ParaView on points.pvd.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    field = sys.argv[3] if len(sys.argv) > 3 else "syy"
    with open(sys.argv[1], newline="") as f:
        rows = [dict((k, float(v)) for k, v in r.items()) for r in csv.DictReader(f)]
    if not rows:
        raise SystemExit(f"{sys.argv[1]}: no data rows")
    if field not in rows[0]:
        raise SystemExit(f"{sys.argv[1]}: no column {field!r} (have {', '.join(rows[0])})")
    fig, ax = plt.subplots(figsize=(8.0, 4.6), dpi=120)
    ax.scatter([r["X"] for r in rows], [r["Y"] for r in rows], s=2, color="0.85", label="original")
    sc = ax.scatter([r["x"] for r in rows], [r["y"] for r in rows], s=4, c=[r[field] for r in rows], cmap="viridis")
    fig.colorbar(sc, ax=ax, label=field)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(sys.argv[4] if len(sys.argv) > 4 else f"material points coloured by {field}")
    ax.legend(loc="upper right", markerscale=4)
    fig.tight_layout()
    fig.savefig(sys.argv[2], format="png")


if __name__ == "__main__":
    main()
