"""The exact isosurface among a PyVista plotter's meshes, and an exact pick (the pip wheel).

  python Examples/pyvista_among_meshes.py [out.png]

The expansion flow's jet (speed = 0.25, coloured by pressure) with a slice of the mesh (coloured
by speed) and a box through the jet: they hide one another by depth, pixel by pixel. The point
marked yellow is DirectSurface.pick at a display position: the exact hit, its cell and the point
arrays interpolated there (speed is the iso-value to rounding). Without out.png it opens a
window: right-click (or P) picks with PyVista's enable_point_picking, which gets the exact hit
too.
"""
import os
import sys

import numpy as np
import pyvista as pv

from tetdsr.pyvista import add_isosurface

HERE = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else None
pv.OFF_SCREEN = out is not None

grid = pv.read(os.path.join(HERE, "..", "Data", "expansion_flow.vtu"))
plotter = pv.Plotter(window_size=(900, 520))
plotter.set_background((0.32, 0.34, 0.43))
surface = add_isosurface(plotter, grid, 0.25, "speed", color_by="pressure", clim=(-0.027, 0.51))
plotter.add_mesh(grid.slice(normal="y", origin=(0.0, 0.05, 0.0)), scalars="speed",
                 cmap="viridis", show_scalar_bar=False)
plotter.add_mesh(pv.Box(bounds=(4.6, 5.0, -0.9, 0.9, -0.12, 0.12)), color="tan")
plotter.camera.position = (4.6, 2.6, 6.0)
plotter.camera.focal_point = (4.4, 0.0, 0.0)
plotter.camera.up = (0.0, 1.0, 0.0)
plotter.camera.view_angle = 30.0
if out:
    plotter.screenshot(return_img=True)  # (the first render: PyVista's render() waits for it)

pick = surface.pick(600, 250) if out else None
if pick is not None:
    print(f"pick at (600, 250): {pick}")
    plotter.add_points(np.array([pick.position]), color="yellow", point_size=14,
                       render_points_as_spheres=True, reset_camera=False)
    plotter.add_text(f"pick: cell {pick.cell_id}, speed = {pick.point_data['speed']:.12f}, "
                     f"pressure = {pick.point_data['pressure']:.6f}", font_size=10, color="yellow")
if out:
    plotter.screenshot(out)
    print(f"wrote {out}")
else:
    plotter.enable_point_picking(
        callback=lambda point, picker: print("picked", point, {
            picker.GetDataSet().GetPointData().GetArrayName(k):
            picker.GetDataSet().GetPointData().GetArray(k).GetTuple(picker.GetPointId())
            for k in range(picker.GetDataSet().GetPointData().GetNumberOfArrays())}),
        use_picker=True)
    plotter.show()
