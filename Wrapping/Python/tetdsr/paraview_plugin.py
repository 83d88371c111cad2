"""TetDSR's ParaView Python plugin: the wheel's vtkDirectSurfaceRayCaster and
vtkDirectSurfaceContour as ParaView filters, "Direct Surface Ray Cast (Python)" and "Exact
Isosurface (Python)" (Filters > Quadratic; the C++ plugin's "Exact Isosurface (TetDSR)" with the
same properties), for any ParaView >= 5.10 whose Python can import the
installed `tetdsr` package (it then uses ParaView's own VTK).

Load it with Tools > Manage Plugins > Load New (this file: `tetdsr.plugin_path()`), or in pvpython
with `tetdsr.load_paraview_plugin(globals())` (which also works around ParaView 5.10/5.11 on
Python >= 3.11, see there). The ray caster's output is an image whose `Colors` are RGBA: show it
with `display.MapScalars = 0`. The contour's is the exact surface as polygons, with its integrals
in the field data.

The properties of the core's settings table (ImageSize, SurfaceColor, Ambient, ..., Tolerance,
NumberOfThreads) are made from its rows (type, elements, default, range or choices), as the C++
plugin's XML is tested against them; the camera's from vtkCamera's own defaults.
"""
import re

from paraview.util.vtkAlgorithm import smdomain, smhint, smproperty, smproxy
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import _core
from tetdsr.contour import vtkDirectSurfaceContour
from tetdsr.filter import vtkDirectSurfaceRayCaster

_ROWS = {row.name: row for row in _core.SETTINGS}
_NO_BOUND = {_core.SettingType.DOUBLE: 1.7976931348623157e308, _core.SettingType.INT: 2 ** 31 - 1}


def _label(name):
    """"SpecularPower" -> "Specular Power"."""
    return re.sub(r"(?<=[a-z])(?=[A-Z])", " ", name)


def _numbers(values, row):
    return " ".join(repr(int(v)) if row.type != _core.SettingType.DOUBLE else repr(float(v))
                    for v in values)


def _domain(row):
    """The row's ParaView domain: a switch, its choices, or its range where it has one."""
    if row.type == _core.SettingType.BOOL:
        return '<BooleanDomain name="bool"/>'
    if row.choices:
        entries = "".join(f'<Entry value="{int(row.lo) + k}" text="{text}"/>'
                          for k, text in enumerate(row.choices))
        return f'<EnumerationDomain name="enum">{entries}</EnumerationDomain>'
    no_bound = _NO_BOUND[row.type]
    bounds = "".join(f' {which}="{_numbers([value] * row.components, row)}"'
                     for which, value in (("min", row.lo), ("max", row.hi))
                     if abs(value) < no_bound)
    kind = "Double" if row.type == _core.SettingType.DOUBLE else "Int"
    return f'<{kind}RangeDomain name="range"{bounds}/>' if bounds else ""


def _table_property(base, name, documentation, widget=""):
    """Set<name> of a plugin proxy, calling `base`'s, with the ParaView property of the core's
    settings table's row `name`."""
    row = _ROWS[name]
    kind = "Double" if row.type == _core.SettingType.DOUBLE else "Int"
    widget = f' panel_widget="{widget}"' if widget else ""
    xml = (f'<{kind}VectorProperty name="{name}" label="{_label(name)}" command="Set{name}" '
           f'number_of_elements="{row.components}" default_values="{_numbers(row.defaults, row)}"'
           f'{widget}>{_domain(row)}<Documentation>{documentation}</Documentation>'
           f'</{kind}VectorProperty>')

    def setter(self, *values):
        getattr(base, "Set" + name)(self, *values)

    setter.__name__ = "Set" + name
    return smproperty.xml(xml)(setter)


