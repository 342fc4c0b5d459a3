#!/usr/bin/env python3
"""Figures of docs/gradient-study.md from the CSV files of build/studies/gradient_study.

Usage: plot_gradient_study.py STUDY_DIR FIGURE_DIR
Writes FIGURE_DIR/study_profiles.png (strain along the bi-material column: classical,
reference, and the two choices at 32 cells) and FIGURE_DIR/study_errors.png (error
against the reference under grid refinement, per variant and choice).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    src, dst = sys.argv[1], sys.argv[2]
    os.makedirs(dst, exist_ok=True)
    prof = rows(os.path.join(src, "study_profiles.csv"))
    err = rows(os.path.join(src, "study_errors.csv"))
    variants = sorted({r["variant"] for r in prof})

    fig, axes = plt.subplots(1, len(variants), figsize=(5.2 * len(variants), 4.2), dpi=120, squeeze=False)
    styles = {"reference": ("k", "-", "reference: 1024 cells, 1 step, smoothed at the end"),
              "end+grid": ("tab:blue", "--", "apply = end, fields = grid (32 cells)"),
              "each_step+points": ("tab:red", ":", "apply = each_step, fields = points (32 cells)")}
    for ax, v in zip(axes[0], variants):
        cls = [(float(r["Y"]), float(r["eps_classical"])) for r in prof if r["variant"] == v and r["choice"] == "end+grid"]
        ax.step([c[0] for c in cls], [-c[1] for c in cls], where="mid", color="0.6", lw=1.2, label="classical (32 cells)")
        for choice, (color, ls, label) in styles.items():
            pts = [(float(r["Y"]), float(r["eps_gradient"])) for r in prof if r["variant"] == v and r["choice"] == choice]
            ax.plot([p[0] for p in pts], [-p[1] for p in pts], color=color, ls=ls, lw=1.8, label=label)
        ax.set_xlabel("original height Y")
        ax.set_ylabel("compressive vertical strain")
        ax.set_title(f"{v}, l = 1: bi-material column under self-weight")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(dst, "study_profiles.png"))

    fig, ax = plt.subplots(figsize=(6.0, 4.2), dpi=120)
    for v, marker in zip(variants, "os"):
        for choice, color in (("end+grid", "tab:blue"), ("each_step+points", "tab:red")):
            pts = sorted((int(r["cells"]), float(r["max_error"])) for r in err if r["variant"] == v and r["choice"] == choice)
            ax.loglog([10.0 / p[0] for p in pts], [p[1] for p in pts], marker=marker, color=color,
                      label=f"{v}, {choice}")
    ax.set_xlabel("cell size h (H0 = 10, l = 1)")
    ax.set_ylabel("max |eps_g - reference| / peak")
    ax.set_title("Gradient strain against the fine single-step reference")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(dst, "study_errors.png"))


if __name__ == "__main__":
    main()
