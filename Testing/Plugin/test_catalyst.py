"""The in situ example (Examples/catalyst/heat_p2.py) in the suite: the P2 heat simulation hands
each step to ParaView Catalyst, whose pipeline saves Direct Surface pictures every 10 steps,
serially and under mpirun -np 2 (each process handing over its slab of cells; each process on an
X server of its own, a time limit, mpi_private_displays.py). Asserts: the cells' node order
checked against VTK's shape functions (the example refuses otherwise), the pictures of steps 10,
20 and 30 written and showing the surfaces, and the 2-process pictures equal the serial ones
within 2 / 255 (a translucent surface around an opaque one).

Usage: test_catalyst.py <TetDSR.so> <work directory> <venv directory>
(creates Scripts/flow-venv.sh's venv in <venv directory> when missing)
"""
import os
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
plugin, work, venv = sys.argv[1:4]
python = os.path.join(venv, "bin", "python")
subprocess.run(["bash", os.path.join(ROOT, "Scripts", "flow-venv.sh"), "-c", "import skfem"], check=True,
               env=dict(os.environ, TETDSR_FLOW_VENV=venv))
example = [python, os.path.join(ROOT, "Examples", "catalyst", "heat_p2.py"), "--steps", "30",
           "--every", "10", "--plugin", plugin]
launcher = [sys.executable, os.path.join(HERE, "mpi_private_displays.py")]
failures = []
for ranks in (1, 2):
    out = os.path.join(work, f"ranks{ranks}")
    run = subprocess.run(launcher + [str(ranks), "300"] + example + ["--out", out],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace")
    print("\n".join(line for line in run.stdout.splitlines() if line.startswith(("heat_p2", "|"))))
    if run.returncode != 0:
        print(run.stdout[-4000:])
        failures.append(f"{ranks} process(es): the example failed ({run.returncode})")


def pixels(path):
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    return vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


for step in (10, 20, 30):
    paths = [os.path.join(work, f"ranks{ranks}", f"heat_{step:04d}.png") for ranks in (1, 2)]
    if not all(os.path.exists(path) for path in paths):
        failures.append(f"step {step}: a picture is missing")
        continue
    serial, distributed = (pixels(path) for path in paths)
    covered = int((np.abs(serial - serial[0]).max(axis=1) > 0).sum())
    difference = np.abs(serial - distributed).max(axis=1)
    print(f"step {step}: the surfaces cover {covered} pixels; 2 processes: {int((difference > 0).sum())} "
          f"pixels differ from 1 (max {difference.max()} / 255)")
    if covered < 10000:
        failures.append(f"step {step}: the surfaces should cover more than 10000 pixels, got {covered}")
    if difference.max() > 2:
        failures.append(f"step {step}: 2 processes differ from 1 by up to {difference.max()} / 255")
for failure in failures:
    print("FAILED:", failure)
sys.exit(1 if failures else 0)
