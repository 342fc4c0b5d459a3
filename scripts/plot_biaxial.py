#!/usr/bin/env python3
"""The biaxial figures and table of docs/shear-bands.md: examples/biaxial_2d.toml on three
grids (h = l/2, l/3, l/4), regularised and classical (no [regularisation]), and with
l = 1/18 (h = l/2 of it on the middle grid); then eps_p on the deformed specimens side by
side, the platen force against its displacement, and the band's inclination and thickness
(the same measure as tests/test_shear_band_2d.cpp) printed as a table.

Usage: scripts/plot_biaxial.py [BUILD_DIR] [OUT_DIR]
       (defaults: build, out/biaxial; figures go to docs/figures/)
A run whose folder already holds reactions.csv is not repeated (a run stopped short is
plotted at its last VTU file). The regularised h = l/4 run alone takes well over an hour
on one core: for docs/shear-bands.md it was stopped at platen 0.018 (step 160).
"""
import csv
import math
import os
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "out", "biaxial")
example = os.path.join(root, "examples", "biaxial_2d.toml")
L = 1.0 / 12.0


def grid(r):
    h = 1.0 / (24 * r)
    return h, [f"grid.origin=[-0.25,{-2 * h}]", f"grid.cell_size={h}", f"grid.cells=[{round(36 * r)},{round(52 * r + 2)}]"]


def last_vtu(folder):
    """The step of the run's last points_NNNN.vtu (ASCII VTK XML), and x, y, eps_p of its points."""
    last = sorted(f for f in os.listdir(folder) if f.startswith("points_") and f.endswith(".vtu"))[-1]
    text = open(os.path.join(folder, last)).read()
    xyz = re.search(r"<Points>\s*<DataArray[^>]*>([^<]*)<", text).group(1).split()
    eps = re.search(r'<DataArray[^>]*Name="eps_p"[^>]*>([^<]*)<', text).group(1).split()
    points = [{"x": float(xyz[3 * i]), "y": float(xyz[3 * i + 1]), "eps_p": float(e)} for i, e in enumerate(eps)]
    return int(last[len("points_"):-len(".vtu")]), points


def run(name, r, classical=False, extra=()):
    folder = os.path.join(out, name)
    h, keys = grid(r)
    if not os.path.exists(os.path.join(folder, "reactions.csv")):
        case = example
        if classical:  # the same case without its [regularisation] section
            text = open(example).read()
            start = text.index("\n[regularisation]\n")
            end = text.index("\n[", start + 1)
            case = os.path.join(out, name + ".toml")
            os.makedirs(out, exist_ok=True)
            open(case, "w").write(text[:start] + text[end:])
        # a classical run may stop short of the end (points inverted in its one-cell band):
        # its VTU files keep the last fields
        cmd = [os.path.join(build, "bin", "gradmpm"), "run", case, "--out", folder, "-q",
               "--set", f"output.vtk_every={10 if classical else 20}", "--set", "output.plot=false"]
        # the figures' runs end at platen 0.045 (180 steps), the example's first 180 steps
        end = ["rigid_boxes[0].displacement=[0.0,-0.045]", "load_steps.count=180"]
        for k in keys + end + list(extra):
            cmd += ["--set", k]
        subprocess.run(cmd, check=not classical)
    reactions = list(csv.DictReader(open(os.path.join(folder, "reactions.csv"))))
    final = os.path.join(folder, "points_final.csv")
    if os.path.exists(final):
        points = [dict((k, float(v)) for k, v in p.items()) for p in csv.DictReader(open(final))]
        row = reactions[-1]
    else:  # a run stopped short: its last fields
        step, points = last_vtu(folder)
        row = next(x for x in reactions if int(x["step"]) == step)
    return {"h": h, "points": points, "at": -float(row["uy"]), "f_at": -float(row["ry"]),
            "u": [-float(x["uy"]) for x in reactions], "f": [-float(x["ry"]) for x in reactions]}


