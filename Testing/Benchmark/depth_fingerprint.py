#!/usr/bin/env python3
"""Fingerprints of the C++ filter's images on the bundled datasets and on the benchmark's Kuhn
lattice: one SHA-256 per output array (Depth, Normals, CellId, Colors, ColorValues) per scene,
so that a refactoring can be checked to leave every image identical to the last bit:

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Testing/Benchmark/depth_fingerprint.py > before.txt
  ... change, rebuild ...
  ... the same > after.txt; diff before.txt after.txt   (no output: bit-identical)

Scenes: every .vtu in Data/ and Testing/Data/ (its first one-component point array, three iso-values inside
its range, two cameras, exact and nodal normals, a clipping plane with a cap), a 20^3 lattice
with a wave field, the lattice with every third cell re-typed as a 4-node tetrahedron, and with
32-bit connectivity.
"""
import glob
import hashlib
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints, vtkTypeInt32Array
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, VTK_TETRA, vtkCellArray, vtkPlane,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import vtkDirectSurfaceRayCaster

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "Testing", "Python"))
from kuhn_lattice import lattice  # noqa: E402


def digest(array):
    return hashlib.sha256(np.ascontiguousarray(vtk_to_numpy(array)).tobytes()).hexdigest()[:16]


def grid_of(points, cells, types, values, int32=False):
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    counts = np.array([10 if t == VTK_QUADRATIC_TETRA else 4 for t in types])
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    connectivity = np.concatenate([c[:n] for c, n in zip(cells, counts)]).astype(np.int64)
    cell_array = vtkCellArray()
    if int32:
        o, c = vtkTypeInt32Array(), vtkTypeInt32Array()
        o.DeepCopy(numpy_to_vtk(offsets.astype(np.int32), deep=True))
        c.DeepCopy(numpy_to_vtk(connectivity.astype(np.int32), deep=True))
        cell_array.SetData(o, c)
    else:
        cell_array.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                           numpy_to_vtkIdTypeArray(connectivity, deep=True))
    grid.SetCells(numpy_to_vtk(np.array(types, dtype=np.uint8), deep=True), cell_array)
    field = numpy_to_vtk(values, deep=True)
    field.SetName("f")
    grid.GetPointData().SetScalars(field)
    return grid


def render(name, grid, array, isos, out):
    lo, hi = grid.GetPointData().GetArray(array).GetRange(0)
    b = grid.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    for view, direction in enumerate(((0.3, 0.5, 1.0), (-1.0, 0.2, -0.4))):
        for mode in (vtkDirectSurfaceRayCaster.EXACT_GRADIENT,
                     vtkDirectSurfaceRayCaster.NODAL_INTERPOLATION):
            for clipped in (False, True):
                caster = vtkDirectSurfaceRayCaster()
                caster.SetInputData(grid)
                caster.SetInputArrayToProcess(0, 0, 0, 0, array)
                for k, fraction in enumerate(isos):
                    caster.SetValue(k, lo + fraction * (hi - lo))
                camera = vtkCamera()
                camera.SetFocalPoint(centre)
                camera.SetPosition([c + 2.5 * size * d for c, d in zip(centre, direction)])
                camera.SetViewAngle(30)
                caster.SetCamera(camera)
                caster.SetImageSize(160, 120)
                caster.SetNormalMode(mode)
                if clipped:
                    plane = vtkPlane()
                    plane.SetOrigin(centre)
                    plane.SetNormal(0.2, -1.0, 0.3)
                    caster.AddClippingPlane(plane)
                    caster.SetCapping(vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE)
                caster.Update()
                data = caster.GetOutput().GetPointData()
                hashes = " ".join(
                    f"{a}={digest(data.GetArray(a))}" for a in
                    ("Depth", "Normals", "CellId", "Colors", "ColorValues") if data.GetArray(a))
                hits = int(np.isfinite(vtk_to_numpy(data.GetArray("Depth"))).sum())
                out.write(f"{name} view{view} mode{mode} clip{int(clipped)} hits={hits} {hashes}\n")


def main():
    out = sys.stdout
    files = sorted(glob.glob(os.path.join(ROOT, "Data", "*.vtu")) +
                   glob.glob(os.path.join(ROOT, "Testing", "Data", "*.vtu")))
    for path in files:
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        grid = reader.GetOutput()
        data = grid.GetPointData()
        array = next(data.GetArrayName(k) for k in range(data.GetNumberOfArrays())
                     if data.GetArray(k).GetNumberOfComponents() == 1)
        render(os.path.basename(path), grid, array, (0.3, 0.55, 0.8), out)
    points, cells = lattice(20)
    x, y, z = points.T
    wave = np.sin(3 * x) * np.cos(2 * y) + 0.5 * z * z
    quadratic = [VTK_QUADRATIC_TETRA] * len(cells)
    render("lattice20-wave", grid_of(points, cells, quadratic, wave), "f", (0.4, 0.6), out)
    mixed = [VTK_TETRA if c % 3 == 0 else VTK_QUADRATIC_TETRA for c in range(len(cells))]
    render("lattice20-mixed", grid_of(points, cells, mixed, wave), "f", (0.4, 0.6), out)
    render("lattice20-int32", grid_of(points, cells, quadratic, wave, int32=True), "f", (0.5,), out)


if __name__ == "__main__":
    main()
