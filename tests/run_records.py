"""`dgmpm run` leaves a record whatever its end: a run stopped by its blow-up check and a run
stopped by SIGTERM both leave summary.json with their status and reason, the energy history up
to where they stopped, and the outputs' index and ParaView series matching the particle files
written. Exit codes: 1 for the failure (with --json, the summary still on stdout), 128 + 15 for
SIGTERM. A run killed by SIGKILL leaves its energy history to its last commit; batch progress
lines give dt, the energy balance and an estimate of the time left that a moving run bears out."""
import csv
import json
import os
import pathlib
import re
import select
import shutil
import signal
import subprocess
import sys
import time

binary, source, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)  # the wait below looks for a new file
work.mkdir(parents=True)
base = json.loads((source / "scenes" / "two_bar_impact.json").read_text())


def check_record(out, status):
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == status, summary
    with open(out / "energy.csv") as f:
        rows = list(csv.DictReader(f))
    # One row per step from the initial one, up to the step the run stopped at (interrupted) or
    # the last one before the step that failed (its energy is the summary's energy_final).
    last = summary["steps"] - (1 if status == "failed" else 0)
    assert [int(r["step"]) for r in rows] == list(range(last + 1)), (len(rows), summary["steps"])
    with open(out / "outputs.csv") as f:
        index = list(csv.DictReader(f))
    assert index, "no output written before the stop"
    for row in index:
        for kind in ("csv", "vtu"):
            if row[kind]:
                assert (out / row[kind]).is_file(), row[kind]
    series = (out / "particles.pvd").read_text()
    assert series.count("<DataSet") == len(index), series
    for name in summary["files"]:
        assert pathlib.Path(name).is_file(), name
    return summary


# A blow-up: Courant 1.5 with one particle per cell, outputs early enough to be written first.
scene = dict(base)
scene["time"] = dict(base["time"], courant=1.5, end=2e-3)
scene["output"] = {"directory": str(work / "blow_up"), "times": [2e-5, 4e-5, 1.9e-3],
                   "formats": ["csv", "vtu"]}
path = work / "blow_up.json"
path.write_text(json.dumps(scene))
run = subprocess.run([binary, "run", str(path), "--json", "--overwrite"], capture_output=True,
                     text=True)
assert run.returncode == 1, (run.returncode, run.stderr)
assert "the run is unstable" in run.stderr, run.stderr
printed = json.loads(run.stdout)
assert printed["status"] == "failed" and "the run is unstable" in printed["reason"], printed
summary = check_record(work / "blow_up", "failed")
assert summary["reason"] == printed["reason"], summary
assert summary["steps"] >= 16, summary

# SIGTERM: a long run stopped once it has said where it is (its stderr is not a terminal: a new
# progress line every 10 s, as a batch job's log gets); the record shows where it stopped.
scene = dict(base)
scene["grid"] = dict(base["grid"], cell_size=[0.0004], cells=[15000])
scene["time"] = dict(base["time"], end=1.0, max_steps=100000000)
scene["output"] = {"directory": str(work / "interrupted"), "times": [1e-6, 2e-6, 0.5],
                   "formats": ["csv", "vtu"]}
scene.pop("exact")
path = work / "interrupted.json"
path.write_text(json.dumps(scene))
PROGRESS = re.compile(r"step \d+  t = \S+ / \S+  \((\d+\.\d)%\)  dt \S+  \(E - E0 - W\) / \(E0 \+ W\) "
                      r"\S+  about (\d+) s left\n")


def progress_lines(process, count, timeout=60):
    """The first `count` progress lines of a running process's stderr."""
    lines, deadline = [], time.time() + timeout
    while len(lines) < count and time.time() < deadline:
        ready, _, _ = select.select([process.stderr], [], [], 1.0)
        if ready:
            line = process.stderr.readline()
            if "s left" in line:
                lines.append(line)
    return lines


