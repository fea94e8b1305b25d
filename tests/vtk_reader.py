#!/usr/bin/env python3
"""Reads a 2D run's VTK output back with Debian's VTK (python3-vtk9), not with dgmpm's code:
runs DGMPM_BINARY on the plate scene into a fresh folder, opens particles.pvd's data sets with
vtkXMLUnstructuredGridReader and checks that every .vtu holds the particles and fields of the
matching CSV, the time series is in order, and sigma_zz and von Mises are consistent.

    python3 tests/vtk_reader.py build/bin/dgmpm scenes/plate_impact.json
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def main():
    binary, scene = sys.argv[1], sys.argv[2]
    out = tempfile.mkdtemp(prefix="dgmpm_vtk_")
    subprocess.run([binary, "run", scene, "--out", out], check=True, capture_output=True)
    pvd = ET.parse(os.path.join(out, "particles.pvd")).getroot()
    sets = pvd.find("Collection").findall("DataSet")
    check(len(sets) >= 2, f"{len(sets)} data sets in particles.pvd")
    times = [float(s.get("timestep")) for s in sets]
    check(times == sorted(times) and len(set(times)) == len(times), f"times in order: {times}")
    nu = 0.3
    for k, s in enumerate(sets):
        path = os.path.join(out, s.get("file"))
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        grid = reader.GetOutput()
        n = grid.GetNumberOfPoints()
        with open(os.path.join(out, f"particles_{k:03d}.csv")) as f:
            rows = list(csv.DictReader(f))
        check(n == len(rows) == 825, f"{path}: {n} points, {len(rows)} CSV rows")
        check(grid.GetNumberOfCells() == n, f"{path}: one vertex cell per particle")
        points = vtk_to_numpy(grid.GetPoints().GetData())
        data = grid.GetPointData()
        names = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]
        for name in ["sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "von_mises", "velocity",
                     "mass", "volume", "id", "material"]:
            check(name in names, f"{path}: array {name}")
        arr = {name: vtk_to_numpy(data.GetArray(name)) for name in names}
        check(arr["velocity"].shape == (n, 3), f"{path}: velocity has 3 components")
        worst = 0.0
        for i, r in enumerate(rows):
            check(int(arr["id"][i]) == int(r["id"]), f"{path}: particle {i} id")
            scale = 2e8
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
        check(worst < 1e-12, f"{path}: VTK and CSV differ by {worst}")
        if k == len(sets) - 1:
            check(arr["sigma_xx"].min() < -1e8, f"{path}: the load's compression is there")
    print(f"{len(sets)} data sets read with VTK {vtk.vtkVersion.GetVTKVersion()}")
    print(f"{0 if failures else 1} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
