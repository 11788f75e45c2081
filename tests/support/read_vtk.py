#!/usr/bin/python3
"""Reads a ParaView series (.pvd) and its .vtp files with VTK's own XML reader (Debian's
python3-vtk9) and prints what it found as JSON: per frame its time, file, point and vertex
counts, the array names, and every point's coordinates and array values.
Exit 77 when VTK cannot be imported (the test reports itself skipped)."""
import json
import os
import sys
import xml.etree.ElementTree as ElementTree

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:
    print(f"VTK's Python bindings are missing ({e}): scripts/setup.sh --tests installs python3-vtk9")
    sys.exit(77)

pvd = sys.argv[1]
frames = []
for ds in ElementTree.parse(pvd).getroot().iter("DataSet"):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(os.path.join(os.path.dirname(pvd), ds.get("file")))
    reader.Update()
    if reader.GetErrorCode() != 0:
        print(f"VTK could not read {ds.get('file')}")
        sys.exit(1)
    out = reader.GetOutput()
    n = out.GetNumberOfPoints()
    data = out.GetPointData()
    arrays = {}
    for k in range(data.GetNumberOfArrays()):
        a = data.GetArray(k)
        c = a.GetNumberOfComponents()
        arrays[a.GetName()] = [a.GetComponent(i, j) for i in range(n) for j in range(c)]
    frames.append({"time": float(ds.get("timestep")), "file": ds.get("file"), "points": n,
                   "verts": out.GetNumberOfVerts(), "xyz": [x for i in range(n) for x in out.GetPoint(i)],
                   "arrays": arrays})
print(json.dumps({"frames": frames}))
