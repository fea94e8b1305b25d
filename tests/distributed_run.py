#!/usr/bin/env python3
"""`mpirun -np N dgmpm run SCENE` against the serial `dgmpm run SCENE`: the particle CSV files are
the same bytes; the summary holds the same particles, cells, steps, times and errors, the energy
to round-off (a sum over ranks), and the load balance (particles per rank, imbalance); the VTK
output (one .pvtu per output time, one piece per rank) read back with Debian's VTK
(vtkXMLPUnstructuredGridReader through vtkXMLPUnstructuredGridReader's parallel twin) holds the
serial .vtu's particles and fields.

    python3 tests/distributed_run.py MPIEXEC NP build/bin/dgmpm scenes/plate_impact.json ...
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy

failures = []
# Every run's folder is made in this one, removed at the end if every check passed (kept, and
# named, otherwise).
WORK = tempfile.mkdtemp(prefix="dgmpm_mpi_")


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(command, out):
    result = subprocess.run(command + ["--out", out, "--json"], check=True, capture_output=True,
                            text=True)
    return json.loads(result.stdout)


def arrays_by_id(data):
    """Point arrays and coordinates of a data set, rows ordered by particle id."""
    points = data.GetPointData()
    ids = vtk_to_numpy(points.GetArray("id"))
    order = ids.argsort()
    out = {"points": vtk_to_numpy(data.GetPoints().GetData())[order]}
    for k in range(points.GetNumberOfArrays()):
        out[points.GetArrayName(k)] = vtk_to_numpy(points.GetArray(k))[order]
    return out


def read(path, parallel):
    reader = vtk.vtkXMLPUnstructuredGridReader() if parallel else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def compare(mpiexec, np, binary, scene):
    name = os.path.basename(scene)
    top = tempfile.mkdtemp(prefix="compare_", dir=WORK)
    serial_dir, split_dir = os.path.join(top, "serial"), os.path.join(top, "split")
    serial = run([binary, "run", scene], serial_dir)
    split = run([mpiexec, "-np", str(np), "--oversubscribe", binary, "run", scene], split_dir)

    for key in ["particles", "cells", "steps", "final_time", "dt_min", "dt_max", "errors"]:
        check(serial.get(key) == split.get(key),
              f"{name}: summary {key}: {serial.get(key)} vs {split.get(key)}")
    e0, e1 = serial["energy_final"], split["energy_final"]
    check(abs(e0 - e1) <= 1e-12 * abs(e0), f"{name}: energy_final {e0} vs {e1}")
    counts = split.get("particles_per_rank", [])
    check(split.get("ranks") == np and len(counts) == np, f"{name}: ranks {split.get('ranks')}")
    check(sum(counts) == serial["particles"], f"{name}: particles per rank {counts}")
    if counts:
        expected = max(counts) * np / serial["particles"]
        check(abs(split["imbalance"] - expected) < 1e-12, f"{name}: imbalance {split['imbalance']}")

    csvs = sorted(f for f in os.listdir(serial_dir) if f.startswith("particles_") and
                  f.endswith(".csv"))
    check(len(csvs) > 0, f"{name}: serial CSV files")
    for f in csvs:
        with open(os.path.join(serial_dir, f), "rb") as a, open(os.path.join(split_dir, f), "rb") as b:
            check(a.read() == b.read(), f"{name}: {f} differs")

    pvd = os.path.join(split_dir, "particles.pvd")
    if not os.path.exists(os.path.join(serial_dir, "particles.pvd")):
        return
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    serial_sets = ET.parse(os.path.join(serial_dir, "particles.pvd")).getroot().find(
        "Collection").findall("DataSet")
    check(len(sets) == len(serial_sets), f"{name}: {len(sets)} data sets in particles.pvd")
    for s, t in zip(serial_sets, sets):
        check(s.get("timestep") == t.get("timestep"), f"{name}: times {s.get('timestep')}")
        check(t.get("file").endswith(".pvtu"), f"{name}: {t.get('file')} is not a .pvtu")
        pieces = [p.get("Source") for p in ET.parse(os.path.join(split_dir, t.get("file")))
                  .getroot().iter("Piece")]
        check(len(pieces) == np, f"{name}: {len(pieces)} pieces in {t.get('file')}")
        a = arrays_by_id(read(os.path.join(serial_dir, s.get("file")), False))
        b = arrays_by_id(read(os.path.join(split_dir, t.get("file")), True))
        check(sorted(a) == sorted(b), f"{name}: arrays {sorted(a)} vs {sorted(b)}")
        for key in a:
            if key in b:
                check(a[key].shape == b[key].shape and (a[key] == b[key]).all(),
                      f"{name}: {t.get('file')} array {key} differs from the serial .vtu")


def restart(mpiexec, np, binary, scene, every):
    """An uninterrupted distributed run with checkpoints, then a restart from its middle one."""
    name = os.path.basename(scene)
    top = tempfile.mkdtemp(prefix="restart_", dir=WORK)
    serial_dir, whole, resumed = (os.path.join(top, d) for d in ("serial", "whole", "resumed"))
    run([binary, "run", scene], serial_dir)
    mpi = [mpiexec, "-np", str(np), "--oversubscribe", binary, "run", scene]
    first = run(mpi + ["--checkpoint-every", str(every)], whole)
    shutil.copytree(whole, resumed)
    main_files = sorted(f for f in os.listdir(whole) if f.endswith(".ckpt") and "_r" not in f)
    pieces = [f for f in os.listdir(whole) if f.endswith(".ckpt") and "_r" in f]
    check(len(main_files) >= 2 and len(pieces) == (np - 1) * len(main_files),
          f"{name}: {len(main_files)} checkpoints, {len(pieces)} pieces on {np} ranks")
    middle = os.path.join(resumed, main_files[len(main_files) // 2])
    again = run(mpi + ["--restart", middle], resumed)
    check(again["steps"] == first["steps"] and again["final_time"] == first["final_time"],
          f"{name}: restart steps {again['steps']} vs {first['steps']}")
    for f in sorted(os.listdir(serial_dir)):
        if f.startswith("particles_") and f.endswith(".csv"):
            with open(os.path.join(serial_dir, f), "rb") as a, \
                    open(os.path.join(resumed, f), "rb") as b:
                check(a.read() == b.read(), f"{name}: {f} after the restart differs from serial")
    with open(os.path.join(whole, "energy.csv"), "rb") as a, \
            open(os.path.join(resumed, "energy.csv"), "rb") as b:
        check(a.read() == b.read(), f"{name}: energy.csv after the restart differs")
    other = subprocess.run([binary, "run", scene, "--out", resumed, "--restart", middle],
                           capture_output=True, text=True)
    check(other.returncode == 2 and f"mpirun -np {np}" in other.stderr,
          f"{name}: a serial restart from {np} ranks' checkpoint: exit {other.returncode}, "
          f"{other.stderr.strip()}")


def blow_up(mpiexec, np, binary, scene):
    """A run that blows up stops every rank with the serial run's message (step, time, particle,
    cell), said once, and exit code 1."""
    top = tempfile.mkdtemp(prefix="blow_up_", dir=WORK)
    with open(scene) as f:
        doc = json.load(f)
    doc["time"]["courant"] = 3.0
    doc.pop("output", None)
    path = os.path.join(top, "blow.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    serial = subprocess.run([binary, "run", path], capture_output=True, text=True)
    split = subprocess.run([mpiexec, "-np", str(np), "--oversubscribe", binary, "run", path],
                           capture_output=True, text=True)
    said = [l.split("): ", 1)[1] for l in split.stderr.splitlines() if l.startswith("error (rank")]
    expected = [l[len("error: "):] for l in serial.stderr.splitlines() if l.startswith("error: ")]
    check(serial.returncode == 1 and "unstable" in serial.stderr, f"serial blow-up: {serial.stderr}")
    check(split.returncode != 0 and said == expected,
          f"blow-up on {np} ranks: exit {split.returncode}, said {said}, serial {expected}")


def interrupted(mpiexec, np, binary, scene):
    """SIGTERM to mpirun: every rank stops at the same step and the run leaves its record
    (summary with status interrupted, energy history to that step, the outputs' index) and, with
    checkpoints on, a checkpoint (every rank's piece) where it stopped."""
    import signal
    import time
    top = tempfile.mkdtemp(prefix="interrupted_", dir=WORK)
    with open(scene) as f:
        doc = json.load(f)
    doc["time"]["end"] = 10.0
    doc["time"]["max_steps"] = 100000000
    doc["output"] = {"times": [1e-4, 5.0], "formats": ["csv"]}
    path, out = os.path.join(top, "long.json"), os.path.join(top, "out")
    with open(path, "w") as f:
        json.dump(doc, f)
    process = subprocess.Popen([mpiexec, "-np", str(np), "--oversubscribe", binary, "run", path,
                                "--out", out, "--checkpoint-every", "100000000"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while not os.path.exists(os.path.join(out, "particles_000.csv")) and time.time() < deadline:
        time.sleep(0.2)
    time.sleep(1.0)
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=120)
    summary_path = os.path.join(out, "summary.json")
    check(os.path.exists(summary_path), f"SIGTERM on {np} ranks: no summary; {stderr[-500:]}")
    if not os.path.exists(summary_path):
        return
    with open(summary_path) as f:
        summary = json.load(f)
    check(summary["status"] == "interrupted" and "SIGTERM" in summary["reason"],
          f"SIGTERM on {np} ranks: {summary.get('status')} {summary.get('reason')}")
    with open(os.path.join(out, "energy.csv")) as f:
        rows = f.read().splitlines()[1:]
    check(len(rows) == summary["steps"] + 1, f"energy rows {len(rows)}, steps {summary['steps']}")
    final = "checkpoint_%09d" % summary["steps"]
    pieces = [final + ".ckpt"] + [f"{final}_r{r}.ckpt" for r in range(1, np)]
    check(all(os.path.exists(os.path.join(out, p)) for p in pieces),
          f"final checkpoint pieces {pieces}: {sorted(os.listdir(out))}")


def main():
    mpiexec, np, binary = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    interrupted(mpiexec, np, binary, sys.argv[4])
    for scene in sys.argv[4:]:
        compare(mpiexec, np, binary, scene)
    restart(mpiexec, np, binary, sys.argv[4], 20)  # the 2D plate
    blow_up(mpiexec, np, binary, sys.argv[4])
    moving = [s for s in sys.argv[4:] if "moving" in s]
    if moving:
        restart(mpiexec, np, binary, moving[0], 200)
    if failures:
        print(f"{len(failures)} failures; the runs are in {WORK}")
        sys.exit(1)
    shutil.rmtree(WORK)
    print("ok")


if __name__ == "__main__":
    main()
