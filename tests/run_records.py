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
assert summary["units"]["energy"] == "J/m^2" and summary["units"]["stress"] == "Pa", summary
assert summary["steps"] >= 16, summary

# Finite strain compressed past Saint Venant-Kirchhoff's hyperbolic range (a bar at F = 0.7
# pushed at 400 m/s): exit 1 naming the step, particle and F, with the record of a failed run.
scene = json.loads((source / "scenes" / "svk_shock_2gpa.json").read_text())
scene["bodies"][0]["deformation_gradient"] = [0.7]
scene["boundaries"]["xmin"] = {"type": "velocity", "value": 400.0}
scene["output"] = {"directory": str(work / "hyperbolic"), "times": [1e-7, 1e-3],
                   "formats": ["csv", "vtu"]}
scene["time"]["end"] = 1e-3
path = work / "hyperbolic.json"
path.write_text(json.dumps(scene))
run = subprocess.run([binary, "run", str(path), "--json"], capture_output=True, text=True)
assert run.returncode == 1, (run.returncode, run.stderr)
hyperbolic = json.loads(run.stdout)
reason = hyperbolic["reason"]
assert hyperbolic["status"] == "failed", hyperbolic
assert re.match(r"step \d+, t = \S+: particle 0 has left its material's hyperbolic range",
                reason), reason
f_stop = float(re.search(r"F = (\S+),", reason).group(1))
assert 0.5 < f_stop < 3 ** -0.5, reason
hyperbolic_record = check_record(work / "hyperbolic", "failed")
assert hyperbolic_record["reason"] == reason, hyperbolic_record
with open(work / "hyperbolic" / "energy.csv") as history:
    assert next(csv.reader(history))[-1] == "max_wave_speed"

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
                            "--progress-every", "1", "--checkpoint-every", "100000000"],
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
# With checkpoints on, one where it stopped (none came due before), on the manifest.
final = "checkpoint_%09d.ckpt" % summary["steps"]
assert (work / "interrupted" / final).is_file(), sorted(os.listdir(work / "interrupted"))
assert final in (work / "interrupted" / "manifest.json").read_text()
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
# 8e-4, not less: the first second's steps run at half the later pace (the automatic step meets
# the moving layouts for the first time), and a run of 4e-4 was a tenth done within it.
scene["time"] = dict(base["time"], end=8e-4, courant="auto", integrator="rk2")
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
# Each within a factor 2; on a shared machine a neighbour's load changes the pace after an
# estimate, so one line in five may miss (by at most a factor 4).
within = [0.5 * actual <= estimate <= 2 * actual for estimate, actual in estimates]
assert sum(within) >= 0.8 * len(within), (estimates, said)
assert all(0.25 * actual <= estimate <= 4 * actual for estimate, actual in estimates), estimates

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

# Restarts land anywhere and extend (the plate, fixed Courant 1, so the step does not depend on
# the end time): from a checkpoint without --out (its own directory), into another directory
# (the earlier outputs copied there: the index and the .pvd name files that exist), and with a
# later time.end and output times that keep those before the checkpoint. Each ends with every
# particle file byte for byte the uninterrupted run's.
plate = json.loads((source / "scenes" / "plate_impact.json").read_text())


def plate_run(name, end, times, *extra, scene_name=None):
    doc = dict(plate, time=dict(plate["time"], end=end))
    doc["output"] = {"directory": str(work / name), "times": times}
    path = work / ((scene_name or name) + ".json")
    path.write_text(json.dumps(doc))
    r = subprocess.run([binary, "run", str(path), "--overwrite", "--json", *extra],
                       capture_output=True, text=True)
    assert r.returncode == 0, (name, r.stderr)
    return json.loads(r.stdout)


def same_particle_files(a, b):
    files = sorted(f.name for f in (work / a).glob("particles_*"))
    assert files and files == sorted(f.name for f in (work / b).glob("particles_*")), (a, b)
    for f in files:
        assert (work / a / f).read_bytes() == (work / b / f).read_bytes(), (a, b, f)
    pvd = (work / b / "particles.pvd").read_text()
    for name in re.findall(r'file="([^"]+)"', pvd):
        assert (work / b / name).is_file(), (b, name)
    return len(files)


times = [2e-4, 4e-4, 8e-4, 1e-3]
plate_run("plate_full", 1e-3, times)
plate_run("plate_ckpt", 1e-3, times, "--checkpoint-every", "25")
restart = str(work / "plate_ckpt" / "checkpoint_000000025.ckpt")
r = subprocess.run([binary, "run", "--restart", restart, "--json"], capture_output=True, text=True)
assert r.returncode == 0 and json.loads(r.stdout)["final_time"] == 1e-3, r.stderr
same_particle_files("plate_full", "plate_ckpt")
r = subprocess.run([binary, "run", "--restart", restart, "--out", str(work / "plate_moved"),
                    "--json"], capture_output=True, text=True)
assert r.returncode == 0, r.stderr
moved = json.loads(r.stdout)
assert any("copied from" in w for w in moved["warnings"]), moved["warnings"]
assert all(pathlib.Path(f).is_file() for f in moved["files"]), moved["files"]
same_particle_files("plate_full", "plate_moved")
with open(work / "plate_moved" / "energy.csv") as f:
    assert [int(row["step"]) for row in csv.DictReader(f)] == list(range(moved["steps"] + 1))
# Extended: the first run ends at 6e-4 with outputs at 2e-4 and 4e-4 (checkpoint at step 25,
# about 5e-4), the restart goes on to 1e-3 with the later outputs.
plate_run("plate_short", 6e-4, times[:2], "--checkpoint-every", "25", scene_name="plate_ext")
ext = dict(plate, time=dict(plate["time"], end=1e-3))
ext["output"] = {"directory": str(work / "plate_short"), "times": times}
(work / "plate_ext.json").write_text(json.dumps(ext))
r = subprocess.run([binary, "run", str(work / "plate_ext.json"), "--restart",
                    str(work / "plate_short" / "checkpoint_000000025.ckpt"), "--json"],
                   capture_output=True, text=True)
assert r.returncode == 0 and json.loads(r.stdout)["final_time"] == 1e-3, r.stderr
extended = same_particle_files("plate_full", "plate_short")
# An end time before the checkpoint, or changed output times before it, are refused.
ext["time"]["end"] = 3e-4
ext["output"]["times"] = [2e-4]
(work / "plate_ext.json").write_text(json.dumps(ext))
r = subprocess.run([binary, "run", str(work / "plate_ext.json"), "--restart",
                    str(work / "plate_short" / "checkpoint_000000025.ckpt")],
                   capture_output=True, text=True)
assert r.returncode == 2 and "time.end: value 0.0003 is not after the checkpoint's time" \
    in r.stderr, r.stderr
ext["time"]["end"] = 1e-3
ext["output"]["times"] = [3e-4, 8e-4]
(work / "plate_ext.json").write_text(json.dumps(ext))
r = subprocess.run([binary, "run", str(work / "plate_ext.json"), "--restart",
                    str(work / "plate_short" / "checkpoint_000000025.ckpt")],
                   capture_output=True, text=True)
assert r.returncode == 2 and "differs at /output/times" in r.stderr, r.stderr

print("run records: blow-up at step %d, finite strain past its range at step %d, SIGTERM at "
      "step %d, SIGKILL after %d history rows, %d progress estimates within a factor 2 of the "
      "time left; restarts in place, elsewhere and extended: %d particle files identical" %
      (printed["steps"], hyperbolic["steps"], summary["steps"], killed_rows, len(estimates),
       extended))
