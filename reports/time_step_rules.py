#!/usr/bin/env python3
"""Issue 4 comparison: DGMPM automatic time steps against the MPM rule dt = 0.5 dx/c and 0.9 dx/c on the
founding scenes (steps, relative L2 stress error, energy change). Run from the repo root after a build:
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
cases['two-bar 1ppc moving'] = mov
print('| scene | method | steps | stress L2 error | energy change |')
print('|---|---|---|---|---|')
for name, sc in cases.items():
    runs = [('dgmpm euler auto l2', dict(method='dgmpm', time=dict(courant='auto', criterion='l2'))),
            ('dgmpm euler auto monotone', dict(method='dgmpm', time=dict(courant='auto', criterion='monotone'))),
            ('dgmpm euler C=0.5', dict(method='dgmpm', time=dict(courant=0.5))),
            ('dgmpm euler C=0.9', dict(method='dgmpm', time=dict(courant=0.9))),
            ('mpm-usl flip C=0.5', dict(method='mpm-usl', time=dict(courant=0.5))),
            ('mpm-usl flip C=0.9', dict(method='mpm-usl', time=dict(courant=0.9))),
            ('mpm-musl flip C=0.5', dict(method='mpm-musl', time=dict(courant=0.5))),
            ('mpm-musl flip C=0.9', dict(method='mpm-musl', time=dict(courant=0.9)))]
    for label, mod in runs:
        d = copy.deepcopy(sc); d['method'] = mod['method']
        d['time'] = {'end': sc['time']['end'], 'integrator': 'euler', **mod['time']}
        with open(tmp, 'w') as f:
            json.dump(d, f)
        r = subprocess.run(['build/bin/dgmpm', 'run', '--json', tmp], capture_output=True, text=True)
        if r.returncode != 0:
            print(f'| {name} | {label} | failed: {r.stderr.strip()[:90]} | | |'); continue
        j = json.loads(r.stdout)
        de = (j['energy_final'] - j['energy_initial']) / j['energy_initial']
        print(f"| {name} | {label} | {j['steps']} | {j['errors']['stress']['l2']:.3g} | {de:+.3g} |")
