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
from matplotlib.colors import LogNorm, Normalize  # noqa: E402
from matplotlib.ticker import FixedFormatter, FixedLocator, NullLocator  # noqa: E402

PROBLEM_TITLES = {
    "two_bar": "Two-bar impact (discontinuous), stress at t = 2 m / c",
    "smooth_pulse": "Smooth pulse (sin$^2$ traction), stress at t = 0.8 m / c",
    "plane_wave_p_30deg": "2D P plane wave at 30 degrees, stress after one period",
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


# One colour per (family, integrator or variant, update), a marker per particle count; dashed
# means the automatic time step, in every figure.
COLOURS = {
    ("dgmpm", "euler"): "tab:blue",
    ("dgmpm", "rk2"): "tab:green",
    ("mpm", "usl"): "tab:red",
    ("mpm", "usf"): "tab:purple",
    ("mpm", "musl"): "tab:orange",
    ("dgmpm", "dcu-euler"): "tab:blue",
    ("dgmpm", "dcu-rk2"): "tab:green",
    ("dgmpm", "ctu-euler"): "tab:olive",
    ("dgmpm", "ctu-rk2"): "tab:brown",
}
MARKERS = {1: "o", 2: "s", 4: "^", 8: "D"}
ROUNDOFF = 1e-12  # errors below: exact transport, drawn in the round-off band


def style(row, thin=False):
    family, variant = row["family"], row["variant"]
    colour = COLOURS.get((family, variant), "black")
    if family == "mpm" and row["update"] == "pic":
        colour = {"tab:red": "tab:pink", "tab:purple": "tab:cyan", "tab:orange": "tab:brown"}[colour]
    return dict(
        color=colour,
        marker=MARKERS.get(int(row["ppc"]), "x"),
        linestyle="--" if row["courant_mode"] == "auto" else "-",
        markersize=3 if thin else 5,
        linewidth=0.7 if thin else 1.3,
        alpha=0.45 if thin else 1.0,
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


def error_axis(ax, series, xkey):
    """Plots (label, style, rows); errors below ROUNDOFF go to a grey band at the foot."""
    errors = [float(r["l2_error"]) for _, _, rs in series for r in rs]
    real = [e for e in errors if e >= ROUNDOFF]
    low = min(real) / 10 if real else 1e-6
    band = (low / 10, low)
    any_roundoff = False
    for label, st, rs in series:
        xs = [float(r[xkey]) for r in rs]
        ys = []
        for r in rs:
            e = float(r["l2_error"])
            any_roundoff |= e < ROUNDOFF
            ys.append(e if e >= ROUNDOFF else (band[0] * band[1]) ** 0.5)
        ax.plot(xs, ys, label=label, **st)
    ax.set_xscale("log")
    ax.set_yscale("log")
    if any_roundoff:
        ax.axhspan(*band, color="0.85", zorder=0)
        ax.text(0.01, (band[0] * band[1]) ** 0.5, " round-off (< 1e-12): exact transport",
                transform=ax.get_yaxis_transform(), va="center", fontsize=7, color="0.3")
        ax.set_ylim(bottom=band[0])
    ax.grid(True, which="both", alpha=0.3)
    ax.set_ylabel("relative L2 error of stress")


def error_vs_time(directory, runs, orders, problem):
    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 7.5), sharey=True, constrained_layout=True)
    cs = curves(runs, problem)
    fixed = [(label, style(first), rs) for label, (first, rs) in cs.items()
             if first["courant_mode"] == "fixed"]
    auto = [(label, style(first), rs) for label, (first, rs) in cs.items()
            if first["courant_mode"] == "auto"]
    mpm = [(label, style(first, thin=True), rs) for label, (first, rs) in cs.items()
           if first["family"] == "mpm"]
    error_axis(left, fixed, "wall_seconds")
    error_axis(right, auto + mpm, "wall_seconds")
    left.set_title("every method at the common Courant number", fontsize=10)
    right.set_title("DGMPM at its automatic time step (dashed); MPM of the left, thin", fontsize=10)
    for ax in (left, right):
        ax.set_xlabel("wall-clock time of the run (s)")
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=3)
    fig.suptitle(PROBLEM_TITLES[problem])
    save(fig, directory, f"error_vs_time_{problem}.png")


