#!/usr/bin/env python3
"""Requirement: a distributed run writes the grid of
each output step as a .pvtu of one piece per rank, each piece its rank's cells with the
fields at their corners taken from the nodes' owners (nothing gathered whole), and VTK's
XML reader (ParaView's) reads it as the serial run's grid: every cell once, and at every
piece's node the serial run's displacement increment and nodal mass (to 1e-8 of each
field's largest magnitude; the two runs' linear solvers differ by round-off).

    grid_pieces_check.py SERIAL_FOLDER RANKS_FOLDER RANKS
"""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

serial, parallel, ranks = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3])
FIELDS = ("displacement_increment", "mass")


def files(folder):
    return [d.get("file") for d in ET.parse(folder / "grid.pvd").getroot().iter("DataSet")]


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def cells_of(grid):
    """Each cell as the sorted tuple of its corners' coordinates (rounded: the same grid)."""
    xyz = vtk_to_numpy(grid.GetPoints().GetData())
    out = []
    for c in range(grid.GetNumberOfCells()):
        ids = grid.GetCell(c).GetPointIds()
        out.append(tuple(sorted(tuple(np.round(xyz[ids.GetId(k)], 9)) for k in range(ids.GetNumberOfIds()))))
    return out


status = 0
serial_files, parallel_files = files(serial), files(parallel)
if len(serial_files) != len(parallel_files):
    print(f"grid.pvd: {len(serial_files)} serial steps, {len(parallel_files)} distributed")
    sys.exit(1)
worst = {f: 0.0 for f in FIELDS}
for sf, pf in zip(serial_files, parallel_files):
    whole = read(serial / sf)
    at = {tuple(np.round(x, 9)): k for k, x in enumerate(vtk_to_numpy(whole.GetPoints().GetData()))}
    values = {f: vtk_to_numpy(whole.GetPointData().GetArray(f)).reshape(whole.GetNumberOfPoints(), -1) for f in FIELDS}
    scale = {f: max(float(np.abs(values[f]).max()), 1e-300) for f in FIELDS}
    pieces = [p.get("Source") for p in ET.parse(parallel / pf).getroot().iter("Piece")]
    if not pf.endswith(".pvtu") or len(pieces) != ranks:
        print(f"{pf}: expected a .pvtu of {ranks} pieces, found {len(pieces)}")
        status = 1
        continue
    cells = []
    for piece in pieces:
        grid = read(parallel / piece)
        cells += cells_of(grid)
        xyz = vtk_to_numpy(grid.GetPoints().GetData())
        for f in FIELDS:
            mine = vtk_to_numpy(grid.GetPointData().GetArray(f)).reshape(grid.GetNumberOfPoints(), -1)
            for k, x in enumerate(xyz):
                worst[f] = max(worst[f], float(np.abs(mine[k] - values[f][at[tuple(np.round(x, 9))]]).max()) / scale[f])
    if sorted(cells) != sorted(cells_of(whole)):
        print(f"{pf}: the pieces' cells ({len(cells)}) are not the serial grid's cells ({whole.GetNumberOfCells()}) once each")
        status = 1
    reader = vtk.vtkXMLPUnstructuredGridReader()  # the .pvtu as ParaView opens it
    reader.SetFileName(str(parallel / pf))
    reader.Update()
    if reader.GetOutput().GetNumberOfCells() != whole.GetNumberOfCells():
        print(f"{pf}: VTK reads {reader.GetOutput().GetNumberOfCells()} cells, the serial grid has {whole.GetNumberOfCells()}")
        status = 1
print(f"{len(parallel_files)} grid steps of {ranks} pieces against the serial grid: largest difference "
      + ", ".join(f"{f} {worst[f]:.1e}" for f in FIELDS) + " of the field's largest magnitude")
if max(worst.values()) > 1e-8:
    status = 1
sys.exit(status)
