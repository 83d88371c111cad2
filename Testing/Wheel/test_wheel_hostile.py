"""Hostile use of the wheel (issue 21): the reproducers of ../shared/hostile-inputs/faces/ (core_*,
wheel_*, pyvista_*) ported to the binding's current API, and what the wheel fuzzer
(Testing/Fuzz/fuzz_wheel.py) found. Cases that once crashed run in a child process, so that a
signal fails the test instead of ending pytest; each asserts the picture or the message."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))

# Shared by the child scripts: one straight quadratic tet holding f = x, and a lattice mesh.
PRELUDE = """
import os, sys
import numpy as np
sys.path.insert(0, os.path.join(%r, "..", "Python"))
from kuhn_lattice import lattice
from tetdsr import _core
EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_POINTS = np.vstack([V, [(V[a] + V[b]) / 2 for a, b in EDGES]])

def prepare(points, cells, field, types=None):
    mesh, messages = _core.PreparedMesh(), _core.Messages()
    cells = np.asarray(cells)
    ready = mesh.prepare(points, np.full(len(cells), 24, np.uint8) if types is None else types,
                         np.arange(0, cells.size + 1, 10, dtype=np.int64), cells.reshape(-1),
                         field, messages=messages)
    return mesh, ready, messages

def image(h, w, color_values=False):
    out = dict(colors=np.zeros((h, w, 4), np.uint8), depth=np.zeros((h, w)),
               normals=np.zeros((h, w, 3)), cell_ids=np.zeros((h, w), np.int64))
    if color_values:
        out["color_values"] = np.zeros((h, w))
    return out

def camera(position, focal=(0.2, 0.2, 0.2)):
    c = _core.Camera()
    c.position, c.focal_point, c.view_up = position, focal, (0, 1, 0)
    return c
