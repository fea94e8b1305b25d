#!/usr/bin/env python3
"""C* of 1, 2, 4 and 9 regular particles per cell in 2D (DCU/CTU x Euler/RK2): scalar
advection a = b (L2 and monotone) and plane strain nu = 0.3 (L2), from `dgmpm courant --dim 2`,
as a Markdown table.

    python3 reports/stability_table_2d.py build/bin/dgmpm
"""
import json
import subprocess
import sys
import time


def layout(n_axis):
    pts = [((i + 0.5) / n_axis, (j + 0.5) / n_axis) for j in range(n_axis) for i in range(n_axis)]
    return ",".join(f"{x!r}:{y!r}" for x, y in pts)


LAYOUTS = {1: layout(1), 2: "0.25:0.5,0.75:0.5", 4: layout(2), 9: layout(3)}


def courant(binary, *args):
    out = subprocess.run([binary, "courant", "--dim", "2", "--json", *args], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["courant"]


def main():
    binary = sys.argv[1]
    print("| particles | flux | time | advection L2 | advection monotone | elastic L2 (nu 0.3) "
          "| elastic query |")
    print("|---|---|---|---|---|---|---|")
    for n, positions in LAYOUTS.items():
        for flux in ("dcu", "ctu"):
            for scheme in ("euler", "rk2"):
                base = ["--positions", positions, "--flux", flux, "--time", scheme]
                adv = courant(binary, *base, "--model", "advection")
                mono = courant(binary, *base, "--model", "advection", "--criterion", "monotone")
                start = time.time()
                el = courant(binary, *base, "--model", "elastic", "--poisson", "0.3")
                print(f"| {n} | {flux} | {scheme} | {adv:.4f} | {mono:.4f} | {el:.4f} | "
                      f"{time.time() - start:.1f} s |", flush=True)


if __name__ == "__main__":
    main()
