#!/usr/bin/env python3
"""Plots the elastic column under self-weight against its closed form, from gradmpm's
column_check.csv (written by a case with [output] check = "column").

Usage: plot_column.py COLUMN_CHECK_CSV OUT_PNG [TITLE]
Left: vertical Cauchy stress against original height Y (points, and the line
-rho0 g (H0 - Y)). Right: current height y against Y (points, and the closed form).
gradmpm embeds this script and runs it after such a case; it also runs on its own.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = sorted((dict((k, float(v)) for k, v in r.items()) for r in csv.DictReader(f)), key=lambda r: r["Y"])
    if not rows:
        raise SystemExit(f"{sys.argv[1]}: no data rows")
    Y = [r["Y"] for r in rows]
    fig, (a, b) = plt.subplots(1, 2, figsize=(9.0, 4.2), dpi=120)
    a.plot([r["stress_exact"] for r in rows], Y, "k-", lw=1.2, label="closed form")
    a.plot([r["stress"] for r in rows], Y, "o", ms=3, color="tab:red", label="material points")
    a.set_xlabel("vertical Cauchy stress")
    a.set_ylabel("original height Y")
    a.legend(loc="best")
    a.grid(True, alpha=0.3)
    b.plot(Y, [r["y_exact"] for r in rows], "k-", lw=1.2, label="closed form (Hencky)")
    b.plot(Y, [r["y"] for r in rows], "o", ms=3, color="tab:blue", label="material points")
    b.plot([0, Y[-1]], [0, Y[-1]], ":", color="0.5", lw=1, label="y = Y (undeformed)")
    b.set_xlabel("original height Y")
    b.set_ylabel("current height y")
    b.legend(loc="best")
    b.grid(True, alpha=0.3)
    fig.suptitle(sys.argv[3] if len(sys.argv) > 3 else "Elastic column under self-weight")
    fig.tight_layout()
    fig.savefig(sys.argv[2], format="png")


if __name__ == "__main__":
    main()
