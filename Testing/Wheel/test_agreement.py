"""The wheel's filter against the C++ build's on the same scenes (scenes.py): the C++ outputs come
from cxx_reference.py (run by Scripts/test-wheel.sh in /usr/bin/python3), named by the environment
variable TETDSR_CXX_REFERENCE. Both builds compile the same core sources, so depths must agree to
1e-12 of the scene's diagonal, pixels must be hit or missed alike, and colours may differ only
where VTK 9.2 and pip's VTK sample a colour map differently (at most 1 / 255)."""
import os

import numpy as np
import pytest

import scenes
from tetdsr import vtkDirectSurfaceRayCaster

REFERENCE = os.environ.get("TETDSR_CXX_REFERENCE")


@pytest.fixture(scope="module")
def reference():
    if not REFERENCE:
        pytest.skip("TETDSR_CXX_REFERENCE is not set (Scripts/test-wheel.sh sets it)")
    assert os.path.exists(REFERENCE), f"expected the C++ filter's outputs at {REFERENCE}"
    return np.load(REFERENCE)


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_wheel_equals_cxx_filter(reference, data, name):
    ours, diagonal = scenes.render(vtkDirectSurfaceRayCaster, data, name)
    theirs = {key.split("/", 1)[1]: reference[key] for key in reference.files
              if key.startswith(name + "/")}
    assert set(ours) | {"diagonal"} == set(theirs), (
        f"expected arrays {sorted(theirs)}, got {sorted(ours)}")
    hit_ours = np.isfinite(ours["Depth"])
    hit_theirs = np.isfinite(theirs["Depth"])
    mismatched = int(np.count_nonzero(hit_ours != hit_theirs))
    assert hit_theirs.sum() > 500, f"expected a visible surface, got {hit_theirs.sum()} pixels"
    assert mismatched == 0, f"expected the same {hit_theirs.sum()} surface pixels, got {mismatched} differing"
    both = hit_ours & hit_theirs
    depth = float(np.max(np.abs(ours["Depth"][both] - theirs["Depth"][both]))) / diagonal
    normals = float(np.max(np.abs(ours["Normals"] - theirs["Normals"])))
    colors = int(np.max(np.abs(ours["Colors"].astype(int) - theirs["Colors"].astype(int))))
    differing = int(np.count_nonzero(np.any(ours["Colors"] != theirs["Colors"], axis=1)))
    print(f"\n{name}: {hit_theirs.sum()} surface pixels; depth difference {depth:.3g} of the "
          f"diagonal; normals {normals:.3g}; colours: {differing} pixels differ, by at most "
          f"{colors} / 255")
    assert depth <= 1e-12, f"expected depths within 1e-12 of the diagonal, got {depth:.3g}"
    assert normals <= 1e-12, f"expected the same normals, got a difference of {normals:.3g}"
    assert np.array_equal(ours["CellId"], theirs["CellId"]), "expected the same cell ids"
    assert colors <= 1, f"expected colours within 1 / 255, got {colors} / 255"
    if "ColorValues" in theirs:
        same_nan = np.array_equal(np.isnan(ours["ColorValues"]), np.isnan(theirs["ColorValues"]))
        assert same_nan, "expected colour values where the C++ filter has them"
        finite = np.isfinite(theirs["ColorValues"])
        gap = float(np.max(np.abs(ours["ColorValues"][finite] - theirs["ColorValues"][finite]), initial=0))
        assert gap <= 1e-12, f"expected the same colour values, got a difference of {gap:.3g}"
