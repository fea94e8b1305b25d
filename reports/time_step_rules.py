#!/usr/bin/env python3
"""Comparison of DGMPM automatic time steps with the MPM rules dt = 0.5 dx/c and 0.9 dx/c on
the founding scenes (steps, relative L2 and max stress error at the end, energy change, wall time).
Run from the repo root after a build:
    python3 reports/time_step_rules.py   -> Markdown table on stdout"""
import copy
import json
import os
import subprocess
import tempfile

tmp = os.path.join(tempfile.mkdtemp(), 'scene.json')
base = json.load(open('scenes/two_bar_impact.json')); base.pop('output')
mov = json.load(open('scenes/two_bar_impact_moving.json')); mov.pop('output')
cases = {}
cases['two-bar 1ppc'] = base
b2 = copy.deepcopy(base)
for b in b2['bodies']: b['particles_per_cell'] = 2
cases['two-bar 2ppc'] = b2
# Bars ending mid-cell: half-full end cells (the small-cell rule), 8 particles per cell.
b8 = copy.deepcopy(base)
dx = b8['grid']['cell_size'][0]
b8['grid']['origin'] = [b8['grid']['origin'][0] - 0.5 * dx]
b8['grid']['cells'] = [b8['grid']['cells'][0] + 1]
for b in b8['bodies']: b['particles_per_cell'] = 8
cases['two-bar 8ppc, ends mid-cell'] = b8
cases['two-bar 1ppc moving'] = mov

runs = [('dgmpm euler auto l2', 'dgmpm', 'euler', dict(courant='auto', criterion='l2')),
        ('dgmpm euler auto monotone', 'dgmpm', 'euler', dict(courant='auto', criterion='monotone')),
        ('dgmpm rk2 auto l2', 'dgmpm', 'rk2', dict(courant='auto', criterion='l2')),
        ('dgmpm euler auto monotone, paper pseudo-stiffness', 'dgmpm', 'euler',
         dict(courant='auto', criterion='monotone'), True),
        ('dgmpm rk2 auto l2, paper pseudo-stiffness', 'dgmpm', 'rk2',
         dict(courant='auto', criterion='l2'), True),
        ('dgmpm euler C=0.5', 'dgmpm', 'euler', dict(courant=0.5)),
        ('dgmpm euler C=0.9', 'dgmpm', 'euler', dict(courant=0.9)),
        ('dgmpm rk2 C=0.5', 'dgmpm', 'rk2', dict(courant=0.5)),
        ('dgmpm rk2 C=0.9', 'dgmpm', 'rk2', dict(courant=0.9)),
        ('mpm-usl flip C=0.5', 'mpm-usl', 'euler', dict(courant=0.5)),
        ('mpm-usl flip C=0.9', 'mpm-usl', 'euler', dict(courant=0.9)),
        ('mpm-usf flip C=0.9', 'mpm-usf', 'euler', dict(courant=0.9)),
        ('mpm-musl flip C=0.5', 'mpm-musl', 'euler', dict(courant=0.5)),
        ('mpm-musl flip C=0.9', 'mpm-musl', 'euler', dict(courant=0.9))]

print('| scene | method | steps | stress L2 error | stress max error | energy change | wall s |')
print('|---|---|---|---|---|---|---|')
for name, sc in cases.items():
    for label, method, integrator, time, *paper in runs:
        d = copy.deepcopy(sc); d['method'] = method
        if paper: d['formulation'] = 'paper'
        d['time'] = {'end': sc['time']['end'], 'integrator': integrator, **time}
        with open(tmp, 'w') as f:
            json.dump(d, f)
        r = subprocess.run(['build/bin/dgmpm', 'run', '--json', tmp], capture_output=True, text=True)
        if r.returncode != 0:
            msg = r.stderr.strip().replace('|', '/')[:80]
            print(f'| {name} | {label} | failed: {msg} | | | | |'); continue
        j = json.loads(r.stdout)
        de = (j['energy_final'] - j['energy_initial']) / j['energy_initial']
        e = j['errors']['stress']
        print(f"| {name} | {label} | {j['steps']} | {e['l2']:.3g} | {e['max']:.3g} | {de:+.3g} "
              f"| {j['wall_seconds']:.3g} |")
