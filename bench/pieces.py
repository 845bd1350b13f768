"""What a fragment's resolution buys: pieces of six shared meshes (cube, ellipsoid 2:1:1, femur, octahedron, torus,
bunny), each cut through its centroid by 3 planes of random normals (fixed seed), both sides, with 6, 10 and 20
spheres, generated as mssSplit generates a piece (its in-memory mesh, the cut plane as a constraint, the
one-voxel protrusion bound) at resolutions 30, 40, 50 and 60 voxels along the piece's shortest edge. D is scored
on an independent grid (mss compare's: 100 voxels along the shortest edge, offset 0.37); the protrusion bound is
one voxel of the piece's grid, so a coarser grid allows larger bumps (a fraction 1/resolution of the piece's
shortest edge); a last run at resolution 50 takes the bound of a voxel at 40 (maxProtrusion = the piece's
shortest bounding-box edge / 40), to compare 40 and 50 at the same bumps. Times: the generation's, in process,
one thread, the best of two. Prints the mean D and time per run and their change against resolution 50, and
appends a row a run to bench/results/pieces.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/pieces.py"""
import os
import sys
import time
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402

import numpy as np  # noqa: E402

import yade_mss  # noqa: E402
from yade_mss import _mss  # noqa: E402

DATA = os.path.join(HERE, '..', 'tests', 'data')
MESHES = ['human_femur', 'ellipsoid_2_1_1', 'torus', 'stanford_bunny_open', 'cube', 'octahedron']
RUNS = ((30, None), (40, None), (50, None), (60, None), (50, 40))  # (resolution, bound: a voxel at; None: its own)
COUNTS = (6, 10, 20)


def pieces():
    """(grain, mesh (vertices, triangles), plane (point, normal)) of every piece, the same at every resolution."""
    rng = np.random.default_rng(5)
    out = []
    for name in MESHES:
        v, t = _mss.readMesh(os.path.join(DATA, name + '.stl'))
        c = np.reshape(v, (-1, 3)).mean(axis=0)
        for _ in range(3):
            n = rng.normal(size=3)
            cut = _mss.splitMesh(v, t, list(c) + list(n))
            for side, sign in (('above', 1.0), ('below', -1.0)):
                for d in cut[side]:
                    mesh = (np.frombuffer(d['vertices']).reshape(-1, 3),
                            np.frombuffer(d['triangles'], dtype=np.int32).reshape(-1, 3))
                    out.append((name, mesh, (tuple(c), tuple(sign * n))))
    return out


def main():
    warnings.simplefilter('ignore')  # the bunny is open: each generation warns
    cases = pieces()
    table = {}
    for res, at in RUNS:
        D, T = [], []
        for name, mesh, plane in cases:
            bound = {} if at is None else {'maxProtrusion': float(np.ptp(mesh[0], axis=0).min()) / at}
            for n in COUNTS:
                best = float('inf')
                for _ in range(2):
                    t0 = time.perf_counter()
                    r = yade_mss.generate(mesh, nSpheres=n, resolution=res, planes=[plane], threads=1, **bound)
                    best = min(best, time.perf_counter() - t0)
                D.append(yade_mss.score(mesh, r, resolution=100, planes=[plane])['dice'])
                T.append(best)
        table[res, at] = (np.array(D), np.array(T))
    ref = table[50, None]
    rows = []
    print('%d pieces x %d counts; D on an independent grid (100 voxels), generation one thread'
          % (len(cases), len(COUNTS)))
    print('%10s %16s %10s %16s %12s %14s' % ('resolution', 'bound', 'mean D', 'D vs 50 (mean)', 'mean ms',
                                             'time vs 50'))
    for res, at in RUNS:
        D, T = table[res, at]
        change = float(np.mean(D / ref[0] - 1))
        ratio = float(np.median(T / ref[1]))
        bound = 'a voxel' if at is None else 'a voxel at %d' % at
        print('%10d %16s %10.4f %+15.2f%% %12.1f %13.2fx' % (res, bound, D.mean(), 100 * change, 1000 * T.mean(),
                                                            ratio))
        rows.append([res, bound, len(D), '%.5f' % D.mean(), '%.4f' % change, '%.2f' % (1000 * T.mean()),
                     '%.3f' % ratio])
    appendRows('pieces.csv', ['resolution', 'bound', 'cases', 'mean_dice', 'dice_change_vs_50', 'mean_ms',
                              'time_ratio_vs_50'], rows)


main()
