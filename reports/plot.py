"""Plots of `dgmpm report`: reads the CSV files the command wrote and writes PNGs beside them.

Usage: python3 plot.py DIR. Every PNG is written under a temporary name, then renamed.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FixedFormatter, FixedLocator, NullLocator  # noqa: E402

PROBLEM_TITLES = {
    "two_bar": "Two-bar impact (discontinuous), stress at t = 2 m / c",
    "smooth_pulse": "Smooth pulse (sin$^2$ traction), stress at t = 0.8 m / c",
}


def read(directory, name):
    with open(os.path.join(directory, name), newline="") as f:
        return list(csv.DictReader(f))


def save(fig, directory, name):
    path = os.path.join(directory, name)
    tmp = path + ".tmp"
    fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


# One colour per (family, integrator or variant, update), a marker per particle count, dashed for
# the automatic time step: the legend groups what differs.
COLOURS = {
    ("dgmpm", "euler"): "tab:blue",
    ("dgmpm", "rk2"): "tab:green",
    ("mpm", "usl"): "tab:red",
    ("mpm", "usf"): "tab:purple",
    ("mpm", "musl"): "tab:orange",
}
MARKERS = {1: "o", 2: "s", 4: "^", 8: "D"}


def style(row):
    family, variant = row["family"], row["variant"]
    colour = COLOURS.get((family, variant), "black")
    if family == "mpm" and row["update"] == "pic":
        colour = {"tab:red": "tab:pink", "tab:purple": "tab:cyan", "tab:orange": "tab:brown"}[colour]
    return dict(
        color=colour,
        marker=MARKERS.get(int(row["ppc"]), "x"),
        linestyle="--" if row["courant_mode"] == "auto" else "-",
        markersize=5,
        linewidth=1.3,
        markerfacecolor="none" if row["courant_mode"] == "auto" else colour,
    )


def curves(rows, problem):
    """label -> (style row, [(x..)]) of the stable runs, in grid order."""
    out = {}
    for r in rows:
        if r["problem"] != problem or r["stable"] != "1":
            continue
        out.setdefault(r["label"], (r, []))[1].append(r)
    return out


def floor_error(e):
    # Round-off errors (DGMPM at Courant 1) would be 0 or 1e-16 on a log axis: show them at 1e-16.
    return max(float(e), 1e-16)


def error_vs_time(directory, runs, orders, problem):
    fig, ax = plt.subplots(figsize=(10, 6.2))
    for label, (first, rs) in curves(runs, problem).items():
        xs = [float(r["wall_seconds"]) for r in rs]
        ys = [floor_error(r["l2_error"]) for r in rs]
        ax.plot(xs, ys, label=label, **style(first))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall-clock time of the run (s)")
    ax.set_ylabel("relative L2 error of stress")
    ax.set_title(PROBLEM_TITLES[problem])
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8,
              title="method (dashed: auto time step)", title_fontsize=8)
    save(fig, directory, f"error_vs_time_{problem}.png")


def convergence(directory, runs, orders, problem):
    fits = {o["label"]: o for o in orders if o["problem"] == problem}
    fig, ax = plt.subplots(figsize=(10, 6.2))
    for label, (first, rs) in curves(runs, problem).items():
        hs = [float(r["h"]) for r in rs]
        es = [floor_error(r["l2_error"]) for r in rs]
        fit = fits.get(label)
        order = float(fit["order"]) if fit else math.nan
        name = f"{label}: order {order:.2f}" if math.isfinite(order) else f"{label}: round-off"
        st = style(first)
        ax.plot(hs, es, label=name, **st)
    ax.set_xscale("log")
    ax.set_yscale("log")
    # Grids span a decade or two: label each cell size used, not just the powers of ten.
    sizes = sorted({float(r["h"]) for r in runs if r["problem"] == problem})
    ax.xaxis.set_major_locator(FixedLocator(sizes))
    ax.xaxis.set_major_formatter(FixedFormatter([f"{h:.3g}" for h in sizes]))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel("cell size h (m)")
    ax.set_ylabel("relative L2 error of stress")
    ax.set_title(PROBLEM_TITLES[problem] + "\n(order: slope of the least-squares fit of log error on log h)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8)
    save(fig, directory, f"convergence_{problem}.png")


def stability_maps(directory):
    rows = read(directory, "stability_map.csv")
    xs = sorted({float(r["x1"]) for r in rows})
    n = len(xs)
    fig, axes = plt.subplots(2, 2, figsize=(10, 8.6), constrained_layout=True)
    panels = [("Euler", "L2"), ("Euler", "monotone"), ("RK2", "L2"), ("RK2", "monotone")]
    values = [float(r["courant"]) for r in rows]
    vmax = max(values)
    for ax, (scheme, criterion) in zip(axes.flat, panels):
        grid = [[math.nan] * n for _ in range(n)]
        for r in rows:
            if r["scheme"] == scheme and r["criterion"] == criterion:
                i = xs.index(float(r["x1"]))
                j = xs.index(float(r["x2"]))
                grid[j][i] = float(r["courant"])  # row: x2 (vertical axis), column: x1
        image = ax.imshow(grid, origin="lower", extent=(0, 1, 0, 1), vmin=0, vmax=vmax,
                          cmap="viridis", interpolation="nearest")
        finite = [v for row in grid for v in row if math.isfinite(v)]
        ax.set_title(f"{scheme}, {criterion}: C* from {min(finite):.3f} to {max(finite):.3f}",
                     fontsize=10)
        ax.set_xlabel("position of particle 1 in the cell, $x_1$")
        ax.set_ylabel("position of particle 2 in the cell, $x_2$")
        ax.plot([0.25, 0.75], [0.75, 0.25], "w+", markersize=8)  # the regular 2-particle layout
    fig.colorbar(image, ax=axes, shrink=0.8, label="admissible Courant number C*")
    fig.suptitle("Admissible Courant number of two equal particles per cell (+: regular layout)")
    save(fig, directory, "stability_maps.png")


def courant_vs_particles(directory):
    rows = read(directory, "courant_vs_particles.csv")
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for (scheme, criterion), colour, ls in [
        (("Euler", "L2"), "tab:blue", "-"),
        (("Euler", "monotone"), "tab:blue", "--"),
        (("RK2", "L2"), "tab:green", "-"),
        (("RK2", "monotone"), "tab:green", "--"),
    ]:
        sel = [r for r in rows if r["scheme"] == scheme and r["criterion"] == criterion]
        ax.plot([int(r["particles"]) for r in sel], [float(r["courant"]) for r in sel], marker="o",
                color=colour, linestyle=ls, label=f"{scheme}, {criterion}")
    ax.set_xlabel("particles per cell N (regular layout, positions (k + 1/2) / N)")
    ax.set_ylabel("admissible Courant number C*")
    ax.set_ylim(bottom=0)
    ax.set_xticks(range(1, 9))
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title("Admissible Courant number against particle count")
    save(fig, directory, "courant_vs_particles.png")


def main():
    directory = sys.argv[1]
    runs = read(directory, "runs.csv")
    orders = read(directory, "orders.csv")
    for problem in ("two_bar", "smooth_pulse"):
        error_vs_time(directory, runs, orders, problem)
        convergence(directory, runs, orders, problem)
    stability_maps(directory)
    courant_vs_particles(directory)


if __name__ == "__main__":
    main()
