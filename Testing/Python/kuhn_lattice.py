"""The tests' lattice of quadratic tetrahedra (numpy only, for both routes, the fuzzers and the
benchmarks): a box as n^3 cubes, each cut along its main diagonal into Kuhn's 6 tetrahedra (tet p
walks from the cube's lowest corner along the axes in the order of permutation p), with mid-edge
nodes, in VTK_QUADRATIC_TETRA's node order; nodes are shared. The C++ tests' twin is
Testing/Core/LatticeMesh.h (forEachKuhnTet).
"""
import itertools

import numpy as np

# Vertex pairs of the six edges, in the order of VTK_QUADRATIC_TETRA's mid-edge nodes.
EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
# The axis orders of the 6 tets of a cube, and whether each is an odd permutation (that tet has
# negative volume unless vertices 1 and 2 are swapped).
PATHS = list(itertools.permutations(range(3)))
ODD = [sum(path[a] > path[b] for a, b in itertools.combinations(range(3), 2)) % 2 == 1
       for path in PATHS]


def kuhn_vertices(cubes, step=1, oriented=True):
    """Kuhn's walk, the one in the Python tests: for cubes (c, 3) of integer lowest corners (in
    units of `step`), the 4 vertices of each of a cube's 6 tets, a list over PATHS of 4 (c, 3)
    arrays: from step * corner along the axes in the path's order. oriented: vertices 1 and 2
    swapped in the odd paths' tets, so that every tet has positive volume."""
    walks = []
    for p, path in enumerate(PATHS):
        v = [step * cubes]
        for axis in path:
            nxt = v[-1].copy()
            nxt[:, axis] += step
            v.append(nxt)
        if oriented and ODD[p]:
            v[1], v[2] = v[2], v[1]
        walks.append(v)
    return walks


def kuhn_tets(n):
    """The n^3 cubes of [0, n]^3 (z fastest) as 6 positively oriented tets each: (6 n^3, 4, 3)
    integer vertices, a cube's tets in PATHS' order."""
    cubes = np.indices((n, n, n), dtype=np.int64).reshape(3, -1).T
    walks = np.array(kuhn_vertices(cubes))  # (6 paths, 4 vertices, cubes, 3)
    return walks.transpose(2, 0, 1, 3).reshape(-1, 4, 3)


def kuhn_quadratic_tets(n, x_fastest=False, oriented=True):
    """The lattice's topology on the half-step grid of m = 2 n + 1 nodes per axis.

    Returns keys (m^3, 3), the integer grid coordinates (0 .. 2 n) of point id 0, 1, ..., and
    cells (6 n^3, 10) int64 point ids. Point ids and cubes run with z fastest (id = (i m + j) m +
    k, cubes i, j, k), or with x_fastest with x fastest (id = i + m (j + m k), cubes k, j, i:
    tetdsr_benchmark.cxx's order); a cube's 6 tets in PATHS' order. oriented: every tet positively
    oriented (vertices 1 and 2 swapped in the odd ones); else as walked, half of them inverted.
    """
    m = 2 * n + 1
    cubes = np.indices((n, n, n), dtype=np.int64).reshape(3, -1).T
    keys = np.indices((m, m, m), dtype=np.int64).reshape(3, -1).T
    if x_fastest:  # (the last index runs fastest: read it as x)
        cubes, keys = cubes[:, ::-1], keys[:, ::-1]
    nodes = np.empty((len(cubes), len(PATHS), 10, 3), dtype=np.int64)
    for p, v in enumerate(kuhn_vertices(cubes, 2, oriented)):
        nodes[:, p] = np.stack(v + [(v[a] + v[b]) // 2 for a, b in EDGES], axis=1)
    if x_fastest:
        ids = nodes[..., 0] + m * (nodes[..., 1] + m * nodes[..., 2])
    else:
        ids = (nodes[..., 0] * m + nodes[..., 1]) * m + nodes[..., 2]
    return keys, ids.reshape(-1, 10)


def lattice(n, lo=-1.0, hi=1.0, oriented=True):
    """[lo, hi]^3 as n^3 cubes of 6 quadratic tets: points (an (m^3, 3) array, m = 2n + 1,
    np.linspace(lo, hi, m) on each axis, z fastest) and cells (a (6 n^3, 10) int64 array);
    oriented as kuhn_quadratic_tets."""
    keys, cells = kuhn_quadratic_tets(n, oriented=oriented)
    return np.linspace(lo, hi, 2 * n + 1)[keys], cells
