#!/usr/bin/env python3
"""Moving particles under the automatic time step: for each scene, the growth-budget criterion
(the default), the strict L2 criterion and fixed Courant numbers against a fine fixed-Courant
reference (C = 0.1): steps, wall seconds (of which choosing steps), the largest excess of the
energy over the initial energy plus the work of the loads, and the relative L2 difference of the
particles' stress and velocity from the reference at the end.
Run from the repo root after a build:
    python3 reports/moving_runs.py [--quick]   -> Markdown table on stdout"""
import copy
import csv
import glob
import json
import math
import os
import subprocess
import sys
import tempfile

BINARY = 'build/bin/dgmpm'
STEEL = {"model": "linear_elastic", "young": 2e11, "poisson": 0.3, "density": 7800}
FREE2 = {"xmin": {"type": "free"}, "xmax": {"type": "free"}, "ymin": {"type": "free"},
         "ymax": {"type": "free"}}


def block(lo, hi, v, ppc=(1, 1)):
    return {"material": "steel", "box": {"min": lo, "max": hi}, "velocity": v,
            "particles_per_cell": list(ppc)}


def plate2d(bodies, end, integrator):
    return {"dimension": 2, "method": "dgmpm",
            "grid": {"origin": [0.0, 0.0], "cell_size": [0.12, 0.12], "cells": [20, 15]},
            "materials": {"steel": STEEL}, "bodies": bodies, "boundaries": FREE2,
            "time": {"end": end, "integrator": integrator}, "particles_move": True}


def cases():
    c = {}
    plate = json.load(open('scenes/plate_impact.json'))
    plate.pop('output')
    plate['particles_move'] = True
    c['2D plate impact (RK2)'] = plate
    c['2D two blocks crossing cells (RK2)'] = plate2d(
        [block([0.24, 0.24], [1.2, 1.56], [150.0, 20.0]),
         block([1.2, 0.36], [2.16, 1.44], [-150.0, 0.0])], 1e-3, 'rk2')
    c['2D two blocks crossing cells (Euler)'] = plate2d(
        [block([0.24, 0.24], [1.2, 1.56], [150.0, 20.0]),
         block([1.2, 0.36], [2.16, 1.44], [-150.0, 0.0])], 1e-3, 'euler')
    c['2D rigid diagonal translation (RK2)'] = plate2d(
        [block([0.24, 0.24], [1.2, 1.2], [300.0, 200.0])], 2.5e-3, 'rk2')
    c['1D rigid bar, 2 per cell (RK2)'] = {
        "dimension": 1, "method": "dgmpm",
        "grid": {"origin": [-0.4], "cell_size": [0.04], "cells": [170]},
        "materials": {"steel": STEEL},
        "bodies": [{"material": "steel", "box": {"min": [0.0], "max": [3.0]}, "velocity": [10.0],
                    "positions_in_cell": [0.25, 0.75]}],
        "boundaries": {"xmin": {"type": "free"}, "xmax": {"type": "free"}},
        "time": {"end": 0.01, "integrator": "rk2"}, "particles_move": True}
    return c


def run(scene, time, work, tag):
    d = copy.deepcopy(scene)
    d['time'] = {'end': scene['time']['end'], 'integrator': scene['time']['integrator'], **time}
    out = os.path.join(work, tag)
    d['output'] = {'directory': out, 'times': [scene['time']['end']], 'formats': ['csv']}
    path = os.path.join(work, tag + '.json')
    with open(path, 'w') as f:
        json.dump(d, f)
    r = subprocess.run([BINARY, 'run', '--json', '--overwrite', path], capture_output=True,
                       text=True)
    if r.returncode != 0:
        return None, r.stderr.strip().splitlines()[-1][:90].replace('|', '/')
    j = json.loads(r.stdout)
    with open(os.path.join(out, 'energy.csv')) as f:
        rows = list(csv.DictReader(f))
    e0 = float(rows[0]['total'])
    scale = max(e0 + max(float(x['boundary_work']) for x in rows), 1e-300)
    j['excess'] = max((float(x['total']) - e0 - float(x['boundary_work'])) / scale for x in rows)
    files = sorted(glob.glob(os.path.join(out, 'particles_*.csv')))
    with open(files[-1]) as f:
        j['particles_state'] = {row['id']: row for row in csv.DictReader(f)}
    return j, ''


def rms_difference(a, b, columns):
    total, count = 0.0, 0
    for pid, row in b.items():
        for c in columns:
            total += (float(a[pid][c]) - float(row[c])) ** 2
            count += 1
    return math.sqrt(total / max(count, 1))


def main():
    quick = '--quick' in sys.argv
    work = tempfile.mkdtemp()
    runs = [('auto, budget (default)', {'courant': 'auto'}),
            ('auto, strict L2', {'courant': 'auto', 'criterion': 'l2'}),
            ('C = 0.5', {'courant': 0.5}), ('C = 0.9', {'courant': 0.9}),
            ('C = 1', {'courant': 1.0})]
    print('| scene | time step | steps | wall s | choosing steps s | max (E - E0 - W) / (E0 + W) '
          '| stress difference / (rho c v) | velocity difference / v |')
    print('|---|---|---|---|---|---|---|---|')
    for name, scene in cases().items():
        if quick and not name.startswith('2D plate'):
            continue
        ref, msg = run(scene, {'courant': 0.1}, work, 'reference')
        if ref is None:
            print(f'| {name} | reference C = 0.1 | failed: {msg} | | | | | |')
            continue
        dim = scene['dimension']
        stress = ['stress'] if dim == 1 else ['sigma_xx', 'sigma_yy', 'sigma_xy']
        velocity = ['velocity'] if dim == 1 else ['velocity_x', 'velocity_y']
        v = max(math.sqrt(sum(float(row[c]) ** 2 for c in velocity))
                for row in ref['particles_state'].values())
        impedance = max(math.sqrt(m['density'] * m['young'] * (1 - m['poisson']) /
                                  ((1 + m['poisson']) * (1 - 2 * m['poisson'])))
                        if dim == 2 else math.sqrt(m['density'] * m['young'])
                        for m in scene['materials'].values())
        print(f"| {name} | reference C = 0.1 | {ref['steps']} | {ref['wall_seconds']:.3g} | | "
              f"{ref['excess']:+.1e} | 0 | 0 |")
        for i, (label, time) in enumerate(runs):
            j, msg = run(scene, time, work, f'run{i}')
            if j is None:
                print(f'| {name} | {label} | failed: {msg} | | | | | |')
                continue
            ds = rms_difference(j['particles_state'], ref['particles_state'], stress) / (
                impedance * v)
            dv = rms_difference(j['particles_state'], ref['particles_state'], velocity) / v
            print(f"| {name} | {label} | {j['steps']} | {j['wall_seconds']:.3g} | "
                  f"{j.get('time_step_seconds', 0):.3g} | {j['excess']:+.1e} | {ds:.3g} | "
                  f"{dv:.3g} |", flush=True)


if __name__ == '__main__':
    main()
