#!/usr/bin/env python3
"""Mandel's problem from the coupled u-p MPM against its closed form
(examples/mandel_2d.toml, docs/pore-pressure.md).

    /usr/bin/python3 scripts/plot_mandel.py TRACKED_POINTS_CSV OUT_PNG

The closed form (Abousleiman, Cheng, Cui, Detournay & Roegiers 1996; Biot coefficient 1,
incompressible grains):
p(x, t) = 2 p_0 sum_n sin a_n / (a_n - sin a_n cos a_n) (cos(a_n x / a) - cos a_n) exp(-a_n^2 c t / a^2),
tan a_n = (1 - nu) / (nu_u - nu) a_n, p_0 = F B (1 + nu_u) / (3 a).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

E, NU, N, KF, K, GW, A, F = 1e7, 0.2, 0.4, 2.2e9, 1e-4, 1000 * 9.80665, 1.0, 1e4
G = E / (2 * (1 + NU))
B = (KF / N) / (E / (3 * (1 - 2 * NU)) + KF / N)
NUU = (3 * NU + B * (1 - 2 * NU)) / (3 - B * (1 - 2 * NU))
C = 2 * (K / GW) * B**2 * G * (1 - NU) * (1 + NUU) ** 2 / (9 * (1 - NUU) * (NUU - NU))
P0 = F * B * (1 + NUU) / (3 * A)


def roots(count=300):
    r = (1 - NU) / (NUU - NU)
    out = []
    for i in range(1, count + 1):
        lo, hi = (i - 1) * math.pi + 1e-12, (i - 0.5) * math.pi - 1e-12
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            if math.tan(mid) - r * mid < 0:
                lo = mid
            else:
                hi = mid
        out.append(0.5 * (lo + hi))
    return out


ROOTS = roots()


def mandel(x, t):
    s = 0.0
    for a in ROOTS:
        s += math.sin(a) / (a - math.sin(a) * math.cos(a)) * (math.cos(a * x / A) - math.cos(a)) * math.exp(-a * a * C * t / A**2)
    return 2 * s


def main(tracked, out):
    by_time = {}
    with open(tracked) as f:
        for r in csv.DictReader(f):
            by_time.setdefault(float(r["time"]), []).append((float(r["x"]), float(r["p"]) / P0, int(r["id"])))
    times = sorted(t for t in by_time if t > 0)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    centre = [next(p for x, p, i in by_time[t] if i == 0) for t in times]
    x0 = next(x for x, p, i in by_time[times[0]] if i == 0)
    T = [C * t / A**2 for t in times]
    ax1.plot(T, centre, "o", ms=3, label="MPM (point at x = h/4, y = h/4)")
    ts = [times[-1] * k / 400 for k in range(1, 401)]
    ax1.plot([C * t / A**2 for t in ts], [mandel(x0, t) for t in ts], "-", label="Mandel (closed form)")
    ax1.axhline(1.0, color="grey", lw=0.6)
    ax1.set_xlabel("$T = c t / a^2$")
    ax1.set_ylabel("$p / p_0$ at the centre")
    ax1.set_title("The Mandel-Cryer effect")
    ax1.legend(fontsize=8)
    for k, Tk in enumerate([0.005, 0.05, 0.1, 0.2, 0.5]):
        t = min(times, key=lambda s: abs(C * s / A**2 - Tk))
        pts = sorted(by_time[t])
        colour = f"C{k}"
        ax2.plot([x for x, _, _ in pts], [p for _, p, _ in pts], "o", ms=3, color=colour)
        xs = [A * i / 100 for i in range(101)]
        ax2.plot(xs, [mandel(x, t) for x in xs], "-", lw=1, color=colour, label=f"T = {Tk:g}")
    ax2.set_xlabel("$x / a$ (0: the centre, 1: the drained side)")
    ax2.set_ylabel("$p / p_0$")
    ax2.set_title("p across the sample: MPM (dots), closed form (lines)")
    ax2.legend(fontsize=8)
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
