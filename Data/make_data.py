#!/usr/bin/env python3
"""Writes the bundled meshes (run with /usr/bin/python3; needs only VTK):

cube27.vtu           The paper's second example: the cube [-1, 1]^3 split into 6 tetrahedra
                     around its main diagonal (27 nodes: 8 corners, 12 edge midpoints, 6 face
                     centres, the cube centre), field "distance" = |x| (0 at the centre,
                     1.732 at the corners).
sphere_in_cell.vtu   The same 6 cells with the exactly quadratic field
                     "sphere" = |x - c|^2 - r^2, c the centroid of cell 0 and r half its
                     inradius: the zero isosurface is a sphere strictly inside cell 0, and
                     every nodal value is positive, so linear contouring finds nothing.
                     Field data records the centre and radius.
"""
import itertools
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

# VTK_QUADRATIC_TETRA mid-edge order.
EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]


def kuhn_cube():
    """Nodes (n x 3) and 10-node cells of [-1,1]^3 split into 6 positively oriented tets."""
    nodes, index = [], {}

    def node(p):
        key = tuple(np.round(p, 12))
        if key not in index:
            index[key] = len(nodes)
            nodes.append(p)
        return index[key]

    cells = []
    for perm in itertools.permutations(range(3)):
        corner = np.array([-1.0, -1.0, -1.0])
        vertices = [corner.copy()]
        for axis in perm:
            corner[axis] += 2.0
            vertices.append(corner.copy())
        if np.linalg.det(np.array(vertices[1:]) - vertices[0]) < 0:
            vertices[1], vertices[2] = vertices[2], vertices[1]
        ids = [node(v) for v in vertices]
        ids += [node(0.5 * (vertices[a] + vertices[b])) for a, b in EDGES]
        cells.append(ids)
    return np.array(nodes), cells


def grid(points, cells, fields):
    ug = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetDataTypeToDouble()
    for p in points:
        vtk_points.InsertNextPoint(*p)
    ug.SetPoints(vtk_points)
    for ids in cells:
        ug.InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids)
    for name, values in fields.items():
        array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
        array.SetName(name)
        ug.GetPointData().AddArray(array)
    ug.GetPointData().SetActiveScalars(next(iter(fields)))
    return ug


def write(ug, path):
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(ug)
    writer.SetDataModeToAscii()
    if not writer.Write():
        sys.exit(f"could not write {path}")


def inradius(vertices):
    volume6 = abs(np.linalg.det(vertices[1:] - vertices[0]))
    area2 = sum(np.linalg.norm(np.cross(vertices[b] - vertices[a], vertices[c] - vertices[a]))
                for a, b, c in [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)])
    return volume6 / area2  # 3V / total area, with 6V and 2*area


def main(out_dir):
    points, cells = kuhn_cube()
    assert len(points) == 27 and len(cells) == 6
    write(grid(points, cells, {"distance": np.linalg.norm(points, axis=1)}),
          os.path.join(out_dir, "cube27.vtu"))

    vertices = points[cells[0][:4]]
    centre = vertices.mean(axis=0)
    radius = 0.5 * inradius(vertices)
    sphere = np.sum((points - centre) ** 2, axis=1) - radius ** 2
    assert sphere.min() > 0.0, "every nodal value must lie above the iso-value 0"
    ug = grid(points, cells, {"sphere": sphere})
    for name, value in (("SphereCentre", centre), ("SphereRadius", [radius])):
        array = vtkDoubleArray()
        array.SetName(name)
        for v in value:
            array.InsertNextValue(v)
        ug.GetFieldData().AddArray(array)
    write(ug, os.path.join(out_dir, "sphere_in_cell.vtu"))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__)))
