#!/usr/bin/env python3
"""Requirement: a distributed run's points.pvd lists one .pvtu per output step,
each with one piece per rank, that VTK's own XML reader (the one ParaView uses) reads as
the whole body: every point once, and at the last step the positions and stresses of
points_final.csv. Each piece is its rank's points (stage 4b); with --moves some points
must change piece between output steps (points that moved into another rank's cells).

    pvtu_check.py RUN_FOLDER RANKS [--moves]
"""
import csv
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import vtk
from vtk.util.numpy_support import vtk_to_numpy

folder, ranks = Path(sys.argv[1]), int(sys.argv[2])
moves_expected = "--moves" in sys.argv[3:]
files = [d.get("file") for d in ET.parse(folder / "points.pvd").getroot().iter("DataSet")]
final = list(csv.DictReader(open(folder / "points_final.csv")))
n = len(final)
status = 0
owner, moves = None, 0  # the piece of each point id at the last step read, and changes of piece
for f in files:
    pieces = [p.get("Source") for p in ET.parse(folder / f).getroot().iter("Piece")]
    now = {}
    for r, piece in enumerate(pieces):
        one = vtk.vtkXMLUnstructuredGridReader()
        one.SetFileName(str(folder / piece))
        one.Update()
        for i in vtk_to_numpy(one.GetOutput().GetPointData().GetArray("id")):
            now[int(i)] = r
    if owner is not None:
        moves += sum(1 for i, r in now.items() if owner.get(i, r) != r)
    owner = now
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(folder / f))
    reader.Update()
    grid = reader.GetOutput()
    ids = sorted(int(i) for i in vtk_to_numpy(grid.GetPointData().GetArray("id")))
    if not f.endswith(".pvtu") or len(pieces) != ranks or grid.GetNumberOfPoints() != n or ids != list(range(n)):
        print(f"{f}: {len(pieces)} pieces, {grid.GetNumberOfPoints()} points (expected .pvtu, {ranks} pieces, "
              f"{n} points, ids 0..{n - 1} once each)")
        status = 1
grid_ids = vtk_to_numpy(grid.GetPointData().GetArray("id"))
xyz = vtk_to_numpy(grid.GetPoints().GetData())
stress = vtk_to_numpy(grid.GetPointData().GetArray("stress"))
worst = 0.0
scale = max(abs(float(r["syy"])) for r in final)
for k, i in enumerate(grid_ids):
    row = final[int(i)]
    for d, c in enumerate("xyz"):
        worst = max(worst, abs(xyz[k][d] - float(row[c])))
    worst = max(worst, abs(stress[k][4] - float(row["syy"])) / scale)
print(f"{len(files)} steps of {ranks} pieces each read by VTK {vtk.vtkVersion.GetVTKVersion()}; "
      f"last step against points_final.csv: largest difference {worst:.1e}; "
      f"{moves} point(s) changed piece between steps")
if worst > 1e-12:
    status = 1
if moves_expected and moves == 0:
    print("expected points to change piece (rank) during the run")
    status = 1
sys.exit(status)