def _field_properties(base, values_name, field_doc, values_doc):
    """SetInputArrayToProcess and SetValue of a plugin proxy (calling `base`'s): the field chosen
    from the input's point arrays, and its iso-values (property `values_name`)."""
    @smproperty.xml(f"""
      <StringVectorProperty name="ContourBy" label="Contour By" command="SetInputArrayToProcess"
                            number_of_elements="5" element_types="0 0 0 0 2" animateable="0">
        <ArrayListDomain name="array_list" attribute_type="Scalars" input_domain_name="inputs_array">
          <RequiredProperties><Property name="Input" function="Input"/></RequiredProperties>
        </ArrayListDomain>
        <Documentation>{field_doc}</Documentation>
      </StringVectorProperty>""")
    def SetInputArrayToProcess(self, *args):
        return base.SetInputArrayToProcess(self, *args)

    @smproperty.xml(f"""
      <DoubleVectorProperty name="{values_name}" label="Isosurfaces" command="SetValue"
                            number_of_elements="1" default_values="0" use_index="1"
                            repeat_command="1" number_of_elements_per_command="1"
                            set_number_command="SetNumberOfContours">
        <ArrayRangeDomain name="scalar_range" default_mode="mid">
          <RequiredProperties>
            <Property name="Input" function="Input"/>
            <Property name="ContourBy" function="ArraySelection"/>
          </RequiredProperties>
        </ArrayRangeDomain>
        <Documentation>{values_doc}</Documentation>
      </DoubleVectorProperty>""")
    def SetValue(self, i, value):
        base.SetValue(self, i, value)

    return SetInputArrayToProcess, SetValue


def _camera_property(name, domain=""):
    """Set<name> of the ray caster's proxy: the camera's `name` (CameraPosition ->
    vtkCamera.SetPosition), with vtkCamera's default."""
    method = name[len("Camera"):]
    default = getattr(vtkCamera(), "Get" + method)()
    values = default if isinstance(default, tuple) else (default,)
    kind = "Int" if isinstance(default, int) else "Double"
    xml = (f'<{kind}VectorProperty name="{name}" label="{_label(name)}" command="Set{name}" '
           f'number_of_elements="{len(values)}" default_values="{" ".join(map(repr, values))}">'
           f'{domain}<Documentation>The camera\'s {_label(method).lower()} (used unless Fit '
           f'Camera To Mesh).</Documentation></{kind}VectorProperty>')

    def setter(self, *values):
        getattr(self._plugin_camera, "Set" + method)(*values)
        self._update_camera()

    setter.__name__ = "Set" + name
    return smproperty.xml(xml)(setter)


