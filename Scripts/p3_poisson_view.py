#!/usr/bin/env python3
"""The iso-value and camera of the P3 Poisson dataset's pictures: vtkContourFilter's and TetDSR's.

Scripts/make_p3_poisson.py chooses its exact solution around ISO_VALUE and calls this file for
the picture; a TetDSR picture of Data/p3_poisson.vtu meant to be compared with it should import
ISO_VALUE, IMAGE_SIZE and set_camera from here. Needs an X server (ParaView's VTK has no
off-screen GL of its own):

  xvfb-run -a /usr/bin/python3 Scripts/p3_poisson_view.py Data/p3_poisson.vtu \
      docs/images/p3_poisson_contour.png
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Scripts/p3_poisson_view.py \
      --tetdsr Data/p3_poisson.vtu docs/images/p3_poisson_tetdsr.png

(TetDSR's picture needs no X server: the filter ray casts on the CPU.)
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import views  # noqa: E402

# The level of the point array "u" whose isosurface the pictures show.
ISO_VALUE = 0.5
IMAGE_SIZE = (600, 600)
# Looking down (60 degrees above the x-y plane) on the five bumps of make_p3_poisson.py, from
# where their pieces of the level set lie furthest apart on the screen; the view takes in all of
# them (the ball itself, radius 1, reaches beyond it).
CAMERA = {"position": (-0.7, 1.4, 2.8), "focal_point": (0.1, 0.0, 0.0),
          "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}
SURFACE_COLOR = (0.85, 0.45, 0.2)


def set_camera(camera):
    """Puts CAMERA on a vtkCamera (clipping range left to the renderer)."""
    views.place_camera(camera, CAMERA)


def render_contour(vtu_path, png_path):
    """vtkContourFilter's isosurface u = ISO_VALUE of the file, flat shaded with its triangles'
    edges drawn, written as a PNG; returns the triangle count (a sentence)."""
    reader = views.read(vtu_path)
    surface, _ = views.contour(reader.GetOutputPort(), "u", ISO_VALUE, clean=False)
    views.write_picture([views.triangles_actor(surface.GetOutputPort(), SURFACE_COLOR)],
                        set_camera, IMAGE_SIZE, png_path)
    return f"{surface.GetOutput().GetNumberOfCells()} triangles"


def render_tetdsr(vtu_path, png_path):
    """TetDSR's exact isosurface u = ISO_VALUE of the file (views.tetdsr_picture)."""
    return views.tetdsr_picture(vtu_path, png_path, "u", ISO_VALUE, IMAGE_SIZE, CAMERA,
                                SURFACE_COLOR)


if __name__ == "__main__":
    views.command_line(render_contour, render_tetdsr, f"u = {ISO_VALUE}")
