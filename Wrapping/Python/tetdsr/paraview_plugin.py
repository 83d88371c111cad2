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
"""
from paraview.util.vtkAlgorithm import smdomain, smhint, smproperty, smproxy
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import _core
from tetdsr.contour import vtkDirectSurfaceContour
from tetdsr.filter import vtkDirectSurfaceRayCaster


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

    @smproperty.xml("""
      <StringVectorProperty name="ContourBy" label="Contour By" command="SetInputArrayToProcess"
                            number_of_elements="5" element_types="0 0 0 0 2" animateable="0">
        <ArrayListDomain name="array_list" attribute_type="Scalars" input_domain_name="inputs_array">
          <RequiredProperties><Property name="Input" function="Input"/></RequiredProperties>
        </ArrayListDomain>
        <Documentation>The point array whose isosurfaces are rendered.</Documentation>
      </StringVectorProperty>""")
    def SetInputArrayToProcess(self, *args):
        return vtkDirectSurfaceRayCaster.SetInputArrayToProcess(self, *args)

    @smproperty.xml("""
      <DoubleVectorProperty name="Isosurfaces" label="Isosurfaces" command="SetValue"
                            number_of_elements="1" default_values="0" use_index="1"
                            repeat_command="1" number_of_elements_per_command="1"
                            set_number_command="SetNumberOfContours">
        <ArrayRangeDomain name="scalar_range" default_mode="mid">
          <RequiredProperties>
            <Property name="Input" function="Input"/>
            <Property name="ContourBy" function="ArraySelection"/>
          </RequiredProperties>
        </ArrayRangeDomain>
        <Documentation>The iso-values: a pixel shows the nearest crossing of any.</Documentation>
      </DoubleVectorProperty>""")
    def SetValue(self, i, value):
        vtkDirectSurfaceRayCaster.SetValue(self, i, value)

    @smproperty.xml("""
      <DoubleVectorProperty name="IsoValueOpacities" label="Iso-Value Opacities"
                            command="SetIsoValueOpacity" clean_command="RemoveAllIsoValueOpacities"
                            use_index="1" repeat_command="1" number_of_elements_per_command="1"
                            number_of_elements="0">
        <Documentation>Opacity of each iso-value's surface, in the Isosurfaces' order (default 1).</Documentation>
      </DoubleVectorProperty>""")
    def SetIsoValueOpacity(self, i, opacity):
        vtkDirectSurfaceRayCaster.SetIsoValueOpacity(self, i, opacity)

    @smproperty.intvector(name="ImageSize", label="Image Size", default_values=[512, 512])
    @smdomain.intrange(min=1, max=8192)
    def SetImageSize(self, width, height):
        vtkDirectSurfaceRayCaster.SetImageSize(self, width, height)

    @smproperty.intvector(name="FitCameraToMesh", label="Fit Camera To Mesh", default_values=1)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetFitCameraToMesh(self, on):
        self._fit_camera = bool(on)
        self._update_camera()

    @smproperty.doublevector(name="CameraPosition", label="Camera Position", default_values=[0.0, 0.0, 1.0])
    def SetCameraPosition(self, x, y, z):
        self._plugin_camera.SetPosition(x, y, z)
        self._update_camera()

    @smproperty.doublevector(name="CameraFocalPoint", label="Camera Focal Point", default_values=[0.0, 0.0, 0.0])
    def SetCameraFocalPoint(self, x, y, z):
        self._plugin_camera.SetFocalPoint(x, y, z)
        self._update_camera()

    @smproperty.doublevector(name="CameraViewUp", label="Camera View Up", default_values=[0.0, 1.0, 0.0])
    def SetCameraViewUp(self, x, y, z):
        self._plugin_camera.SetViewUp(x, y, z)
        self._update_camera()

    @smproperty.doublevector(name="CameraViewAngle", label="Camera View Angle", default_values=30.0)
    @smdomain.doublerange(min=0.01, max=179.0)
    def SetCameraViewAngle(self, angle):
        self._plugin_camera.SetViewAngle(angle)
        self._update_camera()

    @smproperty.intvector(name="CameraParallelProjection", label="Camera Parallel Projection", default_values=0)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetCameraParallelProjection(self, on):
        self._plugin_camera.SetParallelProjection(on)
        self._update_camera()

    @smproperty.doublevector(name="CameraParallelScale", label="Camera Parallel Scale", default_values=1.0)
    def SetCameraParallelScale(self, scale):
        self._plugin_camera.SetParallelScale(scale)
        self._update_camera()

    @smproperty.xml("""
      <DoubleVectorProperty name="SurfaceColor" label="Surface Color" command="SetSurfaceColor"
                            number_of_elements="3" default_values="1 1 1" panel_widget="color_selector">
        <DoubleRangeDomain name="range" min="0 0 0" max="1 1 1"/>
        <Documentation>Ambient and diffuse colour of the surfaces.</Documentation>
      </DoubleVectorProperty>""")
    def SetSurfaceColor(self, red, green, blue):
        vtkDirectSurfaceRayCaster.SetSurfaceColor(self, red, green, blue)

    @smproperty.doublevector(name="Ambient", default_values=0.1)
    @smdomain.doublerange(min=0.0, max=1.0)
    def SetAmbient(self, value):
        vtkDirectSurfaceRayCaster.SetAmbient(self, value)

    @smproperty.doublevector(name="Diffuse", default_values=0.7)
    @smdomain.doublerange(min=0.0, max=1.0)
    def SetDiffuse(self, value):
        vtkDirectSurfaceRayCaster.SetDiffuse(self, value)

    @smproperty.doublevector(name="Specular", default_values=0.2)
    @smdomain.doublerange(min=0.0, max=1.0)
    def SetSpecular(self, value):
        vtkDirectSurfaceRayCaster.SetSpecular(self, value)

    @smproperty.doublevector(name="SpecularPower", label="Specular Power", default_values=30.0)
    @smdomain.doublerange(min=0.0, max=128.0)
    def SetSpecularPower(self, value):
        vtkDirectSurfaceRayCaster.SetSpecularPower(self, value)

    @smproperty.xml("""
      <IntVectorProperty name="NormalMode" label="Normal Mode" command="SetNormalMode"
                         number_of_elements="1" default_values="0">
        <EnumerationDomain name="enum">
          <Entry value="0" text="Exact Gradient"/>
          <Entry value="1" text="Central Differences"/>
          <Entry value="2" text="Nodal Interpolation"/>
          <Entry value="3" text="Depth Buffer"/>
        </EnumerationDomain>
        <Documentation>How the shading normal is obtained.</Documentation>
      </IntVectorProperty>""")
    def SetNormalMode(self, mode):
        vtkDirectSurfaceRayCaster.SetNormalMode(self, mode)

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

    @smproperty.xml("""
      <IntVectorProperty name="Capping" command="SetCapping" number_of_elements="1" default_values="0">
        <EnumerationDomain name="enum">
          <Entry value="0" text="No Cap"/>
          <Entry value="1" text="Below The Largest Iso-Value"/>
          <Entry value="2" text="Above The Smallest Iso-Value"/>
        </EnumerationDomain>
        <Documentation>Which part of a cut is capped (coloured through the colour map).</Documentation>
      </IntVectorProperty>""")
    def SetCapping(self, mode):
        vtkDirectSurfaceRayCaster.SetCapping(self, mode)

    @smproperty.intvector(name="NumberOfThreads", label="Number Of Threads", default_values=0)
    @smdomain.intrange(min=0, max=256)
    def SetNumberOfThreads(self, threads):
        vtkDirectSurfaceRayCaster.SetNumberOfThreads(self, threads)


@smproxy.filter(name="TetDSRDirectSurfaceContourPython", label="Exact Isosurface (Python)")
@smhint.xml('<ShowInMenu category="Quadratic" />')
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkUnstructuredGrid"], composite_data_supported=False)
@smdomain.xml('<InputArrayDomain name="inputs_array" attribute_type="point" number_of_components="1"/>')
class DirectSurfaceContourPython(vtkDirectSurfaceContour):
    """The exact isosurface of a higher-order finite-element field (tetrahedra, hexahedra, wedges
    and pyramids of orders 1 to 4) as a certified, watertight triangle surface, with its area,
    enclosed volume and point-array integrals in the field data (the wheel's filter)."""

    @smproperty.xml("""
      <StringVectorProperty name="ContourBy" label="Contour By" command="SetInputArrayToProcess"
                            number_of_elements="5" element_types="0 0 0 0 2" animateable="0">
        <ArrayListDomain name="array_list" attribute_type="Scalars" input_domain_name="inputs_array">
          <RequiredProperties><Property name="Input" function="Input"/></RequiredProperties>
        </ArrayListDomain>
        <Documentation>The point array whose isosurfaces are extracted.</Documentation>
      </StringVectorProperty>""")
    def SetInputArrayToProcess(self, *args):
        return vtkDirectSurfaceContour.SetInputArrayToProcess(self, *args)

    @smproperty.xml("""
      <DoubleVectorProperty name="ContourValues" label="Isosurfaces" command="SetValue"
                            number_of_elements="1" default_values="0" use_index="1"
                            repeat_command="1" number_of_elements_per_command="1"
                            set_number_command="SetNumberOfContours">
        <ArrayRangeDomain name="scalar_range" default_mode="mid">
          <RequiredProperties>
            <Property name="Input" function="Input"/>
            <Property name="ContourBy" function="ArraySelection"/>
          </RequiredProperties>
        </ArrayRangeDomain>
        <Documentation>The iso-values.</Documentation>
      </DoubleVectorProperty>""")
    def SetValue(self, i, value):
        vtkDirectSurfaceContour.SetValue(self, i, value)

    @smproperty.xml(f"""
      <DoubleVectorProperty name="Tolerance" command="SetTolerance" number_of_elements="1"
                            default_values="{_core.DEFAULT_RELATIVE_TOLERANCE!r}">
        <DoubleRangeDomain name="range" min="0"/>
        <Documentation>The largest distance between the triangles and the true surface, relative
        to the diagonal of the valid cells' box (used when Absolute Tolerance is 0).</Documentation>
      </DoubleVectorProperty>""")
    def SetTolerance(self, relative):
        vtkDirectSurfaceContour.SetTolerance(self, relative)

    @smproperty.xml("""
      <DoubleVectorProperty name="AbsoluteTolerance" label="Absolute Tolerance"
                            command="SetAbsoluteTolerance" number_of_elements="1" default_values="0">
        <DoubleRangeDomain name="range" min="0"/>
        <Documentation>The same distance bound in the mesh's units; 0 uses Tolerance.</Documentation>
      </DoubleVectorProperty>""")
    def SetAbsoluteTolerance(self, tolerance):
        vtkDirectSurfaceContour.SetAbsoluteTolerance(self, tolerance)

    @smproperty.intvector(name="ComputeIntegrals", label="Compute Integrals", default_values=1)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetComputeIntegrals(self, on):
        vtkDirectSurfaceContour.SetComputeIntegrals(self, on)

    @smproperty.intvector(name="NumberOfThreads", label="Number Of Threads", default_values=0)
    @smdomain.intrange(min=0, max=256)
    def SetNumberOfThreads(self, threads):
        vtkDirectSurfaceContour.SetNumberOfThreads(self, threads)
