#!/usr/bin/env python3
"""The softening footing of docs/shear-bands.md:
examples/footing_softening_2d.toml, regularised (l = 0.1) and classical (no
[regularisation]), on three grids (h = l/2, l/3, l/4, 2 points per cell and direction)
and with 3 points per cell on the middle grid, pushed to s/B = 0.06 (the peak is at
0.03); the regularised h = l/2 run also with half the load step. Prints the table (peak load, settlement at the peak, load and
dissipated energy at s/B = 0.05 and 0.1, the points' work against the footing's) and
draws the load-settlement curves, the dissipated energy and the eps_p fields.

Usage: scripts/plot_footing_softening.py [BUILD_DIR] [OUT_DIR]
       (defaults: build, out/footing_softening; figures go to docs/figures/)
Runs go two at a time on one thread each; a run whose folder holds energy.csv and
points_final.csv is not repeated. All ten take about an hour on two cores.
"""
import csv
import math
import re
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "out", "footing_softening")
example = os.path.join(root, "examples", "footing_softening_2d.toml")
L, HALF_B, C0, PUSH = 0.1, 0.5, 10.0, 0.06


def grid_keys(r):
    """h = l / r: two cells beyond the base and the symmetry plane, the top at y = 1.8."""
    h = L / r
    nx, ny = round(2.0 / h) + 4, round(1.5 / h) + 2 + round(0.3 / h)
    return h, [f"grid.origin=[{-2 * h},{-2 * h}]", f"grid.cell_size={h}", f"grid.cells=[{nx},{ny}]"]


def case(classical):
    if not classical:
        return example
    text = open(example).read()  # the same case without its [regularisation] section
    start = text.index("\n[regularisation]\n")
    end = text.index("\n[", start + 1)
    path = os.path.join(out, "classical.toml")
    open(path, "w").write(text[:start] + text[end:])
    return path


runs = []  # (name, label, classical, r, ppc, steps)
for classical in (False, True):
    kind = "classical" if classical else "regularised"
    for r in (2, 3, 4):
        runs.append((f"{kind}_h{r}", f"{kind}, h = l/{r}", classical, r, 2, 60))
    runs.append((f"{kind}_h3_ppc3", f"{kind}, h = l/3, 3 ppc", classical, 3, 3, 60))
runs.append(("regularised_h2_steps120", "regularised, h = l/2, 120 steps", False, 2, 2, 120))

os.makedirs(out, exist_ok=True)
pending, running = [], []
for name, label, classical, r, ppc, steps in runs:
    folder = os.path.join(out, name)
    if os.path.exists(os.path.join(out, name + ".exit")):  # run before (a classical run may stop short)
        continue
    h, keys = grid_keys(r)
    cmd = [os.path.join(build, "bin", "gradmpm"), "run", case(classical), "--out", folder, "-q",
           "--set", "output.vtk_every=5", "--set", "output.plot=false",
           "--set", f"bodies[0].points_per_cell={ppc}", "--set", f"load_steps.count={steps}",
           "--set", f"rigid_boxes[0].displacement=[0.0,{-PUSH}]"]
    for k in keys:
        cmd += ["--set", k]
    pending.append((name, cmd))
# the largest first, so that the two cores stay busy to the end
pending.sort(key=lambda x: -(int(x[0].split("_h")[1][0]) ** 2 * (2 if "ppc3" in x[0] else 1)))
env = dict(os.environ, OMP_NUM_THREADS="1")
while pending or running:
    while pending and len(running) < 2:
        name, cmd = pending.pop(0)
        log = open(os.path.join(out, name + ".log"), "w")
        running.append((name, subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env), time.time()))
        print(f"started {name}", flush=True)
    time.sleep(2)
    for item in list(running):
        name, proc, t0 = item
        if proc.poll() is not None:
            running.remove(item)
            open(os.path.join(out, name + ".seconds"), "w").write(f"{time.time() - t0:.1f}\n")
            open(os.path.join(out, name + ".exit"), "w").write(f"{proc.returncode}\n")
            print(f"{name}: exit {proc.returncode}, {time.time() - t0:.0f} s", flush=True)


def last_fields(folder):
    """x, y, eps_p of the points of the run's last points_NNNN.vtu (ASCII VTK XML)."""
    last = sorted(f for f in os.listdir(folder) if f.startswith("points_") and f.endswith(".vtu"))[-1]
    text = open(os.path.join(folder, last)).read()
    xyz = re.search(r"<Points>\s*<DataArray[^>]*>([^<]*)<", text).group(1).split()
    eps = re.search(r'<DataArray[^>]*Name="eps_p"[^>]*>([^<]*)<', text).group(1).split()
    return [{"x": xyz[3 * i], "y": xyz[3 * i + 1], "eps_p": e} for i, e in enumerate(eps)]


