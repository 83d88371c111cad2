"""The expansion flow cut into two pieces for the distributed tests: piece0.vtu, piece1.vtu (the
cells on either side of the median of the cells' y centroid: the cut runs along the whole jet,
through the surface) and expansion_flow.pvtu naming them, written inline (this Debian's expat
cannot read VTK's appended XML data)."""
import os

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkFiltersCore import vtkExtractCells
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter


def make_pieces(data_dir, work_dir):
    """Writes the pieces and the .pvtu into work_dir; returns the .pvtu's path."""
    pvtu = os.path.join(work_dir, "expansion_flow.pvtu")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(data_dir, "expansion_flow.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    ids = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)[:, :4]
    centroid_y = points[ids, 1].mean(axis=1)
    median = np.median(centroid_y)
    for piece, cells in enumerate([np.nonzero(centroid_y < median)[0],
                                   np.nonzero(centroid_y >= median)[0]]):
        cell_list = vtkIdList()
        for cell in cells:
            cell_list.InsertNextId(int(cell))
        extract = vtkExtractCells()
        extract.SetInputData(grid)
        extract.SetCellList(cell_list)
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetFileName(os.path.join(work_dir, f"piece{piece}.vtu"))
        writer.SetDataModeToBinary()
        writer.SetInputConnection(extract.GetOutputPort())
        writer.Write()
    point_data = grid.GetPointData()
    arrays = "\n".join(
        f'      <PDataArray type="Float64" Name="{point_data.GetArrayName(k)}" '
        f'NumberOfComponents="{point_data.GetArray(k).GetNumberOfComponents()}"/>'
        for k in range(point_data.GetNumberOfArrays()))
    with open(pvtu, "w") as out:
        out.write(f"""<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian" header_type="UInt32">
  <PUnstructuredGrid GhostLevel="0">
    <PPointData Scalars="speed">
{arrays}
    </PPointData>
    <PCellData>
      <PDataArray type="Int64" IdType="1" Name="vtkOriginalCellIds"/>
    </PCellData>
    <PPoints>
      <PDataArray type="Float64" Name="Points" NumberOfComponents="3"/>
    </PPoints>
    <Piece Source="piece0.vtu"/>
    <Piece Source="piece1.vtu"/>
  </PUnstructuredGrid>
</VTKFile>
""")
    return pvtu
