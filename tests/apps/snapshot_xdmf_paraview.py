"""Opens XDMF files with ParaView's two XDMF readers (run with pvpython, called by
snapshot_xdmf_test.py) and prints, per file and reader, one JSON line: the time steps and, at the
last time, the cells, the first cell's VTK type, the points and the arrays.

Usage: pvpython snapshot_xdmf_paraview.py FILE.xmf...
"""
import json
import sys

from paraview import servermanager
from paraview.simple import UpdatePipeline, XDMFReader, Xdmf3ReaderS

for path in sys.argv[1:]:
    for name, make in (("XDMFReader", lambda: XDMFReader(FileNames=[path])),
                       ("Xdmf3ReaderS", lambda: Xdmf3ReaderS(FileName=[path]))):
        reader = make()
        times = list(reader.TimestepValues)
        UpdatePipeline(time=times[-1], proxy=reader)
        data = servermanager.Fetch(reader)
        if data.IsA("vtkMultiBlockDataSet"):
            data = data.GetBlock(0)
        cells, points = data.GetCellData(), data.GetPointData()
        speed = cells.GetArray("speed")
        print(json.dumps({
            "file": path, "reader": name, "times": times, "cells": data.GetNumberOfCells(),
            "cell_type": data.GetCellType(0) if data.GetNumberOfCells() else None,
            "points": data.GetNumberOfPoints(),
            "cell_arrays": [cells.GetArrayName(i) for i in range(cells.GetNumberOfArrays())],
            "point_arrays": [points.GetArrayName(i) for i in range(points.GetNumberOfArrays())],
            "speed_max": speed.GetRange()[1] if speed else None}))
