#!/usr/bin/env python3
"""Plots a field of a 2D run's particles (particles_NNN.csv) at chosen output times, each
particle drawn as a filled cell-sized square, side by side with one shared colour scale.

    python3 reports/plot_fields_2d.py OUT_DIR --field sigma_xx --times 5e-4 1e-3 -o plate.png

--times picks, for each time asked, the scene's nearest output time (particles_NNN.csv is the
NNN-th output time in increasing order); or pass --files (with --labels for the panel titles).
--deformed draws a finite-strain run's particles in the current configuration: each particle's
cell mapped by its deformation gradient F about its current position X + u, with the bodies'
reference outline dashed.
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Polygon, Rectangle  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("directory", help="the run's output directory")
    p.add_argument("--scene", help="the scene file (output times, cell size)")
    p.add_argument("--times", type=float, nargs="+", help="output times to plot (needs --scene)")
    p.add_argument("--files", nargs="+", help="particle CSV names instead of --times")
    p.add_argument("--labels", nargs="+", help="panel titles for --files")
    p.add_argument("--cell", type=float, nargs=2, metavar=("DX", "DY"),
                   help="cell size (default: from --scene, else the smallest particle spacing)")
    p.add_argument("--field", default="sigma_xx")
    p.add_argument("--scale", type=float, default=1e-6, help="multiplies the field (MPa: 1e-6)")
    p.add_argument("--unit", default="MPa")
    p.add_argument("--title", default="")
    p.add_argument("--deformed", action="store_true",
                   help="finite strain: cells mapped by F at the current positions")
    p.add_argument("-o", "--output", required=True)
    a = p.parse_args()

    labels, files = [], []
    cell = None
    if a.scene:
        with open(a.scene) as f:
            scene = json.load(f)
        cell = scene["grid"]["cell_size"]
    if a.cell:
        cell = a.cell
    if a.files:
        files = [os.path.join(a.directory, f) for f in a.files]
        labels = a.labels if a.labels and len(a.labels) == len(a.files) else a.files
    else:
        if not (a.scene and a.times):
            sys.exit("plot_fields_2d.py: give --scene with --times, or --files")
        out_times = sorted(scene["output"]["times"])
        for t in a.times:
            k = min(range(len(out_times)), key=lambda i: abs(out_times[i] - t))
            files.append(os.path.join(a.directory, f"particles_{k:03d}.csv"))
            labels.append(f"t = {out_times[k]:.3g} s")
    data = [read(f) for f in files]
    values = [[v * a.scale for v in d[a.field]] for d in data]
    lo = min(min(v) for v in values)
    hi = max(max(v) for v in values)
    if lo == hi:
        hi = lo + 1
    fig, axes = plt.subplots(1, len(files), figsize=(4.8 * len(files), 4.0), squeeze=False,
                             constrained_layout=True)
    cmap = plt.get_cmap("viridis")
    norm = matplotlib.colors.Normalize(vmin=lo, vmax=hi)
    for ax, d, v, label in zip(axes[0], data, values, labels):
        xs, ys = d["x"], d["y"]
        if cell is None:
            def spacing(v):
                u = sorted(set(v))
                return min(b - a for a, b in zip(u, u[1:])) if len(u) > 1 else 1.0
            h = (spacing(xs), spacing(ys))
        else:
            h = cell
        if a.deformed:
            corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            shapes = []
            for i in range(len(xs)):
                f = ((d["F_xx"][i], d["F_xy"][i]), (d["F_yx"][i], d["F_yy"][i]))
                cx, cy = d["current_x"][i], d["current_y"][i]
                shapes.append(Polygon([(cx + f[0][0] * u * h[0] + f[0][1] * w * h[1],
                                        cy + f[1][0] * u * h[0] + f[1][1] * w * h[1])
                                       for u, w in corners]))
            lo_x, hi_x = min(xs) - h[0] / 2, max(xs) + h[0] / 2
            lo_y, hi_y = min(ys) - h[1] / 2, max(ys) + h[1] / 2
            ax.add_patch(Rectangle((lo_x, lo_y), hi_x - lo_x, hi_y - lo_y, fill=False,
                                   linestyle="--", edgecolor="grey", lw=0.8))
            cxs, cys = d["current_x"], d["current_y"]
            pad = max(h)
            ax.set_xlim(min(lo_x, min(cxs)) - pad, max(hi_x, max(cxs)) + pad)
            ax.set_ylim(min(lo_y, min(cys)) - pad, max(hi_y, max(cys)) + pad)
        else:
            shapes = [Rectangle((x - h[0] / 2, y - h[1] / 2), h[0], h[1]) for x, y in zip(xs, ys)]
            ax.set_xlim(min(xs) - h[0] / 2, max(xs) + h[0] / 2)
            ax.set_ylim(min(ys) - h[1] / 2, max(ys) + h[1] / 2)
        pc = PatchCollection(shapes, cmap=cmap, norm=norm, edgecolor="none")
        pc.set_array(v)
        ax.add_collection(pc)
        ax.set_aspect("equal")
        ax.set_title(label)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    cb = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes[0].tolist())
    cb.set_label(f"{a.field} ({a.unit})")
    if a.title:
        fig.suptitle(a.title)
    fig.savefig(a.output, dpi=120)


if __name__ == "__main__":
    main()
