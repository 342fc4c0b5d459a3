#!/usr/bin/env python3
"""The final shape of a collapsed block (examples/vertical_cut_dynamic_2d.toml): run-out,
final slope angle, and a picture of the points coloured by eps_p.

    /usr/bin/python3 scripts/plot_runout.py RUN_DIR OUT_PNG [--initial-width 8] [--initial-height H] [--column WIDTH]

Run-out: the largest x of any point (the toe). The surface is the highest point in each
column of width 0.25; the slope angle is the least-squares line through the surface points
between 10 % and 90 % of the final height. Prints the figures and writes the picture.
"""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def surface(points, width):
    top = {}
    for x, y in points:
        k = int(math.floor(x / width))
        top[k] = max(top.get(k, -1e300), y)
    return sorted(((k + 0.5) * width, y) for k, y in top.items())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("png")
    ap.add_argument("--initial-width", type=float, default=8.0)
    ap.add_argument("--initial-height", type=float, default=None, help="default: the width")
    ap.add_argument("--column", type=float, default=0.25, help="width of the surface's columns")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(f"{a.run}/points_final.csv")))
    pts = [(float(r["x"]), float(r["y"])) for r in rows]
    eps = [float(r["eps_p"]) for r in rows]
    toe = max(x for x, _ in pts)
    top = surface(pts, a.column)
    h0 = a.initial_height if a.initial_height is not None else a.initial_width
    height = max(y for _, y in top)
    band = [(x, y) for x, y in top if 0.1 * height <= y <= 0.9 * height and x > 2 * a.column]
    n = len(band)
    mx = sum(x for x, _ in band) / n
    my = sum(y for _, y in band) / n
    slope = sum((x - mx) * (y - my) for x, y in band) / sum((x - mx) ** 2 for x, _ in band)
    angle = math.degrees(math.atan(-slope))
    print(f"run-out: toe at x = {toe:.4g} ({toe - a.initial_width:.4g} beyond the initial face); "
          f"final height {height:.4g} (initial {h0:g}); slope angle {angle:.1f} degrees (surface between 10 and 90 % "
          f"of the height)")
    fig, ax = plt.subplots(figsize=(9, 4.5))
    sc = ax.scatter([x for x, _ in pts], [y for _, y in pts], c=eps, s=2, cmap="viridis", vmax=2.0)
    fig.colorbar(sc, ax=ax, label="eps_p (clipped at 2)")
    ax.plot([0, a.initial_width, a.initial_width], [h0, h0, 0], "k--", lw=1, label="initial")
    xs = [mx - 0.5 * a.initial_width, mx + 0.5 * a.initial_width]
    ax.plot(xs, [my + slope * (x - mx) for x in xs], "r-", lw=1, label=f"slope {angle:.1f} deg")
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="upper right")
    ax.set_title(f"final: toe at x = {toe:.3g}")
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
