"""Times vtkContourFilter + OpenGL rendering of its triangles with whatever VTK this Python has
(run.sh uses the newest `vtk` wheel from PyPI, in a venv), on the meshes and iso-values that
tetdsr-benchmark wrote and listed. Needs an X display (xvfb-run -a).

  python vtk_wheel_contour.py <tetdsr-benchmark output .tsv> <mesh dir> <image size>
Prints TSV: n, field, contour_s, triangles, render_s, vtk_version.
"""
import csv
import os
import sys
import time

import vtk

rows, mesh_dir, size = sys.argv[1], sys.argv[2], int(sys.argv[3])
print("n\tfield\tcontour_s\ttriangles\trender_s\tvtk_version")
meshes = {}
for row in csv.DictReader(open(rows), delimiter="\t"):
    n = row["n"]
    if n not in meshes:
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(mesh_dir, f"lattice_{n}.vtu"))
        reader.Update()
        meshes = {n: reader.GetOutput()}  # keep one mesh in memory at a time
    mesh = meshes[n]
    contour = vtk.vtkContourFilter()
    contour.SetInputData(mesh)
    contour.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, row["field"])
    contour.SetValue(0, float(row["iso"]))
    start = time.perf_counter()
    contour.Update()
    contour_s = time.perf_counter() - start

    camera = vtk.vtkCamera()  # the same camera as tetdsr_benchmark.cxx
    camera.SetFocalPoint(0.5, 0.5, 0.5)
    camera.SetPosition(2.1, 1.6, 3.0)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(contour.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera)
    renderer.ResetCameraClippingRange()
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(size, size)
    window.AddRenderer(renderer)
    start = time.perf_counter()
    window.Render()
    render_s = time.perf_counter() - start
    print(f"{n}\t{row['field']}\t{contour_s:.3f}\t{contour.GetOutput().GetNumberOfCells()}\t"
          f"{render_s:.3f}\t{vtk.vtkVersion.GetVTKVersion()}", flush=True)
