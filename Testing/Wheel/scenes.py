"""Scenes both builds render: the C++ filter (cxx_reference.py, in /usr/bin/python3 with the C++
build's `tetdsr` and ParaView's VTK 9.2) and the wheel's filter (test_agreement.py, in the venv
with pip's VTK). Only VTK API common to both versions is used here.

Each scene is a function (caster class, data folder) -> (caster ready to Update, objects to keep
alive, the scene's diagonal)."""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_TETRAHEDRON, VTK_PENTAGONAL_PRISM,
                                           VTK_LAGRANGE_TETRAHEDRON, VTK_QUADRATIC_TETRA, VTK_TETRA,
                                           vtkCellArray, vtkPlane, vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402 (also used by the tests through scenes)

# A fixed quadric |x|_M^2 + g.x: nested ellipsoids in [-1, 1]^3 (scene "quadric_lattice").
QUADRIC_M = np.array([[1.0, 0.3, -0.2], [0.3, 0.7, 0.1], [-0.2, 0.1, 1.3]])
QUADRIC_G = np.array([0.2, -0.1, 0.3])


def read(data, name):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(data, name))
    reader.Update()
    return reader.GetOutput()


def grid(points, cells, fields):
    """A vtkUnstructuredGrid of quadratic tets with point arrays {name: values}."""
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    ug.SetPoints(p)
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 10 * len(cells) + 1, 10, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(np.ascontiguousarray(cells, dtype=np.int64).ravel(), deep=1))
    ug.SetCells(numpy_to_vtk(np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8), deep=1), ca)
    for name, values in fields.items():
        array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
        array.SetName(name)
        ug.GetPointData().AddArray(array)
    ug.GetPointData().SetActiveScalars(next(iter(fields)))
    return ug


def camera(position, focal_point=(0.0, 0.0, 0.0), view_angle=30.0, parallel=False, scale=1.0):
    c = vtkCamera()
    c.SetFocalPoint(*focal_point)
    c.SetPosition(*position)
    c.SetViewUp(0.0, 1.0, 0.0)
    c.SetViewAngle(view_angle)
    c.SetParallelProjection(parallel)
    c.SetParallelScale(scale)
    return c


def _caster(cls, mesh, iso, cam, size):
    caster = cls()
    caster.SetInputData(mesh) if hasattr(caster, "SetInputData") else caster.SetInputDataObject(0, mesh)
    for i, v in enumerate(iso):
        caster.SetValue(i, v)
    if cam is not None:
        caster.SetCamera(cam)
    caster.SetImageSize(*size)
    return caster


def cube(cls, data, parallel):
    mesh = read(data, "cube27.vtu")
    cam = camera((3.0, 2.2, 4.1), view_angle=24.0, parallel=parallel, scale=0.9)
    return _caster(cls, mesh, [0.8], cam, (220, 180)), (mesh, cam), mesh.GetLength()


def sphere_in_cell(cls, data):
    mesh = read(data, "sphere_in_cell.vtu")
    fd = mesh.GetFieldData()
    centre = np.array([fd.GetArray("SphereCentre").GetValue(k) for k in range(3)])
    cam = camera(centre + [0.4, -0.7, 1.3], centre, view_angle=18.0)
    return _caster(cls, mesh, [0.0], cam, (160, 120)), (mesh, cam), mesh.GetLength()


def quadric_lattice(cls, data):
    """Two nested ellipsoids, the outer one translucent, coloured by x, cut by a plane and capped."""
    points, cells = lattice(3)
    field = np.einsum("ij,jk,ik->i", points, QUADRIC_M, points) + points @ QUADRIC_G
    mesh = grid(points, cells, {"quadric": field, "x": points[:, 0].copy()})
    cam = camera((2.6, 1.9, 3.3), view_angle=32.0)
    caster = _caster(cls, mesh, [0.3, 0.8], cam, (200, 160))
    caster.SetIsoValueOpacity(1, 0.5)
    caster.ColorByArrayOn()
    caster.SetInputArrayToProcess(1, 0, 0, 0, "x")
    plane = vtkPlane()
    plane.SetOrigin(0.0, 0.0, 0.3)
    plane.SetNormal(0.0, 0.0, -1.0)
    caster.AddClippingPlane(plane)
    caster.SetCapping(1)  # CAP_BELOW_ISO_VALUE
    return caster, (mesh, cam, plane), mesh.GetLength()


def flow(cls, data):
    """The expansion flow, speed = 0.25 coloured by pressure, with the default camera."""
    mesh = read(data, "expansion_flow.vtu")
    caster = _caster(cls, mesh, [0.25], None, (240, 120))
    caster.SetInputArrayToProcess(0, 0, 0, 0, "speed")
    caster.ColorByArrayOn()
    caster.SetInputArrayToProcess(1, 0, 0, 0, "pressure")
    caster.SetSpecular(0.4)
    return caster, (mesh,), mesh.GetLength()


