"""The clump's surface (mss surface) and the exact score (mss compare --exact) on the femur's 70 spheres and the
axis-aligned tetrahedron's 30: triangles, the mesh's volume error against the union's exact volume, and time;
D on the exact shapes with its standard error against the grid's at three offsets, and time. Prints a table and
appends a row a case to bench/results/shapes.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/shapes.py"""
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402
from fidelity import tetrahedron  # noqa: E402

import numpy as np  # noqa: E402

import yade_mss  # noqa: E402

DATA = os.path.join(HERE, '..', 'tests', 'data')


def best(f, k=3):
    out, t = None, float('inf')
    for _ in range(k):
        t0 = time.perf_counter()
        out = f()
        t = min(t, time.perf_counter() - t0)
    return out, t


def main():
    rows = []
    with tempfile.TemporaryDirectory() as d:
        tet = os.path.join(d, 'tetrahedron.stl')
        tetrahedron(tet, np.eye(3))
        for name, grain, n in (('femur', os.path.join(DATA, 'human_femur.stl'), 70), ('tetrahedron', tet, 30)):
            r = yade_mss.generate(grain, nSpheres=n)
            s, ts = best(lambda: r.surface())
            grid = [yade_mss.score(grain, r, offset=o)['dice'] for o in (0.0, 0.37, 0.5)]
            e, te = best(lambda: yade_mss.score(grain, r, exact=True)['exact'])
            rows.append([name, n, len(s.triangles), s.volume / s.unionVolume - 1, ts, e['dice'], e['diceError'],
                         e['samples'], te] + grid)
    print('%-12s %4s %9s %9s %7s %9s %8s %7s %s' % ('grain', 'n', 'triangles', 'vol.err', 'surf s', 'D exact',
                                                    '+- se', 'exact s', 'grid D at offsets 0 / 0.37 / 0.5'))
    for r in rows:
        print('%-12s %4d %9d %9.5f %7.2f %9.5f %8.5f %7.2f %s' % (tuple(r[:5]) + (r[5], r[6], r[8])
                                                                  + (' / '.join('%.4f' % g for g in r[9:]),)))
    appendRows('shapes.csv', ['grain', 'spheres', 'triangles', 'volume_error', 'surface_s', 'dice_exact',
                              'dice_exact_se', 'samples', 'exact_s', 'dice_grid_0', 'dice_grid_0.37', 'dice_grid_0.5'],
               rows, fmt='%.6g')


if __name__ == '__main__':
    main()
