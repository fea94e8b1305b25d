#!/usr/bin/env python3
"""Errors of DGMPM (DCU/CTU x Euler/RK2, 1 and 4 particles per cell) and MPM (USL/USF/MUSL,
FLIP) on the shipped 2D plane-wave scenes, one period at Courant 0.5, as a Markdown table.

    python3 reports/plane_waves_2d.py build/bin/dgmpm [--cells 32]
"""
import argparse
import json
import os
import subprocess
import tempfile

SCENES = ["plane_wave_p_x", "plane_wave_s_x", "plane_wave_p_30deg", "plane_wave_s_30deg"]
METHODS = [("dgmpm", "dcu", "euler", 1), ("dgmpm", "dcu", "rk2", 1), ("dgmpm", "ctu", "euler", 1),
           ("dgmpm", "ctu", "rk2", 1), ("dgmpm", "dcu", "euler", 2), ("dgmpm", "dcu", "rk2", 2),
           ("dgmpm", "ctu", "euler", 2), ("mpm-usl", None, None, 1), ("mpm-usf", None, None, 1),
           ("mpm-musl", None, None, 1)]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("binary")
    p.add_argument("--cells", type=int, default=32, help="cells per metre")
    a = p.parse_args()
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")
    work = tempfile.mkdtemp(prefix="dgmpm_pw_")
    print("| method | ppc | " + " | ".join(SCENES) + " |")
    print("|---|---|" + "---|" * len(SCENES))
    for method, flux, integrator, ppc_axis in METHODS:
        row = []
        for name in SCENES:
            with open(os.path.join(root, name + ".json")) as f:
                d = json.load(f)
            ly = d["grid"]["cells"][1] * d["grid"]["cell_size"][1]
            ny = round(a.cells * ly)
            d["grid"]["cells"] = [a.cells, ny]
            d["grid"]["cell_size"] = [1.0 / a.cells, ly / ny]
            d["bodies"][0]["particles_per_cell"] = [ppc_axis, ppc_axis]
            d["method"] = method
            d.pop("output", None)
            if method == "dgmpm":
                d["flux"], d["time"]["integrator"] = flux, integrator
            else:
                d.pop("flux", None)
                d["time"].pop("integrator", None)
            path = os.path.join(work, "scene.json")
            with open(path, "w") as f:
                json.dump(d, f)
            out = subprocess.run([a.binary, "run", path, "--json"], capture_output=True, text=True)
            if out.returncode != 0:
                row.append("failed")
                continue
            j = json.loads(out.stdout)
            row.append(f"{j['errors']['stress']['l2']:.3g} ({j['wall_seconds']:.2f} s)")
        label = method if method != "dgmpm" else f"dgmpm {flux} {integrator}"
        print(f"| {label} | {ppc_axis * ppc_axis} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
