#!/usr/bin/env python3
"""Scenes that broke the automatic time step (issue: moving particles, part-full cells, particles
near nodes, steel on rubber), run with "courant": "auto" to their end: at every step the energy
must be at most the initial energy plus the work of the loads (1e-9 relative). 1D and 2D, Euler
and RK2, DCU and CTU, fixed and moving particles, free and loaded boundaries.

usage: energy_bound_scenes.py DGMPM_BINARY WORK_DIR
"""
import csv
import json
import os
import subprocess
import sys

STEEL = {"model": "linear_elastic", "young": 2e11, "poisson": 0.3, "density": 7800}
RUBBER = {"model": "linear_elastic", "young": 2e6, "poisson": 0.45, "density": 1000}
ALUMINIUM = {"model": "linear_elastic", "young": 7e10, "poisson": 0.33, "density": 2700}
FREE = {"type": "free"}


def body(material, lo, hi, velocity, layout=None, ppc=None):
    b = {"material": material, "box": {"min": lo, "max": hi}, "velocity": velocity}
    if layout is not None:
        b["positions_in_cell"] = layout
    else:
        b["particles_per_cell"] = ppc if ppc is not None else (1 if len(lo) == 1 else [1, 1])
    return b


def bar(bodies, materials, end, integrator, move, boundaries=None, cells=170, origin=-0.4):
    return {"dimension": 1, "method": "dgmpm",
            "grid": {"origin": [origin], "cell_size": [0.04], "cells": [cells]},
            "materials": materials, "bodies": bodies,
            "boundaries": boundaries or {"xmin": FREE, "xmax": FREE},
            "time": {"end": end, "integrator": integrator, "courant": "auto"},
            "particles_move": move}


def plate(bodies, materials, end, integrator, flux, move, boundaries=None):
    loaded = {"xmin": [{"type": "traction", "value": [-2e8, 0.0], "range": [0.0, 0.6]}],
              "xmax": FREE, "ymin": FREE, "ymax": FREE}
    return {"dimension": 2, "method": "dgmpm", "flux": flux,
            "grid": {"origin": [0.0, 0.0], "cell_size": [0.12, 0.12], "cells": [20, 15]},
            "materials": materials, "bodies": bodies, "boundaries": boundaries or loaded,
            "time": {"end": end, "integrator": integrator, "courant": "auto"},
            "particles_move": move}


