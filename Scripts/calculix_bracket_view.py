#!/usr/bin/env python3
"""The pictures of the CalculiX bracket (Data/calculix_bracket.vtu: 1,512 curved C3D20R
hexahedra): vtkContourFilter's and TetDSR's isosurface of the von Mises stress at ISO_VALUE, with
the same camera, each inside the faint edges of the part's boundary. Needs an X server (ParaView's
VTK has no off-screen GL of its own) and a TetDSR build:

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
      Scripts/calculix_bracket_view.py Data/calculix_bracket.vtu docs/images/calculix_bracket

writes <prefix>_contour.png and <prefix>_tetdsr.png and prints what each shows.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import views  # noqa: E402
from vtkmodules.vtkRenderingCore import vtkActor  # noqa: E402
from tetdsr import vtkDirectSurfaceMapper  # noqa: E402

ARRAY = "S_Mises"
ISO_VALUE = 20.0  # MPa: the arm's low-stress core, the upper leg's, and a pocket at the bend
IMAGE_SIZE = (800, 600)
SURFACE_COLOR = (0.85, 0.45, 0.2)


def set_camera(camera, bounds):
    """Looking at the bracket from the side of its open bend, a little above."""
    b = np.array(bounds)
    lo, hi = b[0::2], b[1::2]
    centre = 0.5 * (lo + hi)
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + np.array([0.75, -0.9, 0.6]) * np.linalg.norm(hi - lo)))
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetViewAngle(30.0)


def render(reader, surface_actor, png_path):
    views.write_picture([surface_actor, views.mesh_edges_actor(reader.GetOutputPort(), 0.3)],
                        lambda camera: set_camera(camera, reader.GetOutput().GetBounds()),
                        IMAGE_SIZE, png_path)


def main(vtu_path, prefix):
    reader = views.read(vtu_path, update=True)
    surface, pieces = views.contour(reader.GetOutputPort(), ARRAY, ISO_VALUE)
    render(reader, views.triangles_actor(surface.GetOutputPort(), SURFACE_COLOR),
           prefix + "_contour.png")
    print(f"vtkContourFilter, {ARRAY} = {ISO_VALUE:g}: {surface.GetOutput().GetNumberOfCells()} "
          f"triangles, {pieces} pieces")

    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetInputArrayToProcess(0, 0, 0, 0, ARRAY)
    mapper.SetValue(0, ISO_VALUE)
    mapper.ScalarVisibilityOff()  # the actor's colour, as the contour picture's
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*SURFACE_COLOR)
    render(reader, actor, prefix + "_tetdsr.png")
    print(f"TetDSR, {ARRAY} = {ISO_VALUE:g}: {mapper.GetNumberOfRenderedCells()} cells rendered")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