@smproxy.filter(name="TetDSRDirectSurfaceRayCastPython", label="Direct Surface Ray Cast (Python)")
@smhint.xml('<ShowInMenu category="Quadratic" />')
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkUnstructuredGrid"], composite_data_supported=False)
@smdomain.xml('<InputArrayDomain name="inputs_array" attribute_type="point" number_of_components="1"/>')
class DirectSurfaceRayCastPython(vtkDirectSurfaceRayCaster):
    """Ray casts the exact isosurface of a higher-order finite-element field (tetrahedra,
    hexahedra, wedges and pyramids of orders 1 to 4) into an image (the wheel's filter; camera and
    clipping planes as properties)."""

    def __init__(self):
        vtkDirectSurfaceRayCaster.__init__(self)
        self._plugin_camera = vtkCamera()
        self._fit_camera = True

    def _update_camera(self):
        self.SetCamera(None if self._fit_camera else self._plugin_camera)

    SetInputArrayToProcess, SetValue = _field_properties(
        vtkDirectSurfaceRayCaster, "Isosurfaces", "The point array whose isosurfaces are rendered.",
        "The iso-values: a pixel shows the nearest crossing of any.")

    @smproperty.xml("""
      <DoubleVectorProperty name="IsoValueOpacities" label="Iso-Value Opacities"
                            command="SetIsoValueOpacity" clean_command="RemoveAllIsoValueOpacities"
                            use_index="1" repeat_command="1" number_of_elements_per_command="1"
                            number_of_elements="0">
        <Documentation>Opacity of each iso-value's surface, in the Isosurfaces' order (default 1).</Documentation>
      </DoubleVectorProperty>""")
    def SetIsoValueOpacity(self, i, opacity):
        vtkDirectSurfaceRayCaster.SetIsoValueOpacity(self, i, opacity)

    SetImageSize = _table_property(vtkDirectSurfaceRayCaster, "ImageSize", "Width and height in pixels.")

    @smproperty.intvector(name="FitCameraToMesh", label="Fit Camera To Mesh", default_values=1)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetFitCameraToMesh(self, on):
        self._fit_camera = bool(on)
        self._update_camera()

    SetCameraPosition = _camera_property("CameraPosition")
    SetCameraFocalPoint = _camera_property("CameraFocalPoint")
    SetCameraViewUp = _camera_property("CameraViewUp")
    SetCameraViewAngle = _camera_property(
        "CameraViewAngle", '<DoubleRangeDomain name="range" min="0.01" max="179.0"/>')
    SetCameraParallelProjection = _camera_property(
        "CameraParallelProjection", '<BooleanDomain name="bool"/>')
    SetCameraParallelScale = _camera_property("CameraParallelScale")

    SetSurfaceColor = _table_property(vtkDirectSurfaceRayCaster, "SurfaceColor",
                                      "Ambient and diffuse colour of the surfaces.", "color_selector")
    SetAmbient = _table_property(vtkDirectSurfaceRayCaster, "Ambient", "Ambient coefficient.")
    SetDiffuse = _table_property(vtkDirectSurfaceRayCaster, "Diffuse", "Diffuse coefficient.")
    SetSpecular = _table_property(vtkDirectSurfaceRayCaster, "Specular", "Specular coefficient.")
    SetSpecularPower = _table_property(vtkDirectSurfaceRayCaster, "SpecularPower",
                                       "Specular exponent.")
    SetNormalMode = _table_property(vtkDirectSurfaceRayCaster, "NormalMode",
                                    "How the shading normal is obtained.")

    @smproperty.xml("""
      <DoubleVectorProperty name="ClipPlanes" label="Clip Planes" command="AddClipPlane"
                            clean_command="RemoveAllClippingPlanes" repeat_command="1"
                            number_of_elements_per_command="6" number_of_elements="0">
        <Documentation>Up to 6 planes, six numbers each: a point and a normal; each keeps the
        side its normal points to.</Documentation>
      </DoubleVectorProperty>""")
    def AddClipPlane(self, ox, oy, oz, nx, ny, nz):
        plane = vtkPlane()
        plane.SetOrigin(ox, oy, oz)
        plane.SetNormal(nx, ny, nz)
        self.AddClippingPlane(plane)

    SetCapping = _table_property(vtkDirectSurfaceRayCaster, "Capping",
                                 "Which part of a cut is capped (coloured through the colour map).")
    SetNumberOfThreads = _table_property(vtkDirectSurfaceRayCaster, "NumberOfThreads",
                                         "Threads; 0 uses all cores.")


@smproxy.filter(name="TetDSRDirectSurfaceContourPython", label="Exact Isosurface (Python)")
@smhint.xml('<ShowInMenu category="Quadratic" />')
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkUnstructuredGrid"], composite_data_supported=False)
@smdomain.xml('<InputArrayDomain name="inputs_array" attribute_type="point" number_of_components="1"/>')
class DirectSurfaceContourPython(vtkDirectSurfaceContour):
    """The exact isosurface of a higher-order finite-element field (tetrahedra, hexahedra, wedges
    and pyramids of orders 1 to 4) as a certified, watertight triangle surface, with its area,
    enclosed volume and point-array integrals in the field data (the wheel's filter)."""

    SetInputArrayToProcess, SetValue = _field_properties(
        vtkDirectSurfaceContour, "ContourValues", "The point array whose isosurfaces are extracted.",
        "The iso-values.")
    SetTolerance = _table_property(
        vtkDirectSurfaceContour, "Tolerance", "The largest distance between the triangles and the "
        "true surface, relative to the diagonal of the valid cells' box (used when Absolute "
        "Tolerance is 0).")
    SetAbsoluteTolerance = _table_property(
        vtkDirectSurfaceContour, "AbsoluteTolerance",
        "The same distance bound in the mesh's units; 0 uses Tolerance.")
    SetComputeIntegrals = _table_property(
        vtkDirectSurfaceContour, "ComputeIntegrals",
        "Compute the area, enclosed volume and point-array integrals of the curved surface.")
    SetNumberOfThreads = _table_property(vtkDirectSurfaceContour, "NumberOfThreads",
                                         "Threads; 0 uses all cores.")