def scenes():
    s = {}
    steel = {"steel": STEEL}
    traction = {"xmin": {"type": "traction", "value": -1e8}, "xmax": FREE}
    for t in ("euler", "rk2"):
        # A rigid translation with two particles per cell: they reach the faces together.
        s[f"1d rigid bar, 2 per cell, {t}"] = bar(
            [body("steel", [0.0], [3.0], [10.0], layout=[0.25, 0.75])], steel, 0.01, t, True)
        s[f"1d rigid bar, 1 off-centre, {t}"] = bar(
            [body("steel", [0.0], [3.0], [40.0], layout=[0.1])], steel, 0.004, t, True)
        s[f"1d steel on rubber, {t}"] = bar(
            [body("steel", [0.0], [3.0], [20.0]), body("rubber", [3.0], [6.0], [-20.0])],
            {"steel": STEEL, "rubber": RUBBER}, 0.01, t, True)
        s[f"1d two steel bars, 2 per cell, {t}"] = bar(
            [body("steel", [0.0], [3.0], [50.0], ppc=2), body("steel", [3.0], [6.0], [-50.0], ppc=2)],
            steel, 0.002, t, True)
        # Six per cell: past the position lattice, bounded from the moment lattice.
        s[f"1d two steel bars, 6 per cell, {t}"] = bar(
            [body("steel", [0.0], [3.0], [50.0], ppc=6), body("steel", [3.0], [6.0], [-50.0], ppc=6)],
            steel, 0.002, t, True)
        s[f"1d aluminium on steel, 3 per cell, {t}"] = bar(
            [body("steel", [0.0], [3.0], [30.0], ppc=3), body("alu", [3.0], [6.0], [-30.0], ppc=3)],
            {"steel": STEEL, "alu": ALUMINIUM}, 0.003, t, True)
        # A part-full end cell whose particle sits 0.003 of a cell from a node, loaded.
        s[f"1d part-full end cell near a node, loaded, {t}"] = bar(
            [body("steel", [0.0], [3.01], [0.0], layout=[0.003, 0.503])], steel, 0.002, t, False,
            boundaries=traction, cells=80, origin=0.0)
        s[f"1d lone particles at 0.997, loaded, {t}"] = bar(
            [body("steel", [0.0], [2.995], [0.0], layout=[0.997])], steel, 0.002, t, False,
            boundaries=traction, cells=80, origin=0.0)
    free = {"xmin": FREE, "xmax": FREE, "ymin": FREE, "ymax": FREE}
    near_nodes = [[0.003, 0.003], [0.503, 0.003], [0.003, 0.503], [0.503, 0.503]]
    for t, f in (("euler", "dcu"), ("euler", "ctu"), ("rk2", "dcu")):
        k = f"{t} {f}"
        # The first column of cells half full, particles 0.003 of a cell from the nodes.
        s[f"2d part-full column near nodes, {k}"] = plate(
            [body("steel", [0.06, 0.0], [2.4, 1.8], [0.0, 0.0], layout=near_nodes)], steel, 3e-3,
            t, f, False)
        s[f"2d loaded plate, moving, {k}"] = plate(
            [body("steel", [0.0, 0.0], [2.4, 1.8], [0.0, 0.0])], steel, 3e-3, t, f, True)
        s[f"2d two blocks crossing cells, {k}"] = plate(
            [body("steel", [0.24, 0.24], [1.2, 1.56], [150.0, 20.0]),
             body("steel", [1.2, 0.36], [2.16, 1.44], [-150.0, 0.0])], steel,
            1e-3 if t == "euler" else 3e-4, t, f, True, boundaries=free)
        # 2 x 2 moving particles per cell: steps bounded from the moment lattice.
        s[f"2d loaded plate, 2 x 2 moving, {k}"] = plate(
            [body("steel", [0.0, 0.0], [2.4, 1.8], [0.0, 0.0], ppc=[2, 2])], steel, 3e-3, t, f,
            True)
        if f == "dcu":  # crossing 2.5 cells along x
            s[f"2d rigid diagonal translation, 2 x 2, {k}"] = plate(
                [body("steel", [0.24, 0.24], [1.2, 1.2], [300.0, 200.0], ppc=[2, 2])], steel,
                1e-3, t, f, True, boundaries=free)
        s[f"2d rigid diagonal translation, {k}"] = plate(
            [body("steel", [0.24, 0.24], [1.2, 1.2], [300.0, 200.0])], steel, 2.5e-3, t, f, True,
            boundaries=free)
        s[f"2d steel beside rubber, loaded, {k}"] = plate(
            [body("steel", [0.0, 0.0], [1.2, 1.8], [0.0, 0.0]),
             body("rubber", [1.2, 0.0], [2.4, 1.8], [0.0, 0.0])],
            {"steel": STEEL, "rubber": RUBBER}, 3e-3, t, f, False)
    return s


def main():
    binary, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    for i, (name, scene) in enumerate(scenes().items()):
        out = os.path.join(work, f"scene_{i:02d}")
        scene["output"] = {"directory": out, "times": []}
        path = os.path.join(work, f"scene_{i:02d}.json")
        with open(path, "w") as f:
            json.dump(scene, f)
        r = subprocess.run([binary, "run", path, "--json", "--overwrite"], capture_output=True,
                           text=True)
        if r.returncode != 0:
            failures.append(f"{name}: exit {r.returncode}: {r.stderr.strip()[-300:]}")
            continue
        summary = json.loads(r.stdout)
        with open(os.path.join(out, "energy.csv")) as f:
            rows = list(csv.DictReader(f))
        e0 = float(rows[0]["total"])
        # Relative to the largest E0 + W of the run (a loaded body at rest starts from 0).
        scale = max(e0 + max(float(row["boundary_work"]) for row in rows), 1e-300)
        worst, at = -float("inf"), 0
        for row in rows:
            excess = (float(row["total"]) - e0 - float(row["boundary_work"])) / scale
            if excess > worst:
                worst, at = excess, int(row["step"])
        print(f"{name:48s} {summary['steps']:5d} steps, C in [{summary['courant_min']:.3f}, "
              f"{summary['courant_max']:.3f}], worst (E - E0 - W) / max(E0 + W) {worst:+.1e} "
              f"at step {at}", flush=True)
        if len(rows) != summary["steps"] + 1:
            failures.append(f"{name}: energy.csv has {len(rows)} rows for {summary['steps']} steps")
        if worst > 1e-9:
            failures.append(f"{name}: the energy exceeds E0 + W by {worst:.2e} at step {at}")
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
