"""The pip route with PyVista: the exact isosurface speed = 0.25 of the expansion flow, coloured by
pressure, with PyVista's outline of the mesh, in an interactive window or saved.

    pip install ".[pyvista]"          # from a clone; see docs/pip-and-pyvista.md
    python Examples/pyvista_isosurface.py [Data/expansion_flow.vtu] [--save picture.png]
"""
import argparse

import pyvista as pv

from tetdsr.pyvista import add_isosurface

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("mesh", nargs="?", default="Data/expansion_flow.vtu")
parser.add_argument("--save", help="write a screenshot instead of opening a window")
args = parser.parse_args()

flow = pv.read(args.mesh)
plotter = pv.Plotter(off_screen=bool(args.save), window_size=(960, 540))
plotter.set_background("white")
plotter.add_mesh(flow.outline(), color="black")
surface = add_isosurface(plotter, flow, 0.25, "speed", color_by="pressure", cmap="coolwarm",
                         specular=0.3)
plotter.camera_position = [(-3.2, -5.8, 4.4), (3.6, 0.0, 0.0), (0.0, 0.0, 1.0)]
if args.save:
    plotter.screenshot(args.save)
else:
    plotter.show()  # rotate with the mouse: re-cast coarse while dragging, full when released