def convergence(directory, runs, orders, problem):
    fits = {o["label"]: o for o in orders if o["problem"] == problem}
    fig, ax = plt.subplots(figsize=(10, 6.2))
    series = []
    for label, (first, rs) in curves(runs, problem).items():
        fit = fits.get(label)
        order = float(fit["order"]) if fit else math.nan
        name = f"{label}: order {order:.2f}" if math.isfinite(order) else f"{label}: round-off"
        series.append((name, style(first), rs))
    error_axis(ax, series, "h")
    # Reference slopes 1 and 2 from the coarsest grid's median error down to the finest grid.
    sizes = sorted({float(r["h"]) for r in runs if r["problem"] == problem})
    coarsest = [float(r["l2_error"]) for _, _, rs in series for r in rs
                if float(r["h"]) == sizes[-1] and float(r["l2_error"]) >= ROUNDOFF]
    if coarsest:
        e0 = sorted(coarsest)[len(coarsest) // 2]
        for order, ls in ((1, ":"), (2, "-.")):
            ax.plot([sizes[-1], sizes[0]], [e0, e0 * (sizes[0] / sizes[-1]) ** order], color="black",
                    linestyle=ls, linewidth=1.0, label=f"reference slope {order}")
    # Grids span a decade or two: label each cell size used, not just the powers of ten.
    ax.xaxis.set_major_locator(FixedLocator(sizes))
    ax.xaxis.set_major_formatter(FixedFormatter([f"{h:.3g}" for h in sizes]))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel("cell size h (m)")
    ax.set_title(PROBLEM_TITLES[problem] + "\n(order: slope of the least-squares fit of log error on log h)",
                 fontsize=10)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=7)
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
        (("Euler", "monotone"), "tab:blue", ":"),
        (("RK2", "L2"), "tab:green", "-"),
        (("RK2", "monotone"), "tab:green", ":"),
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
    ax.set_title("Admissible Courant number against particle count (dotted: monotone)")
    save(fig, directory, "courant_vs_particles.png")


def stability_maps_2d(directory):
    rows = read(directory, "stability_map_2d.csv")
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    xs = sorted({float(r["x"]) for r in rows})
    n = len(xs)
    values = [float(r["courant"]) for r in rows]
    fig, axes = plt.subplots(1, len(settings), figsize=(5.2 * len(settings), 4.6),
                             constrained_layout=True)
    for ax, setting in zip(axes, settings):
        grid = [[math.nan] * n for _ in range(n)]
        for r in rows:
            if r["setting"] == setting:
                grid[xs.index(float(r["y"]))][xs.index(float(r["x"]))] = float(r["courant"])
        norm = (LogNorm(vmin=min(values), vmax=1.0) if min(values) < 0.1
                else Normalize(vmin=min(values), vmax=1.0))
        image = ax.imshow(grid, origin="lower", extent=(0, 1, 0, 1), norm=norm, cmap="viridis",
                          interpolation="nearest")
        finite = [v for row in grid for v in row if math.isfinite(v)]
        ax.set_title(f"{setting}: C* from {min(finite):.3f} to {max(finite):.3f}", fontsize=10)
        ax.set_xlabel("particle position in the cell, x")
        ax.set_ylabel("particle position in the cell, y")
    fig.colorbar(image, ax=axes, shrink=0.85, label="admissible Courant number C*")
    fig.suptitle("Plane strain (nu = 0.3), one particle per cell: C* against its position")
    save(fig, directory, "stability_maps_2d.png")


def courant_vs_particles_2d(directory):
    rows = read(directory, "courant_vs_particles_2d.csv")
    panels = [("advection", "l2"), ("advection", "monotone"), ("elastic", "l2")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), sharey=True, constrained_layout=True)
    for ax, (model, criterion) in zip(axes, panels):
        for flux in ("dcu", "ctu"):
            for integrator in ("euler", "rk2"):
                sel = [r for r in rows if (r["model"], r["criterion"], r["flux"], r["integrator"])
                       == (model, criterion, flux, integrator)]
                colour = COLOURS[("dgmpm", f"{flux}-{integrator}")]
                ax.plot([int(r["particles"]) for r in sel], [float(r["courant"]) for r in sel],
                        marker="o", color=colour, linestyle=":" if criterion == "monotone" else "-",
                        label=f"{flux.upper()} {'Euler' if integrator == 'euler' else 'RK2'}")
        ax.set_title(f"{model}, {criterion}" + (" (dotted: monotone)" if criterion == "monotone" else ""),
                     fontsize=10)
        ax.set_xlabel("regular particles per cell N")
        ax.set_xticks(sorted({int(r["particles"]) for r in rows}))
        ax.grid(True, alpha=0.3)
        ax.set_ylim(bottom=0)
    axes[0].set_ylabel("admissible Courant number C*")
    axes[0].legend(fontsize=8)
    fig.suptitle("2D: admissible Courant number against regular particles per cell")
    save(fig, directory, "courant_vs_particles_2d.png")


def main():
    directory = sys.argv[1]
    runs = read(directory, "runs.csv")
    orders = read(directory, "orders.csv")
    for problem in ("two_bar", "smooth_pulse"):
        error_vs_time(directory, runs, orders, problem)
        convergence(directory, runs, orders, problem)
    stability_maps(directory)
    courant_vs_particles(directory)
    waves = read(directory, "plane_waves.csv")
    wave_orders = read(directory, "plane_wave_orders.csv")
    error_vs_time(directory, waves, wave_orders, "plane_wave_p_30deg")
    convergence(directory, waves, wave_orders, "plane_wave_p_30deg")
    stability_maps_2d(directory)
    courant_vs_particles_2d(directory)


if __name__ == "__main__":
    main()
