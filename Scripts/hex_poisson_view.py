#!/usr/bin/env python3
"""The iso-value and camera of the hexahedral Poisson dataset's pictures: vtkContourFilter's and
TetDSR's.

Scripts/make_hex_poisson.py chooses its exact solution around ISO_VALUE and calls this file for
the picture; a TetDSR picture of Data/hex_poisson.vtu meant to be compared with it should import
ISO_VALUE, IMAGE_SIZE and set_camera from here. Needs an X server (ParaView's VTK has no
off-screen GL of its own):

  xvfb-run -a /usr/bin/python3 Scripts/hex_poisson_view.py Data/hex_poisson.vtu \
      docs/images/hex_poisson_contour.png
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Scripts/hex_poisson_view.py \
      --tetdsr Data/hex_poisson.vtu docs/images/hex_poisson_tetdsr.png

(TetDSR's picture needs no X server: the filter ray casts on the CPU. It needs a TetDSR build
that handles VTK_QUADRATIC_HEXAHEDRON cells.)

The contour picture prints the contour's triangles and connected pieces, and the number of
pieces of the exact level set (make_hex_poisson.exact_pieces: one per bump whose peak exceeds
ISO_VALUE, checked on a grid).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import views  # noqa: E402

# The level of the point array "u" whose isosurface the pictures show.
ISO_VALUE = 0.5
IMAGE_SIZE = (600, 600)
# The part (a quarter of a thick cylindrical shell, radii 0.5 to 1.5, 0 <= z <= 1.1) seen from
# outside its outer wall along the bisector x = y, 50 degrees above the x-y plane, 4.7 away from
# the focal point: the whole part is in view (the outer wall's ends near the picture's sides) and
# the four bumps' pieces of the level set lie apart on the screen (bump 3's, missed by
# vtkContourFilter, would be at the left, near the outer wall; bump 2's the small one at right).
CAMERA = {"position": (2.76, 2.76, 3.95), "focal_point": (0.62, 0.62, 0.35),
          "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}
SURFACE_COLOR = (0.85, 0.45, 0.2)


def set_camera(camera):
    """Puts CAMERA on a vtkCamera (clipping range left to the renderer)."""
    views.place_camera(camera, CAMERA)


def render_contour(vtu_path, png_path):
    """vtkContourFilter's isosurface u = ISO_VALUE of the file, flat shaded with its triangles'
    edges drawn, inside the faint edges of the mesh's boundary faces, written as a PNG; returns
    the triangle count and the number of connected pieces, and the exact level set's (a
    sentence)."""
    reader = views.read(vtu_path)
    surface, regions = views.contour(reader.GetOutputPort(), "u", ISO_VALUE)
    views.write_picture([views.triangles_actor(surface.GetOutputPort(), SURFACE_COLOR),
                         views.mesh_edges_actor(reader.GetOutputPort(), 0.35)],
                        set_camera, IMAGE_SIZE, png_path)
    exact = exact_piece_count()
    return (f"{surface.GetOutput().GetNumberOfCells()} triangles in {regions} connected pieces; "
            f"the exact level set has "
            f"{exact if exact is not None else '(scipy missing: not counted)'} pieces")


def render_tetdsr(vtu_path, png_path):
    """TetDSR's exact isosurface u = ISO_VALUE of the file (views.tetdsr_picture)."""
    return views.tetdsr_picture(vtu_path, png_path, "u", ISO_VALUE, IMAGE_SIZE, CAMERA,
                                SURFACE_COLOR)


def exact_piece_count():
    """The number of pieces of the exact level set, from make_hex_poisson.py's exact solution
    (needs only numpy and scipy, which Debian's python3 has with python3-scipy; None without)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    try:
        from make_hex_poisson import exact_pieces
    except ImportError:
        return None
    return len(exact_pieces())


if __name__ == "__main__":
    views.command_line(render_contour, render_tetdsr, f"u = {ISO_VALUE}")
