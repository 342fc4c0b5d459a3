#!/usr/bin/env python3
"""The figures of docs/shear-bands.md: runs examples/softening_bar_1d.toml on three grids
(h = l/2, l/4, l/8), with a doubled length scale, and classically (no [regularisation]),
then plots eps_p along the bar and the force-elongation curves.

Usage: scripts/plot_shear_bands.py [BUILD_DIR] [OUT_DIR]
       (defaults: build, out/shear_bands; figures go to docs/figures/)
"""
import csv
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "out", "shear_bands")
example = os.path.join(root, "examples", "softening_bar_1d.toml")
L = 0.025


def run(name, h, extra=(), classical=False):
    case = example
    if classical:  # the same case without its [regularisation] section
        text = open(example).read().split("\n[regularisation]\n")[0] + "\n[output]\nvtk_every = 0\n"
        case = os.path.join(out, name + ".toml")
        os.makedirs(out, exist_ok=True)
        open(case, "w").write(text)
    cmd = [os.path.join(build, "bin", "gradmpm"), "run", case, "--out", os.path.join(out, name), "-q",
           "--set", f"grid.cell_size={h}", "--set", f"grid.cells=[{round(1 / h) + 2}]",
           "--set", "output.vtk_every=0", "--set", "output.plot=false"]
    for e in extra:
        cmd += ["--set", e]
    subprocess.run(cmd, check=not classical)
    folder = os.path.join(out, name)
    rows = list(csv.DictReader(open(os.path.join(folder, "reactions.csv"))))
    u = [0.0] + [float(r["ux"]) for r in rows]
    f = [0.0] + [float(r["rx"]) for r in rows]
    x, k = [], []
    final = os.path.join(folder, "points_final.csv")
    if os.path.exists(final):
        pts = sorted((float(r["X"]), float(r["eps_p"])) for r in csv.DictReader(open(final)))
        x, k = [p[0] for p in pts], [p[1] for p in pts]
    return u, f, x, k


runs = {f"l = {L}, h = l/{n}": run(f"reg_h{n}", L / n) for n in (2, 4, 8)}
runs[f"l = {2 * L}, h = l/8"] = run("reg_2l", L / 4, ["regularisation.length_scale=0.05"])
classical = {f"classical, h = {L / n}": run(f"classical_h{n}", L / n, classical=True) for n in (2, 4, 8)}

fig, ax = plt.subplots(1, 2, figsize=(11, 4))
for label, (u, f, x, k) in runs.items():
    ax[0].plot(x, k, label=label)
    ax[1].plot([1e3 * v for v in u], f, label=label)
for label, (u, f, x, k) in classical.items():
    ax[1].plot([1e3 * v for v in u], f, "--", label=label + " (stops at the peak)")
ax[0].set_xlabel("X")
ax[0].set_ylabel("eps_p at u = 1.05e-3")
ax[0].set_xlim(0.2, 0.8)
ax[0].legend(fontsize=8)
ax[1].set_xlabel("elongation u (1e-3)")
ax[1].set_ylabel("axial force (per area)")
ax[1].set_xlim(0.8, 1.06)
ax[1].set_ylim(0.75, 1.0)
ax[1].legend(fontsize=7)
fig.suptitle("softening bar (examples/softening_bar_1d.toml): implicit-gradient regularisation, m = 2")
fig.tight_layout()
path = os.path.join(root, "docs", "figures", "softening_bar.png")
fig.savefig(path, dpi=110)
print("wrote", path)
