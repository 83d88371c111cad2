"""TetDSR: exact isosurfaces of higher-order finite-element fields by ray casting (the pip build).

It reads tetrahedra (VTK_TETRA, VTK_QUADRATIC_TETRA, VTK_LAGRANGE_TETRAHEDRON,
VTK_BEZIER_TETRAHEDRON), hexahedra (VTK_HEXAHEDRON, VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON,
VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON,
VTK_BEZIER_HEXAHEDRON), wedges (VTK_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE,
VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE) and pyramids (VTK_PYRAMID,
VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID); Lagrange and Bezier cells of orders 1 to 4.

`tetdsr._core` is the VTK-free core. The VTK faces are imported on first use, so that
`import tetdsr` needs no VTK:

- `tetdsr.vtkDirectSurfaceRayCaster`: the filter (a VTKPythonAlgorithmBase), with pip's `vtk`
  (>= 9.3) or ParaView's own VTK;
- `tetdsr.vtkDirectSurfaceContour`: the exact isosurface as data (a certified, watertight
  vtkPolyData with its area, volume and array integrals), the same way;
- `tetdsr.pyvista.add_isosurface(plotter, grid, value, ...)`: the isosurface in a PyVista plotter;
  `tetdsr.pyvista.exact_contour(grid, isosurfaces, ...)`: the exact surface as a pyvista.PolyData;
- the ParaView plugin is the file `paraview_plugin.py` beside this one (`plugin_path()`;
  `load_paraview_plugin()` loads it in pvpython).
"""
import os

from . import _core  # noqa: F401

__all__ = ["vtkDirectSurfaceRayCaster", "vtkDirectSurfaceContour", "plugin_path",
           "load_paraview_plugin"]


def plugin_path():
    """The ParaView Python plugin file, for Tools > Manage Plugins or LoadPlugin(...)."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_plugin.py")


def load_paraview_plugin(ns=None):
    """Loads the ParaView Python plugin into this pvpython / pvbatch session (the filter then is
    `DirectSurfaceRayCastPython` in paraview.simple, in `ns` if given, e.g. globals()).

    ParaView 5.10 and 5.11's plugin loader (paraview.detail.pythonalgorithm) imports
    inspect.getargspec, which Python 3.11 removed: where it is missing it is supplied first from
    inspect.getfullargspec (the loader reads only its `args`). Debian 12's ParaView 5.11 needs it.
    """
    import inspect
    if not hasattr(inspect, "getargspec"):
        inspect.getargspec = inspect.getfullargspec
    from paraview.simple import LoadPlugin
    return LoadPlugin(plugin_path(), remote=False, ns=ns)


def __getattr__(name):
    # PEP 562: the filters import vtkmodules, so only when asked for.
    if name == "vtkDirectSurfaceRayCaster":
        from .filter import vtkDirectSurfaceRayCaster
        return vtkDirectSurfaceRayCaster
    if name == "vtkDirectSurfaceContour":
        from .contour import vtkDirectSurfaceContour
        return vtkDirectSurfaceContour
    raise AttributeError(f"module 'tetdsr' has no attribute {name!r}")
