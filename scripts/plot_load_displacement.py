#!/usr/bin/env python3
"""Plots load against displacement for every named constraint block, from gradmpm's
reactions.csv (one row per converged step and block: step,load,name,rx,ry,rz,ux,uy,uz).

Usage: plot_load_displacement.py REACTIONS_CSV OUT_PNG [TITLE]
For each block the component with the largest final displacement is plotted: |r| (the
reaction force, per unit thickness in plane strain) against |u| (the block's mean
displacement). A collapse load is where the curve levels off.
gradmpm embeds this script and runs it after a case with a named block.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    blocks = {}
    with open(sys.argv[1], newline="") as f:
        for r in csv.DictReader(f):
            blocks.setdefault(r["name"], []).append(r)
    if not blocks:
        raise SystemExit(f"{sys.argv[1]}: no data rows")
    fig, ax = plt.subplots(figsize=(6.0, 4.2), dpi=120)
    for name, rows in blocks.items():
        final = rows[-1]
        comp = max("xyz", key=lambda c: abs(float(final["u" + c])))
        u = [0.0] + [abs(float(r["u" + comp])) for r in rows]
        f = [0.0] + [abs(float(r["r" + comp])) for r in rows]
        ax.plot(u, f, "o-", ms=3, label=f"{name} ({comp})")
    ax.set_xlabel("|mean displacement| of the block")
    ax.set_ylabel("|reaction force|")
    ax.grid(alpha=0.3)
    ax.legend()
    if len(sys.argv) > 3:
        ax.set_title(sys.argv[3], fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], format="png")  # the staged name does not end in .png


if __name__ == "__main__":
    main()
