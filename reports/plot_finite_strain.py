#!/usr/bin/env python3
"""Plots the report's finite-strain study from its CSV files (written by `dgmpm report`).

    python3 reports/plot_finite_strain.py REPORT_DIR

finite_strain_profiles.png: the nominal stress along the half-space (SVK shocks and fan) and the
impacted neo-Hookean bar at the end time, every method against the exact solution, with a close-up
of each front.
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "DGMPM auto": dict(color="tab:blue", marker="o"),
    "DGMPM C = 1": dict(color="tab:green", marker="s"),
    "MPM USL C = 0.5": dict(color="tab:red", marker="^"),
    "MPM MUSL C = 0.5": dict(color="tab:purple", marker="v"),
}
TITLES = {
    "svk_2gpa": "SVK, 2 GPa tension",
    "svk_20gpa": "SVK, 20 GPa tension",
    "svk_fan": "SVK, 20 GPa compression (fan)",
    "nh_impact": "neo-Hookean, +-100 m/s",
}


def main():
    directory = sys.argv[1]
    data = defaultdict(list)  # (case, label) -> [(x, F, P)]
    with open(os.path.join(directory, "finite_strain_profiles.csv")) as f:
        for r in csv.DictReader(f):
            data[(r["case"], r["label"])].append(
                (float(r["x"]), float(r["F"]), float(r["nominal_stress"])))
    cases = [c for c in TITLES if any(k[0] == c for k in data)]
    fig, axes = plt.subplots(2, len(cases), figsize=(4.5 * len(cases), 7), squeeze=False,
                             constrained_layout=True)
    for col, case in enumerate(cases):
        exact = sorted(data[(case, "exact")])
        # The front: where the exact stress changes most; the close-up spans 20 cells around it.
        jumps = [abs(b[2] - a[2]) for a, b in zip(exact, exact[1:])]
        front = exact[max(range(len(jumps)), key=jumps.__getitem__)][0]
        if case == "nh_impact":
            front = max(x for x, _, p in exact if abs(p) > 0.5 * max(abs(q) for _, _, q in exact))
        for row, (lo, hi) in enumerate([(0.0, 6.0), (front - 0.4, front + 0.4)]):
            ax = axes[row][col]
            for label in ["exact"] + list(STYLE):
                points = sorted(p for p in data.get((case, label), []) if lo <= p[0] <= hi)
                if not points:
                    continue
                x = [p[0] for p in points]
                stress = [p[2] * 1e-9 for p in points]
                if label == "exact":
                    ax.plot(x, stress, color="black", lw=1.5, label="exact")
                else:
                    ax.plot(x, stress, ms=2.5 if row else 1.5, lw=0.7, label=label,
                            **STYLE[label])
            ax.set_xlabel("X (m)")
            ax.set_ylabel("nominal stress P (GPa)")
            ax.set_title(TITLES[case] + (" (front)" if row else ""), fontsize=10)
        axes[0][col].legend(fontsize=7)
    fig.savefig(os.path.join(directory, "finite_strain_profiles.png"), dpi=110)


if __name__ == "__main__":
    main()
