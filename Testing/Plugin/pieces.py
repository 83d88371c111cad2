"""Meshes cut into pieces for the distributed tests, one piece per rank, as a .pvtu naming them
(each rank reads its own; RedistributeDataSet cannot move these cells here). The pieces are
written inline (this Debian's expat cannot read VTK's appended XML data).

make_pieces: the expansion flow's piece0.vtu, piece1.vtu (the cells on either side of the median
of the cells' y centroid: the cut runs along the whole jet, through the surface) and
expansion_flow.pvtu. write_pieces: any grid, cut by any per-cell piece number."""
import os

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkFiltersCore import vtkExtractCells
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter


def write_pieces(grid, piece_of_cell, work_dir, stem):
    """Writes the cells of `grid` whose entry of `piece_of_cell` is k to <stem>k.vtu (k = 0, 1,
    ...; each carries vtkOriginalCellIds) and <stem>.pvtu naming them in order, into work_dir;
    returns the .pvtu's path. The grid's point data must have active scalars."""
    sources = []
    for piece in range(int(np.max(piece_of_cell)) + 1):
        cell_list = vtkIdList()
        for cell in np.nonzero(piece_of_cell == piece)[0]:
            cell_list.InsertNextId(int(cell))
        extract = vtkExtractCells()
        extract.SetInputData(grid)
        extract.SetCellList(cell_list)
        writer = vtkXMLUnstructuredGridWriter()
        sources.append(f"{stem}{piece}.vtu")
        writer.SetFileName(os.path.join(work_dir, sources[-1]))
        writer.SetDataModeToBinary()
        writer.SetInputConnection(extract.GetOutputPort())
        writer.Write()
    point_data = grid.GetPointData()
    arrays = "\n".join(
        f'      <PDataArray type="Float64" Name="{point_data.GetArrayName(k)}" '
        f'NumberOfComponents="{point_data.GetArray(k).GetNumberOfComponents()}"/>'
        for k in range(point_data.GetNumberOfArrays()))
    pieces = "\n".join(f'    <Piece Source="{source}"/>' for source in sources)
    pvtu = os.path.join(work_dir, f"{stem}.pvtu")
    with open(pvtu, "w") as out:
        out.write(f"""<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian" header_type="UInt32">
  <PUnstructuredGrid GhostLevel="0">
    <PPointData Scalars="{point_data.GetScalars().GetName()}">
{arrays}
    </PPointData>
    <PCellData>
      <PDataArray type="Int64" IdType="1" Name="vtkOriginalCellIds"/>
    </PCellData>
    <PPoints>
      <PDataArray type="Float64" Name="Points" NumberOfComponents="3"/>
    </PPoints>
{pieces}
  </PUnstructuredGrid>
</VTKFile>
""")
    return pvtu


def make_pieces(data_dir, work_dir):
    """Writes the expansion flow's pieces and expansion_flow.pvtu into work_dir; returns the
    .pvtu's path."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(data_dir, "expansion_flow.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    ids = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)[:, :4]
    centroid_y = points[ids, 1].mean(axis=1)
    pvtu = write_pieces(grid, (centroid_y >= np.median(centroid_y)).astype(int), work_dir, "piece")
    os.replace(pvtu, os.path.join(work_dir, "expansion_flow.pvtu"))
    return os.path.join(work_dir, "expansion_flow.pvtu")