def read(name):
    folder = os.path.join(out, name)
    react = list(csv.DictReader(open(os.path.join(folder, "reactions.csv"))))
    energy = list(csv.DictReader(open(os.path.join(folder, "energy.csv"))))
    s = [0.0] + [-float(x["uy"]) for x in react]
    q = [0.0] + [-float(x["ry"]) / HALF_B / C0 for x in react]
    lam = [float(x["load_factor"]) for x in energy]
    diss = [float(x["dissipation"]) for x in energy]
    work = [float(x["work"]) for x in energy]
    boundary = sum(0.5 * (q[k] + q[k + 1]) * C0 * HALF_B * (s[k + 1] - s[k]) for k in range(len(s) - 1))
    final = os.path.join(folder, "points_final.csv")
    points = list(csv.DictReader(open(final))) if os.path.exists(final) else last_fields(folder)
    seconds = open(os.path.join(out, name + ".seconds")).read().strip() if os.path.exists(
        os.path.join(out, name + ".seconds")) else "?"
    at = lambda xs, ys, x: next((ys[k - 1] + (ys[k] - ys[k - 1]) * (x - xs[k - 1]) / (xs[k] - xs[k - 1])
                                 for k in range(1, len(xs)) if xs[k] >= x - 1e-12), float("nan"))
    k = max(range(len(q)), key=lambda i: q[i])
    return {"s": s, "q": q, "sD": [PUSH * l for l in lam], "D": diss, "peak": q[k], "s_peak": s[k],
            "q05": at(s, q, 0.05), "q10": at(s, q, PUSH), "s_end": s[-1], "D05": at([PUSH * l for l in lam], diss, 0.05), "D10": at([PUSH * l for l in lam], diss, PUSH),
            "balance": work[-1] / boundary - 1.0, "points": points, "seconds": seconds}


results = {name: (label, read(name)) for name, label, *_ in runs}
print("| run | peak q/c | s/B at peak | q/c at s/B = 0.05 | q/c at s/B = 0.06 | dissipated at s/B = 0.05 | "
      "dissipated at s/B = 0.06 | last s/B | points' work / footing's − 1 | seconds |")
print("|---|---|---|---|---|---|---|---|---|---|")
for name, (label, r) in results.items():
    print(f"| {label} | {r['peak']:.3f} | {r['s_peak'] / (2 * HALF_B):.3f} | {r['q05']:.3f} | {r['q10']:.3f} | "
          f"{r['D05']:.4f} | {r['D10']:.4f} | {r['s_end'] / (2 * HALF_B):.4f} | {r['balance']:+.2e} | {r['seconds']} |")

figures = os.path.join(root, "docs", "figures")
os.makedirs(figures, exist_ok=True)
fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.2), dpi=100)
for name, (label, r) in results.items():
    style = ":" if "classical" in name else ("--" if "ppc3" in name or "steps" in name else "-")
    axes[0].plot([x / (2 * HALF_B) for x in r["s"]], r["q"], style, label=label)
    axes[1].plot([x / (2 * HALF_B) for x in r["sD"]], r["D"], style, label=label)
axes[0].set_xlabel("settlement s/B")
axes[0].set_ylabel("footing pressure q/c0")
axes[1].set_xlabel("settlement s/B")
axes[1].set_ylabel("dissipated energy (per unit thickness, half model)")
axes[0].legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(figures, "footing_softening_load.png"))

fig, axes = plt.subplots(2, 3, figsize=(11.0, 6.4), dpi=100, sharex=True, sharey=True)
for row, kind in enumerate(("regularised", "classical")):
    for col, r in enumerate((2, 3, 4)):
        label, res = results[f"{kind}_h{r}"]
        pts = res["points"]
        ax = axes[row][col]
        vmax = sorted(float(p["eps_p"]) for p in pts)[int(0.995 * len(pts))]  # the band, not the footing's corner
        sc = ax.scatter([float(p["x"]) for p in pts], [float(p["y"]) for p in pts],
                        c=[float(p["eps_p"]) for p in pts], s=0.3 * 40 / r ** 2, cmap="viridis", vmin=0, vmax=vmax)
        ax.set_aspect("equal")
        ax.set_xlim(0, 2.0)
        ax.set_title(f"{label}, s/B = {res['s_end'] / (2 * HALF_B):.3f}", fontsize=9)
        fig.colorbar(sc, ax=ax, shrink=0.8, label="eps_p")
fig.tight_layout()
fig.savefig(os.path.join(figures, "footing_softening_eps_p.png"))
print("wrote docs/figures/footing_softening_load.png, footing_softening_eps_p.png")
