#!/usr/bin/env python3
"""vtkContourFilter (rendered by VTK's OpenGL renderer) beside TetDSR, same camera, on the three
bundled meshes; writes one PNG. Needs an X display (run under xvfb-run -a).

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \
      Examples/compare_with_contour.py Data Examples/images/comparison.png
"""
import os
import sys

from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkImageActor, vtkPolyDataMapper,
                                         vtkRenderWindow, vtkRenderer, vtkTextActor,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL backend)

from tetdsr import vtkDirectSurfaceRayCaster

PANEL = 360


def scene(data_dir, name, array, iso, offset):
    """Camera at focal point + offset; the focal point is the jet in the flow, the sphere's
    centre where the mesh records one, else the mesh's centre."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(data_dir, name))
    reader.Update()
    mesh = reader.GetOutput()
    sphere_centre = mesh.GetFieldData().GetArray("SphereCentre")
    if name == "expansion_flow.vtu":
        focal = [5.6, 0.0, 0.0]  # the jet, from the inlet duct into the expansion
    elif sphere_centre:
        focal = [sphere_centre.GetValue(k) for k in range(3)]
    else:
        bounds = mesh.GetBounds()
        focal = [(bounds[2 * k] + bounds[2 * k + 1]) / 2 for k in range(3)]
    camera = vtkCamera()
    camera.SetFocalPoint(*focal)
    camera.SetPosition(*[focal[k] + offset[k] for k in range(3)])
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    contour = vtkContourFilter()
    contour.SetInputConnection(reader.GetOutputPort())
    contour.SetInputArrayToProcess(0, 0, 0, 0, array)  # 0 = FIELD_ASSOCIATION_POINTS
    contour.SetValue(0, iso)
    contour.Update()
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputConnection(reader.GetOutputPort())
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    caster.SetValue(0, iso)
    caster.SetCamera(camera)
    caster.SetImageSize(PANEL, PANEL)
    caster.Update()
    return camera, contour, caster


def label(renderer, text):
    actor = vtkTextActor()
    actor.SetInput(text)
    actor.GetTextProperty().SetFontSize(15)
    actor.SetPosition(8, 8)
    renderer.AddActor2D(actor)


def main(data_dir, out):
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    rows = [("expansion_flow.vtu", "speed", 0.25, (2.2, 3.5, 4.4), "expansion flow, speed = 0.25"),
            ("cube27.vtu", "distance", 0.8, (2.4, 1.7, 3.4), "27-node cube, |x| = 0.8"),
            ("sphere_in_cell.vtu", "sphere", 0.0, (0.9, 0.6, 1.2), "sphere inside one cell")]
    window.SetSize(2 * PANEL, len(rows) * PANEL)
    for row, (name, array, iso, offset, title) in enumerate(rows):
        camera, contour, caster = scene(data_dir, name, array, iso, offset)
        y0, y1 = 1.0 - (row + 1) / len(rows), 1.0 - row / len(rows)
        # Left: the linear contour, rendered by VTK with the same camera.
        left = vtkRenderer()
        left.SetViewport(0.0, y0, 0.5, y1)
        left.SetActiveCamera(camera)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(contour.GetOutputPort())
        mapper.ScalarVisibilityOff()
        actor = vtkActor()
        actor.SetMapper(mapper)
        left.AddActor(actor)
        triangles = contour.GetOutput().GetNumberOfCells()
        label(left, f"vtkContourFilter: {triangles} triangles\n{title}")
        camera.SetClippingRange(0.01, 100)
        left.ResetCameraClippingRange()
        window.AddRenderer(left)
        # Right: TetDSR's image, shown pixel for pixel.
        right = vtkRenderer()
        right.SetViewport(0.5, y0, 1.0, y1)
        image = vtkImageActor()
        image.GetMapper().SetInputConnection(caster.GetOutputPort())
        right.AddActor(image)
        right.ResetCamera()
        right.GetActiveCamera().ParallelProjectionOn()
        right.GetActiveCamera().SetParallelScale(PANEL / 2)
        label(right, f"TetDSR (exact quadratic)\n{title}")
        window.AddRenderer(right)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtkPNGWriter()
    writer.SetFileName(out)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print("wrote", out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
