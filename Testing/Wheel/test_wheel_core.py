"""tetdsr._core on its own (no VTK object involved): the core's checks give the core's
sentences, PreparedMesh reads the dtypes VTK hands over, and Renderer checks every array it is
given (shapes, dtypes, in place) and refuses to cast once its mesh is prepared again."""
import os
import sys

import numpy as np
import pytest

from tetdsr import _core

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402

VTK_QUADRATIC_TETRA, VTK_TETRA, VTK_HEXAGONAL_PRISM, VTK_PENTAGONAL_PRISM = 24, 10, 16, 15


def mesh_arrays(n=2, points_dtype=np.float64, id_dtype=np.int64):
    """A Kuhn lattice of quadratic tets in [-1, 1]^3 with the field |x|^2, as VTK holds it."""
    points, cells = lattice(n)
    offsets = np.arange(0, 10 * len(cells) + 1, 10).astype(id_dtype)
    return dict(points=np.ascontiguousarray(points, dtype=points_dtype),
                cell_types=np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8), offsets=offsets,
                connectivity=np.ascontiguousarray(cells.ravel(), dtype=id_dtype),
                field=np.sum(points * points, axis=1))


def prepared(**arrays):
    messages = _core.Messages()
    mesh = _core.PreparedMesh()
    ready = mesh.prepare(**(mesh_arrays() | arrays), field_name="r2", messages=messages)
    return mesh, ready, messages


def image(height, width):
    return dict(colors=np.zeros((height, width, 4), np.uint8), depth=np.zeros((height, width)),
                normals=np.zeros((height, width, 3)), cell_ids=np.zeros((height, width), np.int64))


def camera():
    c = _core.Camera()
    c.position = (0.3, 0.2, 6.0)
    return c


def test_checks_write_the_core_sentences():
    messages = _core.Messages()
    assert not _core.check_iso_values([0.5, float("inf")], messages)
    assert not _core.check_clip_planes([_core.ClipPlane((0, 0, 0), (0, 0, 0))], messages)
    assert not _core.check_image_size(0, 30, messages)
    _core.report_missing_array(_core.InputArray.COLOR, None, messages)
    assert _core.choose_point_array_component("v", True, 3, -1, False, "ArrayComponent", messages) is None
    assert messages.errors == [
        "Iso-value inf is not finite.",
        "Clipping plane 0 has a zero normal: it keeps no side.",
        "ImageSize 0 x 30 pixels: choose a smaller size.",
        "ColorByArray is on but no colour array is chosen: choose one with "
        "SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).",
        "Array 'v' has 3 components: choose one with ArrayComponent.",
    ], messages.errors
    messages.clear()
    assert messages.ok and messages.errors == []
    changed, value = _core.set_clamped(_core.NUMBER_SETTINGS["SpecularPower"], 500.0, 30.0, messages)
    assert (changed, value) == (True, 128.0), (changed, value)
    assert _core.set_clamped(_core.NUMBER_SETTINGS["Ambient"], float("nan"), 0.1, messages) == (False, 0.1)
    assert messages.errors == ["Ambient must be a number, got NaN."], messages.errors


def test_prepared_mesh_reads_vtk_dtypes_and_tells_what_it_skipped():
    reference, ready, messages = prepared()
    assert ready and messages.ok, messages.errors
    valid = reference.summary["valid"]
    assert valid == 48, f"expected 48 cells of a 2^3 Kuhn lattice, got {valid}"
    single, ready, messages = prepared(points=mesh_arrays(points_dtype=np.float32)["points"],
                                       offsets=mesh_arrays(id_dtype=np.int32)["offsets"],
                                       connectivity=mesh_arrays(id_dtype=np.int32)["connectivity"],
                                       field=mesh_arrays()["field"].astype(np.float32))
    assert ready and single.summary["valid"] == valid, (messages.errors, single.summary)
    types = mesh_arrays()["cell_types"].copy()
    # Types TetDSR does not read, whatever their ids (10 here): a hexagonal and a pentagonal prism.
    types[[3, 7]] = VTK_HEXAGONAL_PRISM, VTK_PENTAGONAL_PRISM
    mesh, ready, messages = prepared(cell_types=types)
    assert ready and mesh.summary["unsupported"] == 2, mesh.summary
    assert mesh.summary["valid"] == valid - 2, mesh.summary
    # (The list of types read is the core's: MeshInput.cpp's, tested word for word in TestMeshInput.)
    assert len(messages.warnings) == 1, messages.warnings
    assert messages.warnings[0].startswith("Skipped 2 cells of a type TetDSR does not read (it reads VTK_TETRA, "
                                           "VTK_QUADRATIC_TETRA,"), messages.warnings
    assert messages.warnings[0].endswith("VTK_TRIQUADRATIC_PYRAMID; not VTK_LAGRANGE_PYRAMID or VTK_BEZIER_PYRAMID: "
                                         "VTK 9.2 has no cell class of the type)."), messages.warnings
    _, ready, messages = prepared(field=np.zeros(5))
    assert not ready and messages.errors[-1].endswith("'r2' has 5 tuples for 125 points."), messages.errors
    short = reference.point_values(np.zeros((4, 3)), "speed", 1, "colour array", messages)
    assert short is None and messages.errors[-1] == "The colour array 'speed' has 4 tuples for 125 points."
    values = reference.point_values(np.arange(375, dtype=np.int16).reshape(125, 3), "v", 1,
                                    "colour array", messages)
    assert values.dtype == np.float64 and values.shape == (125, 3) and values[2, 1] == 7.0
    with pytest.raises(TypeError):
        prepared(field=np.zeros(125, dtype=np.complex128))


