"""What the flow generators (make_expansion_flow.py, make_cylinder_flow.py) share: taking a gmsh
order-2 mesh's tetrahedra (make_p3_poisson.py takes its order-3 ones the same way), and writing
VTK_QUADRATIC_TETRA cells with point arrays to a .vtu."""
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter


def tetrahedra_nodes(node_tags, coords, cell_node_tags, nodes_per_cell=10):
    """Points (n x 3) and cells (m x nodes_per_cell, gmsh's node order) of gmsh's tetrahedra
    (10-node ones by default), keeping only their nodes, numbered 0..n-1 in the order of their
    tags (gmsh's tags need not be contiguous)."""
    node_tags = np.asarray(node_tags, dtype=np.int64)
    row = np.zeros(node_tags.max() + 1, dtype=np.int64)
    row[node_tags] = np.arange(len(node_tags))
    used, cells = np.unique(np.asarray(cell_node_tags, dtype=np.int64), return_inverse=True)
    return np.asarray(coords).reshape(-1, 3)[row[used]], cells.reshape(-1, nodes_per_cell)


def write_vtu(path, points, cells, arrays, field_data=None):
    """Writes the cells as VTK_QUADRATIC_TETRA with the given point arrays (name: values, "speed"
    the active scalars) and one-value field data (name: value)."""
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    connectivity = vtkCellArray()
    connectivity.SetData(numpy_to_vtkIdTypeArray(np.arange(0, cells.size + 1, 10), deep=True),
                         numpy_to_vtkIdTypeArray(cells.ravel().astype(np.int64), deep=True))
    grid.SetCells(VTK_QUADRATIC_TETRA, connectivity)
    for name, values in arrays.items():
        array = numpy_to_vtk(values, deep=True)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    grid.GetPointData().SetActiveScalars("speed")
    for name, value in (field_data or {}).items():
        array = vtkDoubleArray()
        array.SetName(name)
        array.InsertNextValue(value)
        grid.GetFieldData().AddArray(array)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    # Inline binary: VTK 9.2's appended mode once wrote files here that it could not read back.
    writer.SetDataModeToBinary()
    if not writer.Write():
        sys.exit(f"could not write {path}")
