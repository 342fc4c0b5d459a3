#!/usr/bin/env python3
"""Summarises bench-results.csv (scripts/bench): fitted exponents and a figure.

Usage: plot_bench.py BENCH_CSV OUT_PNG
For every case and thread count it fits t ~ dof^k (least squares in log-log) to the
time of one Newton iteration (wall_s where the CSV has it, else the sum of the phases)
and to numeric factorisation + solve alone, prints k, the ratio (everything else: the
iteration less factorisation and solve) / (factorisation + solve) at every size and the
speed-up of the multithreaded assembly; the figure shows one iteration and
factorisation + solve against dof.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PHASES = ["pattern_s", "assembly_s", "analysis_s", "factor_s", "solve_s", "update_s"]


def fit(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f)]
    groups = {}
    for r in rows:
        groups.setdefault((r["case"], int(r["threads"])), []).append(r)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120)
    for (case, threads), rs in sorted(groups.items()):
        rs.sort(key=lambda r: int(r["dof"]))
        dof = [int(r["dof"]) for r in rs]
        # wall_s (the load step's wall time per Newton iteration) where the CSV has it: the
        # phases leave out the Dirichlet elimination, residual norms and copies.
        total = [float(r["wall_s"]) if r.get("wall_s") else sum(float(r[p]) for p in PHASES) for r in rs]
        solver = [float(r["factor_s"]) + float(r["solve_s"]) for r in rs]
        other = [t - s for t, s in zip(total, solver)]
        k_total, k_solver = (fit(dof, total), fit(dof, solver)) if len(rs) > 1 else (float("nan"),) * 2
        print(f"{case:11s} threads {threads}: dof {dof[0]}..{dof[-1]}  exponent one iteration {k_total:.2f}, "
              f"factor+solve {k_solver:.2f}")
        print("    ratio other/(factor+solve): " + ", ".join(f"{d} dof {o / s:.2f}" for d, o, s in zip(dof, other, solver)))
        ax = axes[0] if threads == 1 else axes[1]
        ax.loglog(dof, total, marker="o", label=f"{case}: one Newton iteration")
        ax.loglog(dof, solver, marker="x", ls="--", label=f"{case}: factorisation + solve")
    for (case, threads), rs in sorted(groups.items()):
        if threads > 1 and (case, 1) in groups:
            one = {int(r["dof"]): float(r["assembly_s"]) for r in groups[(case, 1)]}
            for r in rs:
                d = int(r["dof"])
                if d in one and float(r["assembly_s"]) > 0:
                    print(f"{case:11s} dof {d}: assembly speed-up with {threads} threads {one[d] / float(r['assembly_s']):.2f}")
    for ax, title in zip(axes, ["1 thread", "all threads"]):
        ax.set_xlabel("degrees of freedom")
        ax.set_ylabel("seconds")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
