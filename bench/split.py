"""What a split costs inside a YADE scene (mssSplit: cut, generate each piece from its in-memory mesh, build the
clumps): breakable clumps of the ellipsoid and the femur cut through their centre of mass by planes of random
normals (fixed seed), at piece resolutions 30, 40, 50 and 60 (the target: 20 ms a piece at the default
resolution, 40); per piece (the pieces are generated side by side, one per core): each plane's split is made
REPEATS times on a fresh scene and its fastest kept (what it costs on an idle machine: the same split on this
shared machine varies by up to 2x), then the median, least and most over PLANES planes. Beside it, the in-process generation
alone at the same grids (one piece, best of 5), with and without the cut plane as a constraint. Prints a table
and appends a row a case to bench/results/split.csv.
Run: PYTHONPATH=build/py yade -n -x bench/split.py"""
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(sys.argv[-1] if sys.argv[-1].endswith('split.py') else 'bench/split.py'))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402

from yade import utils  # noqa: E402,F401
from yade.wrapper import FrictMat, Omega  # noqa: E402
import yade.minieigenHP as me  # noqa: E402,F401

import yade_mss  # noqa: E402
from yade_mss import _mss, mssClump, mssSplit  # noqa: E402

O = Omega()
DATA = os.path.join(HERE, '..', 'tests', 'data')


PLANES, REPEATS = 9, 3


def splits(path, n, resolution, rng):
    """Median, least and most over PLANES planes of each plane's fastest split of REPEATS (ms per piece)."""
    per = []
    for _ in range(PLANES):
        normal = rng.normal(size=3)
        best = float('inf')
        for _ in range(REPEATS):
            O.reset()
            mat = O.materials.append(FrictMat(density=2000))
            cid, ids = mssClump(path, nSpheres=n, resolution=50, breakable=True, material=mat)
            t0 = time.perf_counter()
            made = mssSplit(cid, (O.bodies[cid].state.pos, normal), resolution=resolution)
            best = min(best, 1000 * (time.perf_counter() - t0) / len(made))
        per.append(best)
    return float(np.median(per)), float(min(per)), float(max(per))


def generation(path, resolution, planes):
    v, t = _mss.readMesh(path)
    V = np.reshape(v, (-1, 3))
    c = list(V.mean(axis=0))
    cut = _mss.splitMesh(v, t, c + [1.0, 0.3, 0.2])
    m = cut['above'][0]
    mesh = (np.frombuffer(m['vertices']).reshape(-1, 3), np.frombuffer(m['triangles'], dtype=np.int32).reshape(-1, 3))
    ts = []
    for _ in range(5):
        t0 = time.perf_counter()
        r = yade_mss.generate(mesh, nSpheres=15, resolution=resolution,
                              planes=[(tuple(c), (1.0, 0.3, 0.2))] if planes else ())
        ts.append(time.perf_counter() - t0)
    return 1000 * min(ts), int(np.prod(r.grid['dims']))


def main():
    rng = np.random.default_rng(11)
    rows = []
    print('OMP_WAIT_POLICY=%s' % os.environ.get('OMP_WAIT_POLICY'))
    print('%-10s %7s %10s %14s %12s %14s %14s %10s' % ('grain', 'spheres', 'resolution', 'split ms/piece',
                                                      '(min-max)', 'generate ms', '+ plane ms', 'voxels'))
    for name, n in (('ellipsoid_2_1_1.stl', 20), ('human_femur.stl', 30)):
        path = os.path.join(DATA, name)
        for res in (30, 40, 50, 60):
            med, lo, hi = splits(path, n, res, rng)
            g0, vox = generation(path, res, False)
            g1, vox = generation(path, res, True)
            rows.append([name, n, res, med, lo, hi, g0, g1, vox, REPEATS])
            print('%-10s %7d %10d %14.1f %12s %14.1f %14.1f %10d' % (name[:10], n, res, med, '%.0f-%.0f' % (lo, hi),
                                                                      g0, g1, vox))
    appendRows('split.csv', ['grain', 'parent_spheres', 'resolution', 'split_ms_per_piece', 'split_min_ms',
                             'split_max_ms', 'generate_ms', 'generate_plane_ms', 'piece_voxels', 'repeats_per_plane'],
               rows)


main()
