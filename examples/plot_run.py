#!/usr/bin/env python3
"""Plots a dgmpm run's particle outputs (the files its outputs.csv lists).

1D runs: stress and velocity along the bar, one line per output time (colour: time), the exact
solution dashed when the scene has one. 2D runs: one field on the particles, each a cell-sized
square, at up to four output times (reports/plot_fields_2d.py draws them).

    python3 examples/plot_run.py out/two_bar_impact -o two_bar.png
    python3 examples/plot_run.py out/plate_impact --field sigma_yy -o plate.png
"""
import argparse
import csv
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def outputs(directory):
    with open(os.path.join(directory, "outputs.csv")) as f:
        return [(float(r["time"]), r["csv"]) for r in csv.DictReader(f) if r["csv"]]


def plot_1d(directory, listed, output):
    fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True)
    colours = plt.get_cmap("viridis")
    end = max(t for t, _ in listed) or 1.0
    for t, name in listed:
        d = read(os.path.join(directory, name))
        order = sorted(range(len(d["x"])), key=lambda i: d["x"][i])
        x = [d["x"][i] for i in order]
        for ax, field, scale in ((axes[0], "stress", 1e-6), (axes[1], "velocity", 1.0)):
            ax.plot(x, [d[field][i] * scale for i in order], color=colours(t / end), lw=1.2,
                    label=f"t = {t:.3g} s")
            if "exact_" + field in d:
                ax.plot(x, [d["exact_" + field][i] * scale for i in order], "k--", lw=0.7)
    axes[0].set_ylabel("stress (MPa, tension > 0)")
    axes[1].set_ylabel("velocity (m/s)")
    axes[1].set_xlabel("x (m)")
    axes[0].legend(fontsize=7, ncol=2)
    axes[0].set_title(os.path.basename(os.path.normpath(directory)) +
                      ("  (dashed: exact)" if "exact_stress" in read(
                          os.path.join(directory, listed[0][1])) else ""))
    fig.savefig(output, dpi=150)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("directory", help="the run's output directory")
    p.add_argument("--field", default="sigma_xx", help="2D: the particle CSV column to draw")
    p.add_argument("-o", "--output", required=True, help="the PNG to write")
    a = p.parse_args()
    listed = outputs(a.directory)
    if not listed:
        sys.exit(f"{a.directory}: outputs.csv lists no particle CSV file")
    first = read(os.path.join(a.directory, listed[0][1]))
    if "y" not in first:
        plot_1d(a.directory, listed, a.output)
        return
    if a.field not in first:
        fields = [k for k in first if k not in ("x", "y")]
        sys.exit(f"{a.directory}: --field {a.field}: no such column in {listed[0][1]}; "
                 f"fields: {', '.join(fields)}")
    pick = listed if len(listed) <= 4 else [listed[(len(listed) - 1) * k // 3] for k in range(4)]
    here = os.path.dirname(os.path.abspath(__file__))
    script = os.path.join(here, "..", "reports", "plot_fields_2d.py")
    subprocess.run([sys.executable, script, a.directory, "--field", a.field, "--files",
                    *[n for _, n in pick], "--labels", *[f"t = {t:.3g} s" for t, _ in pick],
                    "-o", a.output], check=True)


if __name__ == "__main__":
    main()