def band(points, spacing):
    """Inclination (degrees from the loading axis) and thickness: test_shear_band_2d.cpp's measure."""
    ys, xs, ws = [], [], []
    y0 = 0.25
    while y0 <= 0.75 + 1e-9:
        row = sorted((p["x"], p["eps_p"]) for p in points if abs(p["y"] - y0) < spacing / 2)
        y0 += spacing
        if len(row) < 5:
            continue
        k = max(range(len(row)), key=lambda i: row[i][1])
        half = row[k][1] / 2
        i, j = k, k
        while i > 0 and row[i - 1][1] > half:
            i -= 1
        while j + 1 < len(row) and row[j + 1][1] > half:
            j += 1
        if i == 0 or j + 1 == len(row):
            continue
        cross = lambda a, c: row[a][0] + (half - row[a][1]) / (row[c][1] - row[a][1]) * (row[c][0] - row[a][0])
        left, right = cross(i - 1, i), cross(j, j + 1)
        ys.append(y0 - spacing)
        xs.append(0.5 * (left + right))
        ws.append(right - left)
    n = len(ys)
    if n < 3:
        return float("nan"), float("nan")
    my, mx = sum(ys) / n, sum(xs) / n
    slope = sum((y - my) * (x - mx) for y, x in zip(ys, xs)) / sum((y - my) ** 2 for y in ys)
    return math.degrees(math.atan(slope)), sum(ws) / n * math.cos(math.atan(slope))


regularised = {f"h = l/{2 * r:g}": run(f"reg_r{r:g}", r) for r in (1, 1.5, 2)}
classical = {f"h = l/{2 * r:g}": run(f"classical_r{r:g}", r, classical=True) for r in (1, 1.5, 2)}
# l = 1/18 (and its weak patch) against the test's l = 1/12, both at h = 1/36 and platen 0.0125
half_l = run("reg_l18_platen0.0125", 1.5, extra=["rigid_boxes[0].displacement=[0.0,-0.0125]", "load_steps.count=50",
    "regularisation.length_scale=0.055555555555555556",
    "bodies[0].max=[0.055555555555555556,0.055555555555555556]",
    "bodies[1].polygon=[[0.055555555555555556,0.0],[1.0,0.0],[1.0,2.0],[0.0,2.0],[0.0,0.055555555555555556],"
    "[0.055555555555555556,0.055555555555555556]]"])

print("| run | h | platen displacement | force | inclination (deg) | thickness | thickness / l | thickness / h |")
print("|---|---|---|---|---|---|---|---|")
for label, group, l in (("regularised, l = 1/12", regularised, L), ("classical", classical, None)):
    for name, r in group.items():
        a, t = band(r["points"], r["h"] / 2)
        print(f"| {label}, {name} | {r['h']:.4f} | {r['at']:.4f} | {r['f_at']:.4f} | {a:.2f} | {t:.4f} | "
              f"{f'{t / l:.2f}' if l else '–'} | {t / r['h']:.2f} |")
a, t = band(half_l["points"], half_l["h"] / 2)
print(f"| regularised, l = 1/18, h = l/2 | {half_l['h']:.4f} | {half_l['at']:.4f} | {half_l['f_at']:.4f} | "
      f"{a:.2f} | {t:.4f} | {t * 18:.2f} | {t / half_l['h']:.2f} |")

figures = os.path.join(root, "docs", "figures")
os.makedirs(figures, exist_ok=True)
fig, axes = plt.subplots(2, 3, figsize=(9.0, 10.0), dpi=100, sharex=True, sharey=True)
for row, group, title in ((0, regularised, "regularised, l = 1/12"), (1, classical, "classical")):
    for col, (name, r) in enumerate(group.items()):
        ax = axes[row][col]
        vmax = max(p["eps_p"] for p in r["points"] if p["y"] > 0.25)  # the band, not the corner
        sc = ax.scatter([p["x"] for p in r["points"]], [p["y"] for p in r["points"]],
                        c=[p["eps_p"] for p in r["points"]], s=1.0 * r["h"] * 24, cmap="viridis", vmin=0, vmax=vmax)
        ax.set_aspect("equal")
        ax.set_title(f"{title}\n{name}, platen {r['at']:.4f}", fontsize=9)
        fig.colorbar(sc, ax=ax, shrink=0.7, label="eps_p")
fig.tight_layout()
fig.savefig(os.path.join(figures, "biaxial_2d_eps_p.png"))

fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=110)
for name, r in regularised.items():
    ax.plot(r["u"], r["f"], label=f"regularised, {name}")
ax.plot(half_l["u"], half_l["f"], "--", label="regularised, l = 1/18, h = l/2")
for name, r in classical.items():
    ax.plot(r["u"], r["f"], ":", label=f"classical, {name}")
ax.set_xlabel("platen displacement")
ax.set_ylabel("platen force (per unit thickness)")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(figures, "biaxial_2d_force.png"))
print("wrote docs/figures/biaxial_2d_eps_p.png, biaxial_2d_force.png")
