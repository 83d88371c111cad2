"""The ParaView XML documents every property and its defaults equal the C++ constructor's.

Usage (with /usr/bin/python3 and the built tetdsr package): test_plugin_xml.py <xml file>
(Plugin/DirectSurfaceRayCaster.xml or Plugin/DirectSurfaceContour.xml: the filter is told by the
proxy's class).
"""
import sys
import unittest
import xml.etree.ElementTree as ElementTree

from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import vtkDirectSurfaceContour, vtkDirectSurfaceRayCaster

XML = sys.argv.pop(1)

# Per proxy class: its label, the C++ filter whose defaults the XML's must equal, and how many
# defaults at least are compared (so that a renamed command cannot skip them silently).
FILTERS = {"vtkPVDirectSurfaceRayCaster": ("Direct Surface Ray Cast", vtkDirectSurfaceRayCaster, 19),
           "vtkDirectSurfaceContour": ("Exact Isosurface (TetDSR)", vtkDirectSurfaceContour, 5)}


class PluginXml(unittest.TestCase):
    def setUp(self):
        self.proxy = ElementTree.parse(XML).getroot().find("ProxyGroup/SourceProxy")
        self.properties = [p for p in self.proxy if p.get("name") and p.tag.endswith("Property")]
        self.label, self.filter_class, self.least_defaults = FILTERS[self.proxy.get("class")]

    def test_label_and_class(self):
        self.assertEqual(self.proxy.get("label"), self.label)

    def test_every_property_is_documented(self):
        self.assertGreater(len(self.properties), 5)
        for prop in self.properties:
            doc = prop.find("Documentation")
            self.assertTrue(doc is not None and doc.text and doc.text.strip(),
                            f"property {prop.get('name')} has no documentation")

    def test_domains(self):
        by_name = {p.get("name"): p for p in self.properties}
        field = by_name.get("SelectInputScalars", by_name.get("ContourBy"))
        self.assertIsNotNone(field.find("ArrayListDomain"))
        self.assertIsNotNone(by_name["ContourValues"].find("ArrayRangeDomain"))

    def test_defaults_equal_the_constructor(self):
        caster = self.filter_class()
        camera = vtkCamera()
        # The plugin's camera properties edit a vtkCamera: their defaults are vtkCamera's, and
        # FitCameraToMesh on means "no camera set", the C++ default.
        camera_getters = {"SetCameraPosition": camera.GetPosition,
                          "SetCameraFocalPoint": camera.GetFocalPoint,
                          "SetCameraViewUp": camera.GetViewUp,
                          "SetCameraViewAngle": camera.GetViewAngle,
                          "SetCameraParallelProjection": camera.GetParallelProjection,
                          "SetCameraParallelScale": camera.GetParallelScale,
                          "SetFitCameraToMesh": lambda: int(caster.GetCamera() is None),
                          # The interactive clip plane is off by default: no clipping planes,
                          # the C++ default.
                          "SetClipWithPlane": lambda: int(caster.GetClippingPlanes() is not None),
                          "SetValue": lambda: [caster.GetValue(i)
                                               for i in range(caster.GetNumberOfContours())]}
        checked = 0
        for prop in self.properties:
            default = prop.get("default_values")
            command = prop.get("command")
            # SetInputArrayToProcess's default is the array index, not a filter setting.
            if default is None or default == "none" or command == "SetInputArrayToProcess":
                continue
            getter = camera_getters.get(command) or getattr(caster, "G" + command[1:])
            actual = getter()
            actual = list(actual) if isinstance(actual, (tuple, list)) else [actual]
            expected = [float(v) for v in default.split()]
            self.assertEqual([float(a) for a in actual], expected,
                             f"{prop.get('name')}: XML default {expected}, C++ default {actual}")
            checked += 1
        self.assertGreaterEqual(checked, self.least_defaults)
        self.assertEqual(caster.GetNumberOfContours(), 1, "one iso-value by default, as in the XML")


if __name__ == "__main__":
    unittest.main(verbosity=2)