def test_renderer_checks_every_array_and_writes_in_place():
    mesh, _, _ = prepared()
    settings = _core.RenderSettings()
    out = image(40, 50)
    renderer = _core.Renderer(mesh, [0.5], camera(), settings, **out)
    assert renderer.cast(threads=2) == renderer.number_of_tiles == 4 * 3
    hits = np.isfinite(out["depth"])
    assert hits.sum() > 100 and np.all(out["cell_ids"][hits] >= 0), "expected the sphere r = 0.7 in view"
    for name, bad in (("colors", np.zeros((40, 50, 3), np.uint8)), ("normals", np.zeros((50, 40, 3))),
                      ("cell_ids", np.zeros((40, 50), np.int32)), ("depth", np.zeros((40, 50), np.float32))):
        with pytest.raises((ValueError, TypeError)):
            _core.Renderer(mesh, [0.5], camera(), settings, **(image(40, 50) | {name: bad}))
    with pytest.raises(TypeError):  # a view that is not C-contiguous would be a converted copy
        _core.Renderer(mesh, [0.5], camera(), settings, **(image(40, 50) | {"depth": np.zeros((50, 40)).T}))
    with pytest.raises(ValueError, match="No iso-value"):
        _core.Renderer(mesh, [], camera(), settings, **image(40, 50))
    settings.color_by = _core.ColorByArray(np.zeros(125))
    with pytest.raises(ValueError, match="color_table"):
        _core.Renderer(mesh, [0.5], camera(), settings, **image(40, 50))
    settings.color_by = _core.ColorByArray(np.zeros(7))
    with pytest.raises(ValueError, match="7 tuples for 125 points"):
        _core.Renderer(mesh, [0.5], camera(), settings, **image(40, 50))


def test_a_renderer_refuses_to_cast_once_its_mesh_is_prepared_again():
    """A Renderer keeps the surface it casts into (another Renderer's iso-values do not free
    it), but not the scene: after a new prepare it refuses to cast."""
    mesh, _, _ = prepared()
    first_image, second_image = image(20, 20), image(20, 20)
    first = _core.Renderer(mesh, [0.5], camera(), _core.RenderSettings(), **first_image)
    alone = image(20, 20)
    _core.Renderer(mesh, [0.5], camera(), _core.RenderSettings(), **alone).cast()
    _core.Renderer(mesh, [0.2], camera(), _core.RenderSettings(), **second_image).cast()
    assert first.cast() == first.number_of_tiles
    assert np.array_equal(first_image["depth"], alone["depth"]), "expected the image of iso-value 0.5"
    assert not np.array_equal(first_image["depth"], second_image["depth"])
    mesh.prepare(**mesh_arrays(), messages=_core.Messages())
    with pytest.raises(ValueError, match="prepared again since this Renderer was made"):
        first.cast()


def test_cast_asks_abort_and_tells_progress_between_steps():
    mesh, _, _ = prepared()
    renderer = _core.Renderer(mesh, [0.5], camera(), _core.RenderSettings(), **image(160, 160))
    progress = []
    done = renderer.cast(abort=lambda: len(progress) == 3, progress=progress.append)
    tiles = renderer.number_of_tiles
    step = max(1, tiles // _core.PROGRESS_STEPS)
    assert done == 3 * step and progress == [k * step / tiles for k in (1, 2, 3)], (done, progress)
