#!/usr/bin/env python3
"""Plots the report's solids-that-yield study from its CSV files (written by `dgmpm report`).

    python3 reports/plot_plasticity.py REPORT_DIR

plastic_wave_profiles.png: sigma_xx and eps_p_xx of the uniaxial-strain wave at three times, every
method against the exact solution; error_vs_time_plastic_wave.png: relative L2 errors against the
run's wall time; viscoplastic_precursor.png: the Perzyna precursor's profiles and jump.
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "DGMPM 1 ppc": dict(color="tab:blue", marker="o"),
    "DGMPM 2 ppc": dict(color="tab:green", marker="s"),
    "MPM USL 2 ppc": dict(color="tab:red", marker="^"),
    "MPM USF 2 ppc": dict(color="tab:purple", marker="v"),
}


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def profiles(directory):
    data = defaultdict(list)  # (label, time) -> [(x, sigma, eps)]
    for r in rows(os.path.join(directory, "plastic_wave_profiles.csv")):
        data[(r["label"], float(r["time"]))].append(
            (float(r["x"]), float(r["sigma_xx"]), float(r["eps_p_xx"])))
    times = sorted({t for _, t in data})
    fig, axes = plt.subplots(2, len(times), figsize=(5 * len(times), 7), squeeze=False,
                             constrained_layout=True)
    for col, t in enumerate(times):
        for label in ["exact"] + list(STYLE):
            points = sorted(data.get((label, t), []))
            if not points:
                continue
            x = [p[0] for p in points]
            sigma = [p[1] * 1e-6 for p in points]
            eps = [p[2] * 1e3 for p in points]
            if label == "exact":
                kw = dict(color="black", lw=1.5, label="exact")
            else:
                kw = dict(STYLE[label], ms=3, lw=0.8, label=label)
            axes[0][col].plot(x, sigma, **kw)
            axes[1][col].plot(x, eps, **kw)
        axes[0][col].set_title(f"t = {t:.3g} s")
        axes[0][col].set_ylabel("sigma_xx (MPa)")
        axes[1][col].set_ylabel("eps_p_xx (1e-3)")
        axes[1][col].set_xlabel("x (m)")
    axes[0][0].legend(fontsize=8)
    fig.suptitle("uniaxial-strain elastoplastic wave, 50 cells")
    fig.savefig(os.path.join(directory, "plastic_wave_profiles.png"), dpi=110)


def error_vs_time(directory):
    runs = defaultdict(list)
    for r in rows(os.path.join(directory, "plastic_wave_runs.csv")):
        runs[r["label"]].append(r)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    for label, rs in runs.items():
        rs.sort(key=lambda r: int(r["cells"]))
        wall = [float(r["wall_seconds"]) for r in rs]
        for ax, key in zip(axes, ["l2_error_sigma_xx", "l2_error_eps_p_xx"]):
            ax.loglog(wall, [float(r[key]) for r in rs], **STYLE.get(label, {}), label=label)
    for ax, name in zip(axes, ["sigma_xx", "eps_p_xx"]):
        ax.set_xlabel("wall time (s): set-up and time loop")
        ax.set_ylabel(f"relative L2 error of {name}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("uniaxial-strain elastoplastic wave at 4.17e-4 s: error against run time "
                 "(one point per grid)")
    fig.savefig(os.path.join(directory, "error_vs_time_plastic_wave.png"), dpi=110)


def precursor(directory):
    prof = defaultdict(list)
    jump = defaultdict(list)
    for r in rows(os.path.join(directory, "viscoplastic_precursor.csv")):
        tau, t = float(r["tau"]), float(r["time"])
        if r["kind"] == "profile":
            prof[(tau, t)].append((float(r["x"]), -float(r["sigma_xx"]) * 1e-6))
        else:
            jump[(tau, r["kind"])].append((t * 1e3, -float(r["sigma_xx"]) * 1e-6))
    taus = sorted({tau for tau, _ in prof}, reverse=True)
    fig, axes = plt.subplots(1, len(taus) + 1, figsize=(5 * (len(taus) + 1), 4.5),
                             constrained_layout=True)
    for ax, tau in zip(axes, taus):
        for t in sorted({t for (s, t) in prof if s == tau}):
            points = sorted(prof[(tau, t)])
            ax.plot([p[0] for p in points], [p[1] for p in points], lw=1, label=f"t = {t:.3g} s")
        ax.set_title(f"tau = {tau:.4g} s")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("-sigma_xx (MPa)")
        ax.legend(fontsize=8)
    ax = axes[-1]
    colours = ["tab:blue", "tab:orange"]
    for colour, tau in zip(colours, taus):
        for kind, kw in [("jump", dict(ls="none", marker="o", ms=3)), ("exact_jump", dict(lw=1))]:
            points = sorted(jump[(tau, kind)])
            ax.plot([p[0] for p in points], [p[1] for p in points], color=colour,
                    label=f"tau = {tau:.3g} s, " + ("DGMPM" if kind == "jump" else "exact"), **kw)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("precursor jump (MPa)")
    ax.set_title("the precursor's jump against the exact decay")
    ax.legend(fontsize=8)
    fig.savefig(os.path.join(directory, "viscoplastic_precursor.png"), dpi=110)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    directory = sys.argv[1]
    profiles(directory)
    error_vs_time(directory)
    precursor(directory)


if __name__ == "__main__":
    main()
