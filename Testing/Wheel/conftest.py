"""pytest set-up of the wheel's tests: the bundled data folder, and scenes.py / truth.py importable."""
import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


@pytest.fixture(scope="session")
def data():
    return os.path.join(HERE, "..", "..", "Data")

# pip's VTK renders off screen through EGL when there is no X display (no Xvfb needed); without
# this it tries X first and prints a warning.
if not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
