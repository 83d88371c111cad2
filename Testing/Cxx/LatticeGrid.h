// The core tests' lattice meshes (Testing/Core/LatticeMesh.h) as vtkUnstructuredGrids.
#ifndef LatticeGrid_h
#define LatticeGrid_h

#include "LatticeMesh.h"

#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

namespace tetdsr_test
{
/// VTK_QUADRATIC_TETRA cells on double points; the mesh's values become the active scalars "f".
inline vtkSmartPointer<vtkUnstructuredGrid> ToGrid(const LatticeMesh& mesh)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (std::size_t p = 0; p < mesh.points.size() / 3; ++p)
  {
    points->InsertNextPoint(mesh.points.data() + 3 * p);
  }
  grid->SetPoints(points);
  for (std::size_t c = 0; c < mesh.cellNodes.size() / 10; ++c)
  {
    grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, mesh.cellNodes.data() + 10 * c);
  }
  vtkNew<vtkDoubleArray> values;
  values->SetName("f");
  for (double v : mesh.values)
  {
    values->InsertNextValue(v);
  }
  grid->GetPointData()->SetScalars(values);
  return grid;
}
}

#endif
