#!/usr/bin/env python3
"""Reads a 2D run's VTK output back with Debian's VTK (python3-vtk9), not with dgmpm's code:
runs DGMPM_BINARY on the plate scene twice into fresh folders, with binary VTU (the 2D default:
raw arrays appended after the XML) and with "output.vtu_encoding": "ascii", opens particles.pvd's
data sets with vtkXMLUnstructuredGridReader and checks that every .vtu holds the particles and
fields of the matching CSV, its TimeValue is the .pvd's time, the time series is in order,
sigma_zz, von Mises, the stress and strain tensors (the strain from the stress by Hooke's law
written here, eps_zz = 0) and the size are consistent, the FieldData's units name every array's,
the two encodings hold the same values (to the bit: text is written with 17 digits) and the
binary files are at least three times smaller; a third run with moving particles has a
displacement array (and CSV columns) equal to each particle's position less its first one;
examples/plot_run.py draws a field of the run and refuses an absent one.

    python3 tests/vtk_reader.py build/bin/dgmpm scenes/plate_impact.json
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

failures = []
# Every run's folder is made in this one, removed at the end if every check passed (kept, and
# named, otherwise).
WORK = tempfile.mkdtemp(prefix="dgmpm_vtk_")
NAMES = ["sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "von_mises", "velocity",
         "stress_tensor", "strain_tensor", "mass", "volume", "size", "id", "material"]
UNITS = {"sigma_xx": "Pa", "sigma_yy": "Pa", "sigma_xy": "Pa", "sigma_zz": "Pa",
         "von_mises": "Pa", "velocity": "m/s", "stress_tensor": "Pa", "strain_tensor": "1",
         "mass": "kg/m", "volume": "m^2", "size": "m", "Points": "m", "TimeValue": "s"}
YOUNG = 2e11  # the plate's steel


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(binary, scene, encoding, move=False):
    """Runs the scene with the given VTU encoding; returns the output folder."""
    out = tempfile.mkdtemp(prefix=f"{encoding}_", dir=WORK)
    with open(scene) as f:
        doc = json.load(f)
    doc.setdefault("output", {})["vtu_encoding"] = encoding
    if move:
        doc["particles_move"] = True
    path = os.path.join(out, "scene.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    subprocess.run([binary, "run", path, "--out", os.path.join(out, "run")], check=True,
                   capture_output=True)
    return os.path.join(out, "run")


def read(out):
    """Reads every data set of particles.pvd: [(time, path, points, arrays, TimeValue)]."""
    pvd = ET.parse(os.path.join(out, "particles.pvd")).getroot()
    sets = pvd.find("Collection").findall("DataSet")
    result = []
    for s in sets:
        path = os.path.join(out, s.get("file"))
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        grid = reader.GetOutput()
        check(grid.GetNumberOfCells() == grid.GetNumberOfPoints(),
              f"{path}: one vertex cell per particle")
        data = grid.GetPointData()
        names = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]
        for name in NAMES:
            check(name in names, f"{path}: array {name}")
        arrays = {name: vtk_to_numpy(data.GetArray(name)) for name in names}
        field = grid.GetFieldData().GetArray("TimeValue")
        time_value = field.GetValue(0) if field is not None else None
        units = grid.GetFieldData().GetAbstractArray("units")
        units = dict(units.GetValue(i).split(": ") for i in range(units.GetNumberOfValues())) \
            if units is not None else {}
        for name, unit in UNITS.items():
            check(units.get(name) == unit, f"{path}: unit of {name} {units.get(name)}, not {unit}")
        check(set(units) <= set(names) | {"Points", "TimeValue"}, f"{path}: units {units}")
        result.append((float(s.get("timestep")), path,
                       vtk_to_numpy(grid.GetPoints().GetData()), arrays, time_value))
    return result


def check_against_csv(out, sets, nu=0.3):
    times = [t for t, *_ in sets]
    check(len(sets) >= 2, f"{len(sets)} data sets in particles.pvd")
    check(times == sorted(times) and len(set(times)) == len(times), f"times in order: {times}")
    for k, (t, path, points, arr, time_value) in enumerate(sets):
        check(time_value == t, f"{path}: TimeValue {time_value}, .pvd time {t}")
        n = len(points)
        with open(os.path.join(out, f"particles_{k:03d}.csv")) as f:
            rows = list(csv.DictReader(row for row in f if not row.startswith("#")))
        check(n == len(rows) == 825, f"{path}: {n} points, {len(rows)} CSV rows")
        check(arr["velocity"].shape == (n, 3), f"{path}: velocity has 3 components")
        check(arr["stress_tensor"].shape == (n, 9), f"{path}: the stress tensor has 9 components")
        worst = 0.0
        scale = 2e8
        for i, r in enumerate(rows):
            check(int(arr["id"][i]) == int(r["id"]), f"{path}: particle {i} id")
            worst = max(worst, abs(points[i][0] - float(r["x"])), abs(points[i][1] - float(r["y"])),
                        points[i][2] != 0.0)
            for name in ["sigma_xx", "sigma_yy", "sigma_xy"]:
                worst = max(worst, abs(arr[name][i] - float(r[name])) / scale)
            worst = max(worst, abs(arr["velocity"][i][0] - float(r["velocity_x"])),
                        abs(arr["velocity"][i][1] - float(r["velocity_y"])))
            sxx, syy, sxy = (float(r[c]) for c in ("sigma_xx", "sigma_yy", "sigma_xy"))
            szz = nu * (sxx + syy)
            worst = max(worst, abs(arr["sigma_zz"][i] - szz) / scale)
            vm = math.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                           + 3 * sxy * sxy)
            worst = max(worst, abs(arr["von_mises"][i] - vm) / scale)
            tensor = [sxx, sxy, 0.0, sxy, syy, 0.0, 0.0, 0.0, szz]
            worst = max(worst, max(abs(a - b) for a, b in zip(arr["stress_tensor"][i], tensor))
                        / scale)
            worst = max(worst, abs(arr["size"][i] - math.sqrt(arr["volume"][i])))
            trace = sxx + syy + szz
            strain = [((1 + nu) * a - nu * trace * (k in (0, 4, 8))) / YOUNG
                      for k, a in enumerate(tensor)]
            worst = max(worst, max(abs(a - b) for a, b in zip(arr["strain_tensor"][i], strain))
                        * YOUNG / scale, abs(arr["strain_tensor"][i][8]) * YOUNG / scale)
        check(worst < 1e-12, f"{path}: VTK and CSV differ by {worst}")
        if k == len(sets) - 1:
            check(arr["sigma_xx"].min() < -1e8, f"{path}: the load's compression is there")


def check_displacement(out, sets, scene):
    """The moving run: position - displacement is the particle's seeding point (the centre of
    its first cell: one particle per cell), in the VTU and the CSV."""
    with open(scene) as f:
        h = np.array(json.load(f)["grid"]["cell_size"] + [1.0])
    first = {}
    last = sets[-1][3]
    for i, p, u in zip(last["id"], sets[-1][2], last["displacement"]):  # the cell of p - u
        centre = (np.floor((p - u) / h) + 0.5) * h
        centre[2] = 0.0
        first[int(i)] = centre
    worst, largest = 0.0, 0.0
    for k, (t, path, points, arr, _) in enumerate(sets):
        check("displacement" in arr and arr["displacement"].shape == (len(points), 3),
              f"{path}: a displacement array of 3 components")
        with open(os.path.join(out, f"particles_{k:03d}.csv")) as f:
            rows = {int(r["id"]): r for r in csv.DictReader(f)}
        d = arr["displacement"]
        u = points - np.array([first[int(i)] for i in arr["id"]])
        worst = max(worst, float(np.abs(d - u).max()))
        largest = max(largest, float(np.abs(u).max()))
        csv_u = np.array([[float(rows[int(i)]["displacement_x"]),
                           float(rows[int(i)]["displacement_y"]), 0.0] for i in arr["id"]])
        worst = max(worst, float(np.abs(csv_u - d).max()))
    check(worst < 1e-14, f"displacements differ from the positions' change by {worst} m")
    check(largest > 1e-3, f"the plate moved: largest displacement {largest} m")
    print(f"moving run: {len(sets)} data sets, largest displacement {largest:.3g} m, "
          f"worst difference {worst:.2g} m")


def main():
    binary, scene = sys.argv[1], sys.argv[2]
    outs = {e: run(binary, scene, e) for e in ("binary", "ascii")}
    sets = {e: read(out) for e, out in outs.items()}
    moving = run(binary, scene, "binary", move=True)
    check_displacement(moving, read(moving), scene)
    for e in outs:
        check_against_csv(outs[e], sets[e])
    check(len(sets["binary"]) == len(sets["ascii"]), "as many data sets in both encodings")
    for b, a in zip(sets["binary"], sets["ascii"]):
        check(np.array_equal(b[2], a[2]), f"{b[1]}: points as in the ASCII file")
        for name in NAMES:
            check(np.array_equal(b[3][name], a[3][name]), f"{b[1]}: {name} as in the ASCII file")
    with open(sets["binary"][-1][1], "rb") as f:
        check(b'format="appended"' in f.read(), "the default 2D VTU is binary")
    size = {e: sum(os.path.getsize(p) for _, p, *_ in sets[e]) for e in outs}
    n = len(sets["binary"][-1][2])
    print(f"{len(sets['binary'])} data sets per encoding read with VTK "
          f"{vtk.vtkVersion.GetVTKVersion()}; bytes per particle per output: binary "
          f"{size['binary'] / n / len(sets['binary']):.0f}, ASCII "
          f"{size['ascii'] / n / len(sets['ascii']):.0f}")
    check(3 * size["binary"] <= size["ascii"], f"binary {size['binary']} B, ASCII {size['ascii']} B")
    # examples/plot_run.py on the same run: a field the CSV has is drawn, an absent one refused
    # with the list of fields (it was a traceback).
    plot = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "plot_run.py")
    png = os.path.join(outs["binary"], "plot.png")
    r = subprocess.run([sys.executable, plot, outs["binary"], "--field", "sigma_yy", "-o", png],
                       capture_output=True, text=True)
    check(r.returncode == 0 and os.path.getsize(png) > 0, f"plot_run.py sigma_yy: {r.stderr}")
    r = subprocess.run([sys.executable, plot, outs["binary"], "--field", "plastic_strain", "-o",
                        png], capture_output=True, text=True)
    check(r.returncode != 0 and "no such column" in r.stderr and "sigma_xx" in r.stderr
          and "Traceback" not in r.stderr, f"plot_run.py on an absent field: {r.stderr}")
    print(f"{0 if failures else 1} passed, {len(failures)} failed")
    if failures:
        print(f"the runs are in {WORK}")
        sys.exit(1)
    shutil.rmtree(WORK)


if __name__ == "__main__":
    main()