""" % HERE


def run_child(body, timeout=120, prelude=""):
    """Runs PRELUDE, `prelude` and `body` in a fresh interpreter; returns (returncode, stdout,
    stderr)."""
    code = PRELUDE + prelude + textwrap.dedent(body)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr


def expect_clean_exit(body, timeout=120, prelude=""):
    code, out, err = run_child(body, timeout, prelude)
    assert code == 0, f"expected exit 0, got {code} (negative: a signal)\nstdout:\n{out}\nstderr:\n{err[-3000:]}"
    return out


def test_core_cells_edited_after_prepare():
    """core_cells_edited_after_scene.py: a node id set to 10^6 in the caller's array after
    prepare, then a render with colour values: the prepared mesh keeps the ids it validated."""
    out = expect_clean_exit("""
        cells = np.arange(10, dtype=np.int64).reshape(1, 10)
        mesh, ready, messages = prepare(TET_POINTS, cells, TET_POINTS[:, 0].copy())
        assert ready, messages.errors

        def render():
            settings = _core.RenderSettings()
            values = mesh.point_values(TET_POINTS[:, 1].copy(), "y", 1, "colour array", messages)
            settings.color_by = _core.ColorByArray(values, 0)
            settings.color_table = _core.sample_color_table(lambda v: (v, v, v), 0, 1, 0, 1)
            out = image(48, 48, True)
            renderer = _core.Renderer(mesh, [0.25], camera((2.0, 1.5, 3.0)), settings, **out)
            assert renderer.cast() == renderer.number_of_tiles
            return out

        before = render()
        cells[0, 5] = 10 ** 6  # an ordinary in-place numpy edit, after validation
        after = render()
        hits = int(np.isfinite(before["depth"]).sum())
        assert hits > 50, f"expected the plane x = 0.25 on more than 50 pixels, got {hits}"
        for name in before:
            same = np.array_equal(before[name], after[name], equal_nan=True)
            assert same, f"{name}: expected the image of the ids validated, got another"
        print("hits", hits)
    """)
    print(out)


@pytest.mark.parametrize("mode", ["EXACT_GRADIENT", "CENTRAL_DIFFERENCES", "NODAL_INTERPOLATION",
                                  "DEPTH_BUFFER"])
def test_core_depth_buffer_normals_only_in_their_mode(mode):
    """core_shade_from_depth_wrong_mode.py: shading from depth is no call of its own any more
    (Renderer.cast runs the depth-buffer pass in DEPTH_BUFFER mode only): each mode casts and
    gives unit normals on the plane x = 0.25 (normal +x)."""
    out = expect_clean_exit("""
        mesh, ready, messages = prepare(TET_POINTS, np.arange(10).reshape(1, 10), TET_POINTS[:, 0].copy())
        assert not hasattr(_core.Renderer, "shade_from_depth")
        settings = _core.RenderSettings()
        settings.normals.mode = _core.NormalMode.%s
        out = image(96, 96)
        renderer = _core.Renderer(mesh, [0.25], camera((2.0, 1.5, 3.0)), settings, **out)
        assert renderer.cast() == renderer.number_of_tiles
        hits = np.isfinite(out["depth"])
        normals = out["normals"][hits]
        # Depth-buffer normals are differences of neighbouring depths: exact on a plane inside,
        # not at its border (pixels whose neighbours miss).
        inner = np.abs(normals[:, 0] - 1.0) < 1e-6
        print("hits", hits.sum(), "exact normals", inner.sum())
        assert hits.sum() > 100, hits.sum()
        assert inner.sum() > 0.6 * hits.sum(), f"expected normals (1, 0, 0) on most hits, got {inner.sum()} of {hits.sum()}"
    """ % mode)
    print(out)


def test_core_concurrent_renderers_one_mesh():
    """core_concurrent_renderers_one_scene.py: Renderers made and cast from six Python threads
    on one PreparedMesh, each with its own iso-values: every image as the same one made alone."""
    out = expect_clean_exit("""
        import threading
        points, cells = lattice(4)
        mesh, ready, messages = prepare(points, cells, np.sum(points ** 2, axis=1))
        assert ready, messages.errors
        isos = [0.05 + 0.013 * k for k in range(0, 200, 7)]

        def depth(iso):
            out = image(6, 6)
            r = _core.Renderer(mesh, [iso], camera((2.2, 1.6, 3.0), (0, 0, 0)), _core.RenderSettings(), **out)
            assert r.cast(1) == r.number_of_tiles
            return out["depth"]

        alone = {iso: depth(iso) for iso in isos}
        wrong = []

        def worker(k):
            for it in range(60):
                iso = isos[(k * 977 + it * 31) % len(isos)]
                if not np.array_equal(depth(iso), alone[iso]):
                    wrong.append(iso)

        threads = [threading.Thread(target=worker, args=(k,)) for k in range(6)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not wrong, f"expected every threaded image as made alone, {len(wrong)} of 360 differ"
        print("360 images as made alone")
    """)
    print(out)


def test_core_threads_that_cannot_start_raise():
    """core_threads_cannot_start_abort.py: cast(threads=1024) with the address space capped
    64 MiB above current use (so that the 9th thread's 8 MiB stack cannot be mapped): a
    RuntimeError naming the thread that could not start, never an abort."""
    out = expect_clean_exit("""
        import resource
        mesh, ready, messages = prepare(TET_POINTS, np.arange(10).reshape(1, 10), TET_POINTS[:, 0].copy())
        out = image(512, 512)
        renderer = _core.Renderer(mesh, [0.25], camera((2.0, 1.5, 3.0)), _core.RenderSettings(), **out)
        vm = int(open("/proc/self/statm").read().split()[0]) * resource.getpagesize()
        resource.setrlimit(resource.RLIMIT_AS, (vm + 2 ** 26, resource.RLIM_INFINITY))
        try:
            renderer.cast(1024)
            raise SystemExit("expected a RuntimeError: 1024 threads started under a 64 MiB cap")
        except RuntimeError as error:
            print("raised:", error)
            assert "Could not start thread" in str(error) and "fewer threads" in str(error), str(error)
        resource.setrlimit(resource.RLIMIT_AS, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
        assert renderer.cast(2) == renderer.number_of_tiles  # and it casts once it can
    """)
    print(out)


FILTER_PRELUDE = """
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkRenderingCore import vtkCamera
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

def tet_grid():
    grid = vtkUnstructuredGrid()
    p = vtkPoints(); p.SetData(numpy_to_vtk(TET_POINTS, deep=1)); grid.SetPoints(p)
    cells = vtkCellArray(); cells.InsertNextCell(10, list(range(10)))
    grid.SetCells(VTK_QUADRATIC_TETRA, cells)
    for name, values in (("x", TET_POINTS[:, 0]), ("y", TET_POINTS[:, 1])):
        a = numpy_to_vtk(values.copy(), deep=1); a.SetName(name); grid.GetPointData().AddArray(a)
    return grid

def tet_caster(grid):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, "x")
    caster.SetValue(0, 0.25)
    caster.SetImageSize(64, 48)
    cam = vtkCamera(); cam.SetPosition(2.0, 1.5, 3.0); cam.SetFocalPoint(0.2, 0.2, 0.2)
    caster.SetCamera(cam)
    return caster, cam

def array(caster, name):
    return vtk_to_numpy(caster.GetOutput().GetPointData().GetArray(name)).copy()
"""


@pytest.mark.parametrize("then", ["ColorByArrayOn", "SetNormalMode(2)"])
def test_wheel_connectivity_edited_without_modified(then):
    """wheel_connectivity_edited_without_modified.py: the connectivity set to 10^12 through numpy
    after a first Update, no Modified(), then colouring on (or nodal normals): the kept mesh's
    validated ids are used (a stale but whole image), no crash."""
    change = ("caster.ColorByArrayOn(); caster.SetInputArrayToProcess(1, 0, 0, 0, 'y')"
              if then == "ColorByArrayOn" else "caster.SetNormalMode(2)")
    out = expect_clean_exit(prelude=FILTER_PRELUDE, body="""
        grid = tet_grid()
        caster, cam = tet_caster(grid)
        messages = Messages(caster)
        caster.Update()
        first = array(caster, "CellId")
        vtk_to_numpy(grid.GetCells().GetConnectivityArray())[:] = 10 ** 12   # no Modified()
        %s
        caster.Update()
        assert messages.errors == [], messages.errors
        ids = array(caster, "CellId")
        hits = int((ids == 0).sum())
        print("hits before", int((first == 0).sum()), "after", hits)
        assert hits == int((first == 0).sum()) and hits > 50, f"expected {(first == 0).sum()} hits, got {hits}"
    """ % change)
    print(out)


PYVISTA_TWO = """
import itertools
import pyvista as pv
from tetdsr.pyvista import add_isosurface
points, cells = lattice(2)
grid = pv.UnstructuredGrid(np.c_[np.full(len(cells), 10), cells].ravel(),
                           np.full(len(cells), pv.CellType.QUADRATIC_TETRA, np.uint8), points)
grid.point_data["f"] = np.sum(points ** 2, axis=1)

def shot(values_colors, **options):
    pl = pv.Plotter(off_screen=True, window_size=(128, 96))
    pl.background_color = "black"
    pl.camera.position = (2.2, 1.6, 3.0); pl.camera.focal_point = (0, 0, 0); pl.camera.up = (0, 1, 0)
    surfaces = [add_isosurface(pl, grid, value, "f", color=color, **options) for value, color in values_colors]
    img = pl.screenshot(return_img=True).astype(int)
    red = int(((img[:, :, 0] > 60) & (img[:, :, 1] < 30) & (img[:, :, 2] < 30)).sum())
    grey = int(((np.abs(img[:, :, 0] - img[:, :, 1]) < 8) & (img[:, :, 0] > 30)).sum())
    return img, red, grey, pl, surfaces
"""


def test_pyvista_two_isosurfaces_occlude_each_other():
    """pyvista_two_isosurfaces_wrong_occlusion.py: two add_isosurface calls on one plotter
    (|x|^2 = 0.5 white, then 0.2 red inside it) are cast into one image: the window shows what
    one call with both values shows (the white sphere hides the red one)."""
    out = expect_clean_exit(prelude=PYVISTA_TWO, body="""
        alone, red0, grey0, _, _ = shot([(0.5, "white")])
        both, red, grey, pl, surfaces = shot([(0.5, "white"), (0.2, "red")])
        print("white alone: red, white pixels", red0, grey0, "; white then red:", red, grey)
        assert red == 0 and grey == grey0 > 1000, f"expected 0 red and {grey0} white pixels, got {red} and {grey}"
        assert np.array_equal(alone, both), "expected the picture of the white sphere alone"
        # The outer one removed: the red one shows.
        surfaces[0].remove()
        pl.render()
        img = pl.screenshot(return_img=True).astype(int)
        red_left = int(((img[:, :, 0] > 60) & (img[:, :, 1] < 30) & (img[:, :, 2] < 30)).sum())
        print("after removing the white one: red pixels", red_left)
        assert red_left > 500, f"expected the red sphere once the white one is removed, got {red_left} red pixels"
    """)
    print(out)


# -- calls out of order and values the API once accepted silently (in this process: none of
#    these ever crashed)

def _tet_mesh_arrays(id_dtype=np.int64):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    points = np.vstack([v, [(v[a] + v[b]) / 2 for a, b in edges]])
    return dict(points=points, cell_types=np.array([24], np.uint8),
                offsets=np.array([0, 10]).astype(id_dtype), connectivity=np.arange(10).astype(id_dtype),
                field=points[:, 0].copy())


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.uint64, np.int16])
def test_core_non_integer_or_narrow_cell_ids_refused(dtype):
    """Cell ids of float64 (or another type than int32 / int64) are refused with the core's
    sentence, never truncated."""
    from tetdsr import _core
    messages = _core.Messages()
    ready = _core.PreparedMesh().prepare(**_tet_mesh_arrays(dtype), messages=messages)
    expected = ("The input's cell offsets and connectivity must be arrays of 32- or 64-bit "
                "integers with one component.")
    assert not ready and messages.errors == [expected], f"expected [{expected!r}], got {messages.errors}"


def _caster_with_messages(data):
    import scenes
    from shared_helpers import Messages
    from tetdsr import vtkDirectSurfaceRayCaster
    caster, keep, _ = scenes.sphere_in_cell(vtkDirectSurfaceRayCaster, data)
    return caster, keep, Messages(caster)


def test_filter_setters_refuse_wrong_types_and_nan(data):
    from vtkmodules.vtkCommonDataModel import vtkPlane
    from vtkmodules.vtkRenderingCore import vtkCamera
    caster, keep, messages = _caster_with_messages(data)
    before = caster.GetSurfaceColor(), caster.GetColorRange(), caster.GetLightPosition()
    for setter, args, expected in (
            ("SetCamera", (vtkPlane(),), "SetCamera takes a vtkCamera or None, got vtkPlane"),
            ("SetLookupTable", (vtkPlane(),), "SetLookupTable takes a vtkScalarsToColors or None, got vtkPlane"),
            ("SetClippingPlanes", (vtkPlane(),), "SetClippingPlanes takes a vtkPlaneCollection or None, got vtkPlane"),
            ("AddClippingPlane", ("plane",), "AddClippingPlane takes a vtkPlane, got str"),
            ("SetNormalMode", (2.7,), "SetNormalMode takes an integer, got 2.7"),
            ("SetImageSize", (64.5, 48), "SetImageSize takes an integer, got 64.5"),
            ("SetNumberOfThreads", ("4",), "SetNumberOfThreads takes an integer, got '4'"),
            ("SetAmbient", ("0.3",), "SetAmbient takes numbers, got ('0.3',)"),
            ("SetSurfaceColor", (1, "red", 0), "SetSurfaceColor takes numbers, got (1, 'red', 0)")):
        with pytest.raises(TypeError) as raised:
            getattr(caster, setter)(*args)
        assert str(raised.value) == expected, f"expected {expected!r}, got {str(raised.value)!r}"
    caster.SetSurfaceColor(float("nan"), 0, 0)
    caster.SetColorRange(0.0, float("inf"))
    caster.SetLightPosition(1, float("nan"), 0)
    caster.SetAmbient(float("nan"))
    assert messages.errors == [
        # (the core's sentence, the C++ filter's too)
        "SurfaceColor must be finite numbers, got (nan, 0, 0); it is left unchanged.",
        "ColorRange must be finite numbers, got (0, inf); it is left unchanged.",
        "LightPosition must be finite numbers, got (1, nan, 0); it is left unchanged.",
        "Ambient must be a number, got NaN."], messages.errors
    after = caster.GetSurfaceColor(), caster.GetColorRange(), caster.GetLightPosition()
    assert after == before, f"expected the settings kept {before}, got {after}"
    caster.SetNormalMode(7)
    caster.SetNumberOfThreads(-2)
    assert caster.GetNormalMode() == 3 and caster.GetNumberOfThreads() == 0
    assert messages.warnings == ["NormalMode 7 is outside [0, 3]: 3 is used.",
                                 "NumberOfThreads -2 is outside [0, 2147483647]: 0 is used."], messages.warnings
    caster.SetNormalMode(np.int64(1))  # numpy integers are integers
    assert caster.GetNormalMode() == 1
    # Iso-values: within the core's per-iso-value index range (vtkContourValues would allocate
    # them all).
    messages.errors.clear()
    caster.SetValue(10 ** 9, 0.5)
    caster.SetNumberOfContours(-1)
    caster.GenerateValues(2 ** 31 - 1, 0.0, 1.0)
    limit = 2 ** 20
    assert messages.errors == [f"SetValue: index 1000000000 is outside [0, {limit}).",
                               f"SetNumberOfContours: number -1 is outside [0, {limit}].",
                               f"GenerateValues: count 2147483647 is outside [0, {limit}]."], messages.errors
    assert caster.GetNumberOfContours() == 1, caster.GetNumberOfContours()


def test_filter_says_why_nothing_is_drawn():
    """An empty grid, an all-NaN field and an empty multiblock: an error each (the empty
    multiblock executed nothing and said nothing)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkUnstructuredGrid
    import scenes
    from shared_helpers import Messages
    from tetdsr import vtkDirectSurfaceRayCaster
    points, cells = scenes.lattice(1)
    nan_grid = scenes.grid(points, cells, {"f": np.full(len(points), np.nan)})
    empty_blocks = vtkMultiBlockDataSet()
    empty_blocks.SetNumberOfBlocks(2)
    empty_blocks.SetBlock(0, vtkUnstructuredGrid())
    for data, expected in ((vtkUnstructuredGrid(), "The input mesh is empty"),
                           (nan_grid, "all 6 input cells were skipped"),
                           (vtkMultiBlockDataSet(), "The input mesh is empty"),
                           (empty_blocks, "The input mesh is empty")):
        caster = vtkDirectSurfaceRayCaster()
        messages = Messages(caster)
        caster.SetInputDataObject(0, data)
        caster.SetValue(0, 0.5)
        caster.SetImageSize(20, 20)
        caster.Update()
        assert any(expected in e for e in messages.errors), (
            f"{type(data).__name__}: expected an error with {expected!r}, got {messages.errors}")


def test_filter_image_that_cannot_be_allocated_is_an_error(data):
    """The output's memory comes from numpy: a size beyond what the process may allocate is the
    core's error (pip VTK's SetNumberOfTuples threw std::bad_alloc through its wrapper)."""
    code, out, err = run_child("""
        import resource, scenes
        from shared_helpers import Messages
        from tetdsr import vtkDirectSurfaceRayCaster
        caster, keep, _ = scenes.sphere_in_cell(vtkDirectSurfaceRayCaster, %r)
        messages = Messages(caster)
        # Its output arrays need 1.5 GiB (44 bytes a pixel): more than allowed below, less than
        # the machine has (the core's check_image_size lets it through).
        caster.SetImageSize(6000, 6000)
        vm = int(open("/proc/self/statm").read().split()[0]) * resource.getpagesize()
        resource.setrlimit(resource.RLIMIT_AS, (vm + 2 ** 30, resource.RLIM_INFINITY))
        caster.Update()
        print(messages.errors)
        assert messages.errors == ["Cannot allocate the 6000 x 6000 output image."], messages.errors
    """ % data, prelude="sys.path.insert(0, %r)\n" % HERE)
    assert code == 0, f"expected exit 0, got {code}\n{out}\n{err[-2000:]}"


def test_pyvista_arguments_refused_with_a_message(data):
    pv = pytest.importorskip("pyvista")
    from tetdsr.pyvista import add_isosurface
    grid = pv.read(os.path.join(data, "sphere_in_cell.vtu"))
    plotter = pv.Plotter(off_screen=True, window_size=(40, 30))
    for options, error, expected in (
            (dict(interactive_scale=float("nan")), ValueError,
             "add_isosurface: interactive_scale must be a finite number in (0, 1], got nan"),
            (dict(interactive_scale=0), ValueError,
             "add_isosurface: interactive_scale must be a finite number in (0, 1], got 0"),
            (dict(ambient=float("inf")), ValueError,
             "add_isosurface: ambient must be a finite number in [0, 1], got inf"),
            (dict(specular_power="high"), TypeError,
             "add_isosurface: specular_power must be a number, got 'high'"),
            (dict(normal_mode="phong"), ValueError,
             "add_isosurface: normal_mode must be one of 'exact', 'central', 'nodal', 'depth', got 'phong'"),
            (dict(threads=-1), ValueError,
             "add_isosurface: threads must be an integer >= 0 (0: all cores), got -1"),
            (dict(value=float("nan")), ValueError,
             "add_isosurface: value must be a finite number, got nan"),
            (dict(value=[]), ValueError,
             "add_isosurface: value is an empty list: give one iso-value or more"),
            (dict(grid=pv.UnstructuredGrid()), ValueError,
             "add_isosurface: the grid is empty (0 points, 0 cells)"),
            (dict(grid=pv.MultiBlock()), TypeError,
             "add_isosurface: grid is a multiblock dataset (empty): pass one pyvista.UnstructuredGrid "
             "(e.g. multiblock.combine())")):
        arguments = dict(grid=grid, value=0.0) | options
        with pytest.raises(error) as raised:
            add_isosurface(plotter, arguments.pop("grid"), arguments.pop("value"), "sphere", **arguments)
        assert str(raised.value) == expected, f"expected {expected!r}, got {str(raised.value)!r}"
    assert plotter.renderer.GetLayer() == 0, "expected nothing added to the plotter"
    plotter.close()


def test_core_renderer_callbacks_cannot_deadlock_the_mesh():
    """A prepare from a cast's own progress callback (which runs with the cast's lock held) and
    a second cast of the same Renderer from it are refused, not a deadlock."""
    code, out, err = run_child("""
        mesh, ready, messages = prepare(TET_POINTS, np.arange(10).reshape(1, 10), TET_POINTS[:, 0].copy())
        renderer = _core.Renderer(mesh, [0.25], camera((2.0, 1.5, 3.0)), _core.RenderSettings(), **image(64, 64))
        refusals = []

        def progress(fraction):
            for call in (lambda: mesh.prepare(TET_POINTS, np.array([24], np.uint8), np.array([0, 10]),
                                              np.arange(10), TET_POINTS[:, 0].copy(), messages=_core.Messages()),
                         lambda: renderer.cast()):
                try:
                    call()
                except ValueError as error:
                    refusals.append(str(error))

        assert renderer.cast(progress=progress) == renderer.number_of_tiles
        print(sorted(set(refusals)))
        assert sorted(set(refusals)) == [
            "prepare was called from a cast's abort or progress callback: prepare once the cast has returned",
            "this Renderer is casting already (in another thread, or this is its own callback): make one "
            "Renderer per thread"], refusals
    """, timeout=60)
    assert code == 0, f"expected exit 0, got {code}\n{out}\n{err[-2000:]}"


def test_core_curved_cell_with_a_node_at_1e300_is_out_of_scale():
    """fuzz_wheel.py seed 2021 case 22212: a mid-edge node at -1e300 passed the size check (on
    the vertices' edges) as a curved cell whose control-point box overflows; with 50 iso-values
    the surface index over that box segfaulted. Now no such cell is kept (each is tangled or out
    of scale, counted), the image is cast, and a camera 1e300 away is refused as in the filter."""
    out = expect_clean_exit("""
        points, cells = lattice(3)
        points = points.copy()
        node = cells[0, 4]  # a mid-edge node (of every cell that has it)
        users = [c for c in range(len(cells)) if node in cells[c]]
        assert all(node in cells[c, 4:] for c in users)
        field = np.sum(points ** 2, axis=1)  # (of the unedited points: finite)
        points[node, 0] = -1e300
        mesh, ready, messages = prepare(points, cells, field)
        print(mesh.summary, messages.warnings)
        skipped = mesh.summary["out_of_scale"] + mesh.summary["tangled"]
        assert ready and skipped == len(users) and mesh.summary["curved"] == 0, (
            f"expected the {len(users)} cells with the node skipped (tangled or out of scale), "
            f"none kept as curved, got {mesh.summary}")
        bounds = mesh.bounds()
        assert all(np.isfinite(bounds)), bounds
        out = image(31, 31)
        r = _core.Renderer(mesh, list(np.linspace(0, 2, 50)), camera((2.2, 1.6, 3.0), (0, 0, 0)),
                           _core.RenderSettings(), **out)
        assert r.cast() == r.number_of_tiles and np.isfinite(out["depth"]).sum() > 100
        try:
            _core.Renderer(mesh, [0.3], camera((1e300,) * 3), _core.RenderSettings(), **image(8, 8))
            raise SystemExit("expected the camera 1e300 away refused")
        except ValueError as error:
            assert "scene diagonals from the scene" in str(error), str(error)
    """)
    print(out)


def test_pyvista_all_nan_field_says_why_nothing_is_drawn():
    """An all-NaN field in a plotter: the background only, and the filter's error on VTK's
    output window (stderr), not silence."""
    code, out, err = run_child(prelude=PYVISTA_TWO, body="""
        grid.point_data["f"] = np.full(grid.n_points, np.nan)
        img, red, grey, pl, surfaces = shot([(0.5, "white")])
        print("lit pixels", int((img.sum(axis=2) > 0).sum()))
        assert int((img.sum(axis=2) > 0).sum()) == 0
    """)
    assert code == 0, f"expected exit 0, got {code}\n{out}\n{err[-2000:]}"
    expected = "No cell can be rendered: all 48 input cells were skipped"
    assert expected in err, f"expected {expected!r} on stderr, got:\n{err[-2000:]}"
