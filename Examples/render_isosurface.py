#!/usr/bin/env python3
"""Render the exact isosurface of a quadratic tetrahedral mesh to a PNG (VTK Python pipeline).

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/render_isosurface.py \
      Data/cube27.vtu --iso 0.8 --size 512 512 --view 3 2.2 4.1 --out cube27.png

Without --view the filter's default camera looks down -z at the whole mesh. Optional: colour by a
second point array (--color-by, --color-range, --color-map), one opacity per iso-value
(--opacity), clipping planes (--clip, repeatable) and caps (--cap).
"""
import argparse
import math
import sys

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import vtkDirectSurfaceRayCaster


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", help="a .vtu file of VTK_QUADRATIC_TETRA cells")
    parser.add_argument("--array", help="point array to render (default: active scalars)")
    parser.add_argument("--iso", type=float, nargs="+", required=True, help="iso-value(s)")
    parser.add_argument("--size", type=int, nargs=2, default=[512, 512], metavar=("W", "H"))
    parser.add_argument("--view", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="look at the mesh from this direction (the whole mesh in view)")
    parser.add_argument("--zoom", type=float, default=1.0,
                        help="with --view: magnify by this factor (narrower view angle)")
    parser.add_argument("--out", default="isosurface.png", help="output PNG")
    parser.add_argument("--color-by", metavar="ARRAY", help="colour by this point array (magnitude)")
    parser.add_argument("--color-range", type=float, nargs=2, metavar=("LO", "HI"),
                        help="values spread over the colour map (default: the array's range)")
    parser.add_argument("--color-map", choices=["cool-to-warm", "rainbow", "grayscale", "black-body"],
                        default="cool-to-warm")
    parser.add_argument("--opacity", type=float, nargs="+", help="opacity per iso-value")
    parser.add_argument("--clip", type=float, nargs=6, action="append", default=[],
                        metavar=("X", "Y", "Z", "NX", "NY", "NZ"),
                        help="clipping plane through (X, Y, Z) keeping the side NX NY NZ points to")
    parser.add_argument("--cap", choices=["below", "above"],
                        help="cap the cut where the field is below/above the iso-value")
    args = parser.parse_args()

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.mesh)
    reader.Update()

    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputConnection(reader.GetOutputPort())
    if args.array:
        caster.SetInputArrayToProcess(0, 0, 0, 0, args.array)  # 0 = FIELD_ASSOCIATION_POINTS
    for i, value in enumerate(args.iso):
        caster.SetValue(i, value)
    caster.SetImageSize(*args.size)
    if args.color_by:
        caster.ColorByArrayOn()
        caster.SetInputArrayToProcess(1, 0, 0, 0, args.color_by)
        if args.color_range:
            caster.SetColorRange(*args.color_range)
    caster.SetColorMap(["cool-to-warm", "rainbow", "grayscale", "black-body"].index(args.color_map))
    for i, opacity in enumerate(args.opacity or []):
        caster.SetIsoValueOpacity(i, opacity)
    for x, y, z, nx, ny, nz in args.clip:
        plane = vtkPlane()
        plane.SetOrigin(x, y, z)
        plane.SetNormal(nx, ny, nz)
        caster.AddClippingPlane(plane)
    if args.cap:
        caster.SetCapping(1 if args.cap == "below" else 2)
    if args.view:
        # Fit the mesh's bounding sphere in the 30 degree view angle, as ResetCamera does.
        bounds = reader.GetOutput().GetBounds()
        centre = [(bounds[2 * k] + bounds[2 * k + 1]) / 2 for k in range(3)]
        radius = reader.GetOutput().GetLength() / 2
        norm = math.sqrt(sum(v * v for v in args.view))
        distance = radius / math.sin(math.radians(15))
        camera = vtkCamera()
        camera.SetFocalPoint(*centre)
        camera.SetPosition(*[centre[k] + distance * args.view[k] / norm for k in range(3)])
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(2 * math.degrees(math.atan(math.tan(math.radians(15)) / args.zoom)))
        caster.SetCamera(camera)
    errors = []
    caster.AddObserver(vtkCommand.ErrorEvent, lambda obj, event: errors.append(event))
    caster.Update()
    if errors or caster.GetOutput().GetNumberOfPoints() == 0:
        sys.exit("rendering failed (see the error above)")

    writer = vtkPNGWriter()
    writer.SetFileName(args.out)
    writer.SetInputConnection(caster.GetOutputPort())
    writer.Write()
    image = caster.GetOutput()
    depth = image.GetPointData().GetArray("Depth")
    covered = sum(1 for p in range(depth.GetNumberOfTuples()) if depth.GetValue(p) != float("inf"))
    print(f"wrote {args.out}: {args.size[0]}x{args.size[1]}, {covered} pixels on the surface, "
          f"{caster.GetNumberOfRenderedCells()} cells")


if __name__ == "__main__":
    main()
