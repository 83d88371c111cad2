"""Renders the shared scenes (scenes.py) with the C++ build's filter and saves every output
array to one .npz, for test_agreement.py to compare with the wheel's.
Run with /usr/bin/python3 and PYTHONPATH=build/lib/python3/dist-packages (ParaView's VTK 9.2).
Usage: cxx_reference.py <Data folder> <out.npz>"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenes  # noqa: E402
from tetdsr import vtkDirectSurfaceRayCaster  # noqa: E402  (the C++ filter)

data, out = sys.argv[1], sys.argv[2]
saved = {}
for name in scenes.SCENES:
    arrays, diagonal = scenes.render(vtkDirectSurfaceRayCaster, data, name)
    for key, values in arrays.items():
        saved[f"{name}/{key}"] = values
    saved[f"{name}/diagonal"] = np.array(diagonal)
    print(f"{name}: {int(np.isfinite(arrays['Depth']).sum())} surface pixels (C++ filter)")
np.savez(out, **saved)