process = subprocess.Popen([binary, "run", str(path), "--overwrite", "--threads", "1",
                            "--progress-every", "1"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
progress = progress_lines(process, 3)
assert len(progress) == 3 and all(PROGRESS.fullmatch(p) for p in progress), progress
assert (work / "interrupted" / "particles_001.csv").exists()
# The energy history is on disk under its own name while the run goes (every 2 s at most).
with open(work / "interrupted" / "energy.csv") as f:
    assert len(f.readlines()) > 2
process.send_signal(signal.SIGTERM)
stdout, stderr = process.communicate(timeout=60)
assert process.returncode == 128 + signal.SIGTERM, (process.returncode, stderr)
assert "interrupted:" in stderr and "SIGTERM" in stderr, stderr
summary = check_record(work / "interrupted", "interrupted")
assert "SIGTERM" in summary["reason"] and 0 < summary["final_time"] < 1.0, summary
# SIGKILL leaves no chance to write anything: energy.csv holds the whole rows of its last commit
# (every 2 s), from step 0 on, and no summary claims the run ended.
path = work / "killed.json"
scene["output"] = {"directory": str(work / "killed"), "times": [0.5]}
path.write_text(json.dumps(scene))
process = subprocess.Popen([binary, "run", str(path), "--overwrite", "--threads", "1",
                            "--progress-every", "1"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
assert len(progress_lines(process, 4)) == 4
process.kill()
process.communicate(timeout=60)
with open(work / "killed" / "energy.csv") as f:
    text = f.read()
assert text.endswith("\n"), text[-200:]
rows = list(csv.DictReader(text.splitlines()))
assert len(rows) > 1 and [int(r["step"]) for r in rows] == list(range(len(rows))), len(rows)
assert all(len(r) == len(rows[0]) and None not in r.values() for r in rows)
assert not (work / "killed" / "summary.json").exists()
killed_rows = len(rows)

# The batch progress estimate follows the pace of a moving run whose step changes: once a tenth
# of the run is done, within a factor 2 of the time actually left (where that is 2 s or more).
scene = dict(base)
scene["grid"] = dict(base["grid"], origin=[-0.2], cell_size=[0.0008], cells=[8000])
scene["bodies"] = [dict(b, particles_per_cell=2) for b in base["bodies"]]
scene["particles_move"] = True
scene["time"] = dict(base["time"], end=4e-4, courant="auto", integrator="rk2")
scene["output"] = {"directory": str(work / "estimate"), "times": []}
scene.pop("exact")
path = work / "estimate.json"
path.write_text(json.dumps(scene))
start = time.time()
process = subprocess.Popen([binary, "run", str(path), "--overwrite", "--threads", "1",
                            "--progress-every", "0.5"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
said = [(time.time() - start, line) for line in process.stderr]
process.wait()
assert process.returncode == 0
end = time.time() - start
estimates = []
for at, line in said:
    m = PROGRESS.fullmatch(line)
    if m and float(m.group(1)) >= 10 and end - at >= 2:
        estimates.append((int(m.group(2)), end - at))
assert estimates, said
for estimate, actual in estimates:
    assert 0.5 * actual <= estimate <= 2 * actual, (estimate, actual, said)

# Checkpoint settings that would do nothing are not silent: a number to keep without checkpoints
# is refused (exit 2), a checkpoint interval past the end time is warned about.
scene = dict(base)
scene["output"] = {"directory": str(work / "checkpoints"), "times": []}
path = work / "checkpoints.json"
path.write_text(json.dumps(scene))
keep = subprocess.run([binary, "run", str(path), "--checkpoint-keep", "2"], capture_output=True,
                      text=True)
assert keep.returncode == 2 and "--checkpoint-keep: value 2" in keep.stderr, keep
late = subprocess.run([binary, "run", str(path), "--checkpoint-every", "1e-3s"],
                      capture_output=True, text=True)
assert late.returncode == 0 and "none is written" in late.stderr, late
assert not list((work / "checkpoints").glob("*.ckpt")), list((work / "checkpoints").iterdir())

# A load on a side no body reaches is said, not silent: the bar starts half a metre in.
scene = dict(base)
scene["bodies"] = [dict(base["bodies"][0], box={"min": [0.5], "max": [3.0]}), base["bodies"][1]]
scene["boundaries"] = {"xmin": {"type": "traction", "value": [[0.0, -1e8], [1.0, -1e8]]},
                      "xmax": {"type": "free"}}
scene["output"] = {"directory": str(work / "untouched"), "times": []}
scene.pop("exact")
path = work / "untouched.json"
path.write_text(json.dumps(scene))
loose = subprocess.run([binary, "run", str(path)], capture_output=True, text=True)
assert loose.returncode == 0, loose
assert "warning: boundaries.xmin: the traction there does nothing" in loose.stderr, loose.stderr
scene["bodies"] = base["bodies"]
path.write_text(json.dumps(scene))
touching = subprocess.run([binary, "run", str(path)], capture_output=True, text=True)
assert touching.returncode == 0 and "does nothing" not in touching.stderr, touching.stderr

print("run records: blow-up at step %d, SIGTERM at step %d, SIGKILL after %d history rows, "
      "%d progress estimates within a factor 2 of the time left" %
      (printed["steps"], summary["steps"], killed_rows, len(estimates)))