def mixed_cells(cls, data):
    """The sphere in a cell, plus a pentagonal prism (a type TetDSR does not read: skipped) and a
    linear tet: the copying path."""
    mesh = vtkUnstructuredGrid()
    mesh.DeepCopy(read(data, "sphere_in_cell.vtu"))
    base = mesh.GetNumberOfPoints()
    for p in range(10):
        mesh.GetPoints().InsertNextPoint(0.2 + 0.5 * (p & 1), 0.2 + 0.5 * ((p >> 1) & 1), 1.5 + 0.5 * (p >> 2))
        mesh.GetPointData().GetArray("sphere").InsertNextValue(-0.5 + 0.3 * p)
    mesh.InsertNextCell(VTK_PENTAGONAL_PRISM, 10, [base + k for k in range(10)])
    mesh.InsertNextCell(VTK_TETRA, 4, [base, base + 1, base + 2, base + 4])
    cam = camera((1.5, 1.2, 5.0), (0.0, 0.0, 0.5), view_angle=35.0)
    return _caster(cls, mesh, [0.0], cam, (150, 150)), (mesh, cam), mesh.GetLength()


def higher_order(cls, data, vtk_type, order):
    """A straight Lagrange or Bezier grid (higher_order_grids.py): the order-4 torus, or the order-3
    cubic coloured by a cubic array and cut by a capped plane."""
    import higher_order_grids as hog
    field = hog.torus() if order == 4 else hog.cubic_blob()
    mesh = hog.grid(2, vtk_type, order, {"f": field.value, "colour": lambda x: x[..., 0] ** 3 - x[..., 1] * x[..., 2]})
    cam = camera((1.7, 1.35, 2.5), (0.5, 0.5, 0.5), view_angle=24.0)
    caster = _caster(cls, mesh, [field.iso], cam, (160, 120))
    keep = (mesh, cam)
    if order == 3:
        caster.ColorByArrayOn()
        caster.SetInputArrayToProcess(1, 0, 0, 0, "colour")
        plane = vtkPlane()
        plane.SetOrigin(0.5, 0.5, 0.55)
        plane.SetNormal(0.2, 0.1, -1.0)
        caster.AddClippingPlane(plane)
        caster.SetCapping(1)  # CAP_BELOW_ISO_VALUE
        keep += (plane,)
    return caster, keep, mesh.GetLength()


def hexahedra_and_wedges(cls, data, kind):
    """Hexahedra and wedges (hex_wedge_grids.py): "mixed", the curved mesh mixing 20-node
    hexahedra, 15- and 18-node wedges and quadratic tetrahedra (a sphere, coloured by a cubic);
    "lagrange_hex3", straight Lagrange hexahedra of order 3 (pieces of order 9) holding a Q3
    polynomial, cut by a capped plane."""
    import hex_wedge_grids as hw
    from vtkmodules.vtkCommonDataModel import VTK_LAGRANGE_HEXAHEDRON
    cam = camera((1.7, 1.35, 2.5), (0.5, 0.5, 0.5), view_angle=24.0)
    colour = {"colour": lambda x: x[..., 0] ** 3 - x[..., 1] * x[..., 2]}
    if kind == "mixed":
        centre = np.array([0.47, 0.53, 0.51])
        mesh = hw.mixed_mesh(hw.bulge(), {"f": lambda x: np.sum((x - centre) ** 2, axis=-1), **colour})
        caster = _caster(cls, mesh, [0.09], cam, (120, 90))  # (curved hexahedra: a solve per ray)
        keep = (mesh, cam)
    else:
        u = lambda x, k: x[..., k] - 0.5  # noqa: E731
        mesh = hw.grid(2, VTK_LAGRANGE_HEXAHEDRON, 64, {
            "f": lambda x: u(x, 0) ** 2 + u(x, 1) ** 2 + u(x, 2) ** 2 + 4.0 * (u(x, 0) * u(x, 1) * u(x, 2)) ** 3,
            **colour})
        caster = _caster(cls, mesh, [0.1], cam, (160, 120))
        plane = vtkPlane()
        plane.SetOrigin(0.5, 0.5, 0.55)
        plane.SetNormal(0.2, 0.1, -1.0)
        caster.AddClippingPlane(plane)
        caster.SetCapping(1)  # CAP_BELOW_ISO_VALUE
        keep = (mesh, cam, plane)
    caster.ColorByArrayOn()
    caster.SetInputArrayToProcess(1, 0, 0, 0, "colour")
    return caster, keep, mesh.GetLength()


SCENES = {
    "cube_perspective": lambda cls, data: cube(cls, data, False),
    "cube_parallel": lambda cls, data: cube(cls, data, True),
    "sphere_in_cell": sphere_in_cell,
    "quadric_lattice": quadric_lattice,
    "flow": flow,
    "mixed_cells": mixed_cells,
    "lagrange_torus": lambda cls, data: higher_order(cls, data, VTK_LAGRANGE_TETRAHEDRON, 4),
    "bezier_cubic": lambda cls, data: higher_order(cls, data, VTK_BEZIER_TETRAHEDRON, 3),
    "mixed_hex_wedge": lambda cls, data: hexahedra_and_wedges(cls, data, "mixed"),
    "lagrange_hex3": lambda cls, data: hexahedra_and_wedges(cls, data, "lagrange_hex3"),
}
OUTPUTS = ("Colors", "Depth", "Normals", "CellId", "ColorValues")


def render(cls, data, name):
    """The scene's output arrays as numpy arrays (copies) and its diagonal."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    caster, keep, diagonal = SCENES[name](cls, data)
    caster.Update()
    point_data = caster.GetOutputDataObject(0).GetPointData()
    arrays = {k: vtk_to_numpy(point_data.GetArray(k)).copy() for k in OUTPUTS
              if point_data.GetArray(k) is not None}
    del keep
    return arrays, diagonal
