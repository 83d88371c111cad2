#!/usr/bin/env python3
"""A Q3 Poisson solution on curved hexahedra, written by MFEM's own ParaView writer
(PyMFEM's ParaViewDataCollection, high-order output: VTK_LAGRANGE_HEXAHEDRON cells of 64 nodes),
then gathered by ParaView's VTK into one compressed .vtu.

Run it through Scripts/make-mfem-hex.sh, which makes or reuses build/mfem-venv (a pinned PyMFEM
and its own numpy 2) and runs this script there; the script then runs itself again under
/usr/bin/python3 (ParaView's VTK 9.2, Debian's numpy 1.24) to read, check and rewrite MFEM's
output. The two interpreters are kept apart because PyMFEM 4.10 needs numpy >= 2.4.1, and
ParaView's VTK 9.2 is built for Debian's numpy 1. Data/mfem_hex_q3.vtu is the default run:

  bash Scripts/make-mfem-hex.sh --out Data/mfem_hex_q3.vtu

The mesh: mfem.Mesh.MakeCartesian3D(N, N, N) of the unit cube (N = 4 by default: 64 hexahedra),
SetCurvature(3) (the nodes become an H1 Q3 grid function, Gauss-Lobatto points), then
mesh.Transform with the smooth map

  X = x + A sin(pi y) sin(pi z),  Y = y + A sin(pi z) sin(pi x),  Z = z + A sin(pi x) sin(pi y)

(A = 0.1; its Jacobian stays within Gershgorin distance 2 pi A = 0.63 of the identity, so it is
invertible): every node goes through the map, so each cell is a curved isoparametric Q3 hexahedron
(the faces of the cube bulge; interior cells curve too).

The fields, all in the same H1 Q3 space as the mesh nodes:
  "u":  the finite-element solution of -laplace(u) = f in the curved domain, u = g on its boundary,
        with f and g from the manufactured solution u_exact = sin(pi X) sin(pi Y) sin(pi Z) (X, Y, Z
        physical coordinates; f = 3 pi^2 u_exact). Assembled with MFEM's DiffusionIntegrator and
        DomainLFIntegrator, solved with PCG + Gauss-Seidel to a relative residual of 1e-12. The L2
        error is printed at N/2 and N with the observed rate (Q3: 4 once asymptotic; printed,
        not asserted).
  "x":  the physical x coordinate, projected (ProjectCoefficient). The mesh's geometry is in the same
        Q3 space, so this is represented exactly: at every node its value is the node's x, and its
        isosurfaces are planes x = c cutting the curved cells (the truth for tests).
  "r2": (X - 1/2)^2 + (Y - 1/2)^2 + (Z - 1/2)^2, projected: a smooth nonlinear field (on the curved
        cells it is a degree-6 polynomial of the reference coordinates, so Q3 only interpolates it).

MFEM writes them with ParaViewDataCollection: SetHighOrderOutput(True), SetLevelsOfDetail(3),
SetDataFormat(VTKFormat_BINARY) (Float64) and compression; the layout is NAME/NAME.pvd ->
Cycle000000/data.pvtu -> proc000000.vtu, every cell with its own copy of its 64 nodes (points are
not shared between cells). This happens in a temporary directory (--keep DIR keeps MFEM's files).

The VTK half (/usr/bin/python3) reads data.pvtu with vtkXMLPUnstructuredGridReader, checks that
every cell is VTK_LAGRANGE_HEXAHEDRON (72) with 64 points, and writes the grid unchanged (MFEM's
points, cells and arrays, duplicated nodes kept) as one .vtu, binary inline (base64) and
zlib-compressed, "u" the active scalars. Not appended data: Debian 12's libexpat (2.5.0 with the
backported reparse deferral) makes ParaView 5.11's VTK 9.2 reader reject appended files larger than
one 4 KB read ("not well-formed (invalid token)" / "junk after document element"; VTK issue 19258,
fixed in later VTK), as docs/paraview.md notes. It reads the written file back and checks:
  - the "x" array against each point's x coordinate (max difference printed; must be < 1e-12);
  - at random reference points of every cell, VTK's map (vtkLagrangeHexahedron::EvaluateLocation)
    and VTK's interpolation of "u", "x" and "r2" against MFEM's own values at the same reference
    point (ElementTransformation::Transform and GridFunction::GetValue, saved by the MFEM half):
    VTK's parametric (r, s, t) is MFEM's reference (x, y, z) of the same element, cell i is MFEM's
    element i;
  - how curved the cells are: the largest distance of a node from the trilinear map of its cell's
    eight corners.
With --provenance PATH it writes a paragraph on the run (mesh, map, versions, command, arrays,
sizes, runtime, the check) to PATH.

Measured on the 2-core development machine, the default run: 64 cells, 4,096 points (2,197
distinct), 2,197 dofs; MFEM wrote proc000000.vtu of 67,381 bytes, the output is 75,569 bytes; every
cell curved (nodes 4.8e-3 to 2.1e-2 off the trilinear map of the corners); L2 error of u 2.58e-3
(N = 2) and 2.55e-4 (N = 4), rate 3.34 (pre-asymptotic: --elements 8 gives 1.63e-5, rate 3.97),
nodal max error 1.6e-4; the "x" array equals the points' x bit for bit (max difference 0), and VTK
against MFEM at the 320 random points agrees to 1.3e-15 at worst. About 26 s with a new venv (pip
downloads the 101 MB wheel), 3 s when it exists. The written file is the same byte for byte on
every run.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

ORDER = 3
AMPLITUDE = 0.1
N_SAMPLES = 5          # random reference points per cell for the VTK-against-MFEM check
SEED = 20250601
COLLECTION = "mfem_hex_q3"
TOL = 1e-12


def physical_map(x, y, z):
    s = math.sin
    p = math.pi
    return (x + AMPLITUDE * s(p * y) * s(p * z),
            y + AMPLITUDE * s(p * z) * s(p * x),
            z + AMPLITUDE * s(p * x) * s(p * y))


def u_exact(p):
    return math.sin(math.pi * p[0]) * math.sin(math.pi * p[1]) * math.sin(math.pi * p[2])


def r2_field(p):
    return (p[0] - 0.5) ** 2 + (p[1] - 0.5) ** 2 + (p[2] - 0.5) ** 2


# ---------------------------------------------------------------------------------------------
# The MFEM half (run in build/mfem-venv).

def build_and_solve(mfem, n):
    """The curved Q3 mesh of n^3 hexahedra, its Q3 space and the Poisson solution on it."""
    mesh = mfem.Mesh.MakeCartesian3D(n, n, n, mfem.Element.HEXAHEDRON, 1.0, 1.0, 1.0)
    mesh.SetCurvature(ORDER)

    class Deformation(mfem.VectorPyCoefficient):
        def EvalValue(self, x):
            return physical_map(x[0], x[1], x[2])

    mesh.Transform(Deformation(3))

    class Exact(mfem.PyCoefficient):
        def EvalValue(self, x):
            return u_exact(x)

    class Source(mfem.PyCoefficient):
        def EvalValue(self, x):
            return 3.0 * math.pi ** 2 * u_exact(x)

    fec = mfem.H1_FECollection(ORDER, 3)
    fes = mfem.FiniteElementSpace(mesh, fec)
    ess_bdr = mfem.intArray([1] * mesh.bdr_attributes.Max())
    ess_tdofs = mfem.intArray()
    fes.GetEssentialTrueDofs(ess_bdr, ess_tdofs)

    exact = Exact()
    source = Source()
    b = mfem.LinearForm(fes)
    b.AddDomainIntegrator(mfem.DomainLFIntegrator(source))
    b.Assemble()
    u = mfem.GridFunction(fes)
    u.ProjectCoefficient(exact)            # the boundary values; the interior is solved for
    a = mfem.BilinearForm(fes)
    a.AddDomainIntegrator(mfem.DiffusionIntegrator(mfem.ConstantCoefficient(1.0)))
    a.Assemble()
    A = mfem.OperatorPtr()
    B = mfem.Vector()
    X = mfem.Vector()
    a.FormLinearSystem(ess_tdofs, u, b, A, X, B)
    AA = mfem.OperatorHandle2SparseMatrix(A)
    smoother = mfem.GSSmoother(AA)
    mfem.PCG(AA, smoother, B, X, 0, 5000, 1e-24, 0.0)   # RTOLERANCE is squared: 1e-12 relative
    a.RecoverFEMSolution(X, b, u)
    l2 = u.ComputeL2Error(exact)
    # keep the Python coefficient objects alive as long as the mesh and forms
    keep = (Deformation, exact, source, fec, a, b)
    return mesh, fes, u, l2, keep


def mfem_half(args):
    import importlib.metadata
    import random
    import mfem.ser as mfem

    t0 = time.time()
    n = args.elements
    results = {}
    if n % 2 == 0 and n >= 4:
        _, _, _, l2_coarse, _ = build_and_solve(mfem, n // 2)
        results["l2_coarse"] = l2_coarse
    mesh, fes, u, l2, keep = build_and_solve(mfem, n)
    results["l2"] = l2
    results["rate"] = (math.log(results["l2_coarse"] / l2) / math.log(2.0)
                       if "l2_coarse" in results else None)

    class XCoef(mfem.PyCoefficient):
        def EvalValue(self, p):
            return p[0]

    class R2Coef(mfem.PyCoefficient):
        def EvalValue(self, p):
            return r2_field(p)

    xgf = mfem.GridFunction(fes)
    xgf.ProjectCoefficient(XCoef())
    r2gf = mfem.GridFunction(fes)
    r2gf.ProjectCoefficient(R2Coef())

    # nodal error of u against the exact solution at the mesh's nodes (same space)
    exact_gf = mfem.GridFunction(fes)
    exact_gf.ProjectCoefficient(keep[1])
    nodal = max(abs(a - b) for a, b in zip(u.GetDataArray(), exact_gf.GetDataArray()))
    results["nodal_max_error"] = float(nodal)
    results["u_range"] = [float(min(u.GetDataArray())), float(max(u.GetDataArray()))]

    work = args.keep if args.keep else tempfile.mkdtemp(prefix="mfem_hex_")
    os.makedirs(work, exist_ok=True)
    dc = mfem.ParaViewDataCollection(COLLECTION, mesh)
    dc.SetPrefixPath(work)
    dc.SetHighOrderOutput(True)
    dc.SetLevelsOfDetail(ORDER)
    dc.SetDataFormat(mfem.VTKFormat_BINARY)
    dc.SetCompression(True)
    dc.RegisterField("u", u)
    dc.RegisterField("x", xgf)
    dc.RegisterField("r2", r2gf)
    dc.SetCycle(0)
    dc.SetTime(0.0)
    dc.Save()
    written = []
    for root, _, files in os.walk(os.path.join(work, COLLECTION)):
        for f in sorted(files):
            p = os.path.join(root, f)
            written.append([os.path.relpath(p, work), os.path.getsize(p)])
    written.sort()

    # MFEM's own values at random reference points of every element, for the VTK half to compare
    rng = random.Random(SEED)
    samples = []
    for e in range(mesh.GetNE()):
        T = mesh.GetElementTransformation(e)
        for _ in range(N_SAMPLES):
            r = [rng.random() for _ in range(3)]
            ip = mfem.IntegrationPoint()
            ip.Set3(r[0], r[1], r[2])
            T.SetIntPoint(ip)
            phys = T.Transform(ip)   # PyMFEM returns the point (Transform(ip, v) leaves v unset)
            samples.append({"cell": e, "r": r, "X": [phys[0], phys[1], phys[2]],
                            "u": u.GetValue(e, ip), "x": xgf.GetValue(e, ip),
                            "r2": r2gf.GetValue(e, ip)})

    pip_show = subprocess.run([sys.executable, "-m", "pip", "show", "mfem"], capture_output=True,
                              text=True).stdout
    pip_show = "; ".join(line.strip() for line in pip_show.splitlines()
                         if line.split(":")[0] in ("Name", "Version", "Location", "Requires"))
    info = {
        "pip_show": pip_show, "started": t0,
        "elements": mesh.GetNE(), "n": n, "order": ORDER, "amplitude": AMPLITUDE,
        "dofs": fes.GetTrueVSize(), "mfem_version": importlib.metadata.version("mfem"),
        "numpy_version": importlib.metadata.version("numpy"),
        "python": sys.version.split()[0], "mfem_seconds": time.time() - t0,
        "written": written, "samples": samples, **results,
    }
    with open(os.path.join(work, "mfem_info.json"), "w") as f:
        json.dump(info, f)
    print(f"MFEM {info['mfem_version']} (Python {info['python']}, numpy {info['numpy_version']}): "
          f"{info['elements']} curved Q3 hexahedra, {info['dofs']} dofs")
    if results["rate"] is not None:
        print(f"  Poisson L2 error: N={n // 2}: {results['l2_coarse']:.3e}, N={n}: {l2:.3e} "
              f"(rate {results['rate']:.2f}); nodal max error {nodal:.2e}")
    else:
        print(f"  Poisson L2 error {l2:.3e}; nodal max error {nodal:.2e}")
    for rel, size in written:
        print(f"  wrote {rel} ({size} bytes)")
    print(f"  {info['mfem_seconds']:.1f} s")

    cmd = ["/usr/bin/python3", os.path.abspath(__file__), "--vtk-half", work, "--out", args.out]
    if args.provenance:
        cmd += ["--provenance", args.provenance]
    rc = subprocess.call(cmd)
    if not args.keep:
        shutil.rmtree(work)
    if rc != 0:
        sys.exit(rc)


# ---------------------------------------------------------------------------------------------
# The VTK half (/usr/bin/python3: ParaView's VTK 9.2).

def vtk_half(args):
    import numpy as np
    import vtk
    from vtkmodules.util.numpy_support import vtk_to_numpy

    t0 = time.time()
    work = args.vtk_half
    with open(os.path.join(work, "mfem_info.json")) as f:
        info = json.load(f)
    pvtu = os.path.join(work, COLLECTION, "Cycle000000", "data.pvtu")
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(pvtu)
    reader.Update()
    grid = reader.GetOutput()
    nc, npnt = grid.GetNumberOfCells(), grid.GetNumberOfPoints()
    if nc != info["elements"]:
        sys.exit(f"{pvtu}: {nc} cells, MFEM has {info['elements']} elements")
    types = {grid.GetCellType(i) for i in range(nc)}
    sizes = {grid.GetCell(i).GetNumberOfPoints() for i in range(nc)}
    if types != {vtk.VTK_LAGRANGE_HEXAHEDRON} or sizes != {64}:
        sys.exit(f"{pvtu}: cell types {types}, points per cell {sizes}; expected {{72}}, {{64}}")

    out = args.out
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(out)
    grid.GetPointData().SetActiveScalars("u")
    writer.SetInputData(grid)
    writer.SetDataModeToBinary()           # inline: Debian 12's expat rejects appended data
    writer.SetCompressorTypeToZLib()
    if writer.Write() != 1:
        sys.exit(f"could not write {out}")

    # read the written file back and check it
    r2 = vtk.vtkXMLUnstructuredGridReader()
    r2.SetFileName(out)
    r2.Update()
    g = r2.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    pd = g.GetPointData()
    cd = g.GetCellData()
    arrays = {}
    print(f"{out}: {g.GetNumberOfCells()} cells (all VTK_LAGRANGE_HEXAHEDRON = "
          f"{vtk.VTK_LAGRANGE_HEXAHEDRON}, 64 points each), {g.GetNumberOfPoints()} points "
          f"({g.GetPoints().GetData().GetDataTypeAsString()}), {os.path.getsize(out)} bytes")
    for assoc, data in (("point", pd), ("cell", cd)):
        for k in range(data.GetNumberOfArrays()):
            a = data.GetArray(k)
            lo, hi = a.GetRange(-1) if a.GetNumberOfComponents() > 1 else a.GetRange()
            arrays[a.GetName()] = [assoc, a.GetDataTypeAsString(), a.GetNumberOfComponents(),
                                   lo, hi]
            print(f"  {assoc} array {a.GetName()!r}: {a.GetDataTypeAsString()} x "
                  f"{a.GetNumberOfComponents()}, range [{lo:.6g}, {hi:.6g}]")
    if pd.GetScalars() is not None:
        print(f"  active point scalars: {pd.GetScalars().GetName()!r}")
    b = g.GetBounds()
    print(f"  bounds x [{b[0]:.6g}, {b[1]:.6g}] y [{b[2]:.6g}, {b[3]:.6g}] z [{b[4]:.6g}, "
          f"{b[5]:.6g}]")
    ids = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 64)
    print(f"  distinct point ids used: {len(np.unique(ids))}; distinct coordinates: "
          f"{len(np.unique(np.round(pts, 12), axis=0))}")

    # 1. the linear field: "x" at every node against the node's x
    xarr = vtk_to_numpy(pd.GetArray("x")).astype(float)
    xdiff = float(np.max(np.abs(xarr - pts[:, 0])))
    print(f"  max |x array - point x| over {len(xarr)} points: {xdiff:.3e}")

    # 2. VTK's map and interpolation at random reference points against MFEM's values
    worst = {"X": 0.0, "u": 0.0, "x": 0.0, "r2": 0.0}
    fields = {k: vtk_to_numpy(pd.GetArray(k)).astype(float) for k in ("u", "x", "r2")}
    w = [0.0] * 64
    xyz = [0.0] * 3
    sub = vtk.reference(0)
    for s in info["samples"]:
        cell = g.GetCell(s["cell"])
        cell.EvaluateLocation(sub, s["r"], xyz, w)
        wa = np.array(w)
        cid = ids[s["cell"]]
        worst["X"] = max(worst["X"], max(abs(xyz[i] - s["X"][i]) for i in range(3)))
        for k in ("u", "x", "r2"):
            worst[k] = max(worst[k], abs(float(wa @ fields[k][cid]) - s[k]))
    print(f"  VTK against MFEM at {len(info['samples'])} random reference points: map "
          f"{worst['X']:.2e}, u {worst['u']:.2e}, x {worst['x']:.2e}, r2 {worst['r2']:.2e}")

    # 3. how curved: node distance from the trilinear map of the cell's 8 corners
    pc = g.GetCell(0)
    pc.SetUniformOrderFromNumPoints(64)
    par = np.array([pc.GetParametricCoords()[i] for i in range(64 * 3)]).reshape(64, 3)
    tri = np.stack([(1 - par[:, 0]) * (1 - par[:, 1]) * (1 - par[:, 2]),
                    par[:, 0] * (1 - par[:, 1]) * (1 - par[:, 2]),
                    par[:, 0] * par[:, 1] * (1 - par[:, 2]),
                    (1 - par[:, 0]) * par[:, 1] * (1 - par[:, 2]),
                    (1 - par[:, 0]) * (1 - par[:, 1]) * par[:, 2],
                    par[:, 0] * (1 - par[:, 1]) * par[:, 2],
                    par[:, 0] * par[:, 1] * par[:, 2],
                    (1 - par[:, 0]) * par[:, 1] * par[:, 2]], axis=1)
    cellpts = pts[ids]                                    # (cells, 64, 3)
    lin = np.einsum("pk,ckd->cpd", tri, cellpts[:, :8, :])
    dev = np.linalg.norm(cellpts - lin, axis=2).max(axis=1)
    print(f"  curvature: nodes off the trilinear map of the corners by up to {dev.max():.3e} "
          f"(every cell above 1e-3: {bool((dev > 1e-3).all())}, least {dev.min():.3e})")

    bad = [k for k, v in worst.items() if v > TOL] + (["x-array"] if xdiff > TOL else [])
    seconds = time.time() - t0
    if args.provenance:
        write_provenance(args.provenance, info, out, g, arrays, xdiff, worst, dev, seconds,
                         vtk.vtkVersion.GetVTKVersion(), b)
        print(f"  provenance: {args.provenance}")
    if bad:
        sys.exit(f"checks above {TOL}: {bad}")
    print(f"  VTK half {seconds:.1f} s")


def write_provenance(path, info, out, g, arrays, xdiff, worst, dev, seconds, vtk_version, b):
    arr_text = "; ".join(f"{k} ({v[0]}, {v[1]} x {v[2]}, range {v[3]:.6g} to {v[4]:.6g})"
                         for k, v in arrays.items())
    written = ", ".join(f"{p} ({s} bytes)" for p, s in info["written"])
    rate = (f"{info['l2_coarse']:.3e} at N = {info['n'] // 2} and {info['l2']:.3e} at N = "
            f"{info['n']} (observed rate {info['rate']:.2f})" if info.get("rate") else
            f"{info['l2']:.3e}")
    total = time.time() - info["started"]
    text = f"""`{out}` was written by MFEM's own ParaView writer (PyMFEM `mfem` {info['mfem_version']}, Python
{info['python']}, numpy {info['numpy_version']}, in build/mfem-venv) and gathered into one file by
ParaView's VTK {vtk_version} under /usr/bin/python3. Mesh: `mfem.Mesh.MakeCartesian3D({info['n']},
{info['n']}, {info['n']}, HEXAHEDRON, 1, 1, 1)` ({info['elements']} hexahedra), `SetCurvature(3)`,
then `mesh.Transform` with X = x + A sin(pi y) sin(pi z), Y = y + A sin(pi z) sin(pi x),
Z = z + A sin(pi x) sin(pi y), A = {info['amplitude']} (every cell is a curved isoparametric Q3
hexahedron: its nodes lie up to {dev.max():.3e}, at least {dev.min():.3e}, off the trilinear map of
its corners). Fields in the H1 Q3 space of the mesh ({info['dofs']} dofs): "u", the FE solution
of -laplace(u) = 3 pi^2 u_exact with u = u_exact on the boundary, u_exact = sin(pi X) sin(pi Y)
sin(pi Z) (DiffusionIntegrator, PCG + GSSmoother to 1e-12; L2 error {rate}; nodal max error
{info['nodal_max_error']:.2e}); "x", the projected physical x coordinate (exact on these cells:
its isosurfaces are planes); "r2", the projected (X-1/2)^2 + (Y-1/2)^2 + (Z-1/2)^2.
ParaViewDataCollection with SetHighOrderOutput(True), SetLevelsOfDetail(3),
SetDataFormat(VTKFormat_BINARY), SetCompression(True) wrote {written}. The output file holds that
grid unchanged (vtkXMLPUnstructuredGridReader -> vtkXMLUnstructuredGridWriter, binary inline,
zlib; not appended, which this machine's VTK 9.2 with Debian 12's expat cannot read back): {g.GetNumberOfCells()} cells, all VTK_LAGRANGE_HEXAHEDRON (72) with 64 points each, and
{g.GetNumberOfPoints()} points (every cell has its own copy of its nodes, as MFEM writes them),
{os.path.getsize(out)} bytes; bounds [{b[0]:.4g}, {b[1]:.4g}] x [{b[2]:.4g}, {b[3]:.4g}] x
[{b[4]:.4g}, {b[5]:.4g}]; arrays: {arr_text}. Checks on the file as read back: max |x array - point
x| = {xdiff:.3e}; at {len(info['samples'])} random reference points (5 a cell) VTK's map and
interpolation against MFEM's own values: map {worst['X']:.2e}, u {worst['u']:.2e}, x
{worst['x']:.2e}, r2 {worst['r2']:.2e}. Runtime: MFEM half {info['mfem_seconds']:.1f} s, VTK half
{seconds:.1f} s, {total:.1f} s from the MFEM half's imports to the end (the venv check and
interpreter start-up not counted). `pip show mfem`: {info['pip_show']}. Regenerate with
`bash Scripts/make-mfem-hex.sh --out {out}` (from the repository root; it creates build/mfem-venv
and pip installs the pinned `mfem=={info['mfem_version']}`); the file is the same byte for byte on
every run.
"""
    import textwrap
    with open(path, "w") as f:
        f.write(f"# Provenance of {out}\n\n" + textwrap.fill(" ".join(text.split()), 100) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="Data/mfem_hex_q3.vtu")
    ap.add_argument("--elements", type=int, default=4, help="hexahedra per direction (N)")
    ap.add_argument("--keep", metavar="DIR", help="write MFEM's collection into DIR and keep it")
    ap.add_argument("--provenance", metavar="PATH", help="write a provenance paragraph to PATH")
    ap.add_argument("--vtk-half", metavar="DIR", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.vtk_half:
        vtk_half(args)
    else:
        mfem_half(args)


if __name__ == "__main__":
    main()
