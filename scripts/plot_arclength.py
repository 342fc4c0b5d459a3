#!/usr/bin/env python3
"""The softening bar's load-displacement curve traced by arc-length control against its
closed form (examples/softening_bar_arclength_1d.toml, docs/mpm.md "Arc-length control").

    /usr/bin/python3 scripts/plot_arclength.py REACTIONS_CSV OUT_PNG

The closed form (uniaxial strain, finite-strain von Mises with linear softening in the
weak zone, the rest elastic): at the weak zone's plastic strain kappa its log strain is
eps_w = ((3 mu + H) kappa + sigma_y) / (2 mu), the bar's Cauchy stress
sigma = 2 mu (eps_w - kappa) e^-eps_w, the rest of the bar at E eps e^-eps = sigma, and
the grip at u = (L - w)(e^eps_o - 1) + w (e^eps_w - 1).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

E, MU, H, SY, L, W = 1000.0, 500.0, -750.0, 0.9, 1.0, 0.025


def elastic_strain(sigma):
    eps = sigma / E
    for _ in range(50):
        eps -= (E * eps * math.exp(-eps) - sigma) / (E * (1 - eps) * math.exp(-eps))
    return eps


def closed_form():
    u, f = [], []
    eps_y = elastic_strain(SY * math.exp(-SY / E))  # (the weak zone yields at tau = sigma_y)
    for k in range(50):  # elastic loading
        e = eps_y * k / 49
        u.append(L * math.expm1(e))
        f.append(E * e * math.exp(-e))
    kmax = SY / -H
    for k in range(1, 200):  # softening
        kappa = kmax * k / 200
        eps_w = ((3 * MU + H) * kappa + SY) / (2 * MU)
        sigma = 2 * MU * (eps_w - kappa) * math.exp(-eps_w)
        u.append((L - W) * math.expm1(elastic_strain(sigma)) + W * math.expm1(eps_w))
        f.append(sigma)
    return u, f


def main():
    rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["name"] == "end"]
    u = [0.0] + [float(r["ux"]) for r in rows]
    f = [0.0] + [float(r["rx"]) for r in rows]
    cu, cf = closed_form()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, zoom in zip(axes, (False, True)):
        ax.plot([1e3 * x for x in cu], cf, "-", color="0.6", lw=3, label="closed form")
        ax.plot([1e3 * x for x in u], f, "o-", ms=3, lw=1, color="C0", label="gradmpm, arc-length")
        if zoom:  # the snap-back: force and displacement fall together
            ax.set_xlim(0.6, 0.95)
            ax.set_ylim(0.55, 0.95)
            ax.set_title("past the peak (steps 18 to 34: snap-back)")
        else:
            ax.set_title("classical softening bar, arc-length control")
        ax.set_xlabel("grip displacement u (1e-3)")
        ax.set_ylabel("force")
        ax.legend(loc="lower right")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
