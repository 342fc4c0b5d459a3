#!/usr/bin/env python3
"""A strip footing on consolidating clay (examples/footing_consolidation_2d.toml,
docs/pore-pressure.md): the settlement under its centre against time, between the two
limits of the same case, and the excess pore pressure 2 m down.

    /usr/bin/python3 scripts/plot_footing_consolidation.py GRADMPM OUT_DIR

Runs the case three times with GRADMPM (a few seconds each):
  coupled    as written;
  undrained  k = 0 in both materials, to the end of the load's day;
  drained    time steps of 1e12 s (each one drained), the load over 200 of them (Modified
             Cam-Clay's drained settlement depends on the load's step: 0.044, 0.058, 0.066
             and 0.068 m in 10, 30, 100 and 400 steps).
Writes OUT_DIR/{coupled,undrained,drained}/ and OUT_DIR/footing_consolidation.png, and
prints the settlements.
"""
import csv
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

CASE = os.path.join(os.path.dirname(__file__), "..", "examples", "footing_consolidation_2d.toml")
DAY = 86400.0
RUNS = {
    "coupled": [],
    "undrained": ["materials.clay.permeability=0.0", "materials.crust.permeability=0.0", "time.end_time=86400.0"],
    "drained": ["time.dt=1e12", "time.ramp_time=2e14", "time.end_time=2e14"],
}


def run(gradmpm, out, name):
    folder = os.path.join(out, name)
    command = [gradmpm, "run", CASE, "--out", folder, "--quiet"]
    for s in RUNS[name]:
        command += ["--set", s]
    subprocess.run(command, check=True)
    rows = list(csv.DictReader(open(os.path.join(folder, "tracked_points.csv"))))
    return {i: [r for r in rows if int(r["id"]) == i] for i in {int(r["id"]) for r in rows}}


def main(gradmpm, out):
    tracks = {name: run(gradmpm, out, name) for name in RUNS}
    top, deep = 1442, 674
    settlement = {n: [float(t[top][0]["y"]) - float(r["y"]) for r in t[top]] for n, t in tracks.items()}
    coupled = tracks["coupled"]
    days = [float(r["time"]) / DAY for r in coupled[top]]
    s_u, s_d = settlement["undrained"][-1], settlement["drained"][-1]
    print(f"settlement under the centre: undrained {s_u:.4f} m, coupled after 1 day {settlement['coupled'][1]:.4f} m, "
          f"after {days[-1]:.0f} days {settlement['coupled'][-1]:.4f} m, drained {s_d:.4f} m")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    ax1.plot(days[1:], settlement["coupled"][1:], "o-", ms=3, label="coupled u-p")
    ax1.axhline(s_u, color="C1", ls="--", label="undrained (k = 0)")
    ax1.axhline(s_d, color="C2", ls="--", label="drained")
    ax1.set_xscale("log")
    ax1.invert_yaxis()
    ax1.set_xlabel("time (days)")
    ax1.set_ylabel("settlement under the centre (m)")
    ax1.set_title("Strip footing on Modified Cam-Clay, q = 12 kPa, B = 2 m")
    ax1.legend(fontsize=8)
    excess = [float(r["p_excess"]) for r in coupled[deep]]
    ax2.plot(days[1:], [e / 1e3 for e in excess[1:]], "o-", ms=3, color="C3")
    ax2.set_xscale("log")
    ax2.set_xlabel("time (days)")
    ax2.set_ylabel("excess pore pressure (kPa)")
    ax2.set_title("2 m below the centre (p less hydrostatic at its place)")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    png = os.path.join(out, "footing_consolidation.png")
    fig.savefig(png, dpi=120)
    print(f"wrote {png}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
