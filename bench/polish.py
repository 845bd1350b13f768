"""The joint polish (generate(polish=True), mss generate --polish): D with and without it on every shared mesh,
the CT grain and the tetrahedron in four orientations, at 10, 30 and 70 spheres, bounded (the default one-voxel
bound), unbounded and clipped, at resolution 103 (the CT grain on its own voxels). D is scored on an independent
grid (mss compare's: 100 voxels along the shortest edge, offset 0.37); times are the generation's, in process,
the best of two. Prints every case, won or lost, and the mean change where the polish is kept, and appends a
row a case to bench/results/polish.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/polish.py [--quick]   (--quick: 30 spheres, bounded only)"""
import math
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402
from fidelity import randomRotation, tetrahedron  # noqa: E402

import numpy as np  # noqa: E402

import yade_mss  # noqa: E402

DATA = os.path.join(HERE, '..', 'tests', 'data')
MESHES = ['cube', 'ellipsoid_2_1_1', 'human_femur', 'octahedron', 'sphere_r1', 'stanford_bunny_open', 'torus']
MODES = {'bounded': {}, 'unbounded': {'maxProtrusion': math.inf}, 'clipped': {'clip': True}}


def grains(tmp):
    out = [(m, os.path.join(DATA, m + '.stl'), {'resolution': 103}) for m in MESHES]
    rng = np.random.default_rng(1)
    for name, R in [('tetrahedron', np.eye(3))] + [('tetrahedron r%d' % i, randomRotation(rng)) for i in range(3)]:
        path = os.path.join(tmp, name.replace(' ', '_') + '.stl')
        tetrahedron(path, R)
        out.append((name, path, {'resolution': 103}))
    ct = np.load(os.path.join(DATA, 'grain_voxels_155x157x167.npy'))
    out.append(('CT grain', ct, {}))
    return out


def timed(grain, **kw):
    best, r = math.inf, None
    for _ in range(2):
        t = time.perf_counter()
        r = yade_mss.generate(grain, **kw)
        best = min(best, time.perf_counter() - t)
    return r, best


def main():
    quick = '--quick' in sys.argv
    counts = [30] if quick else [10, 30, 70]
    modes = ['bounded'] if quick else list(MODES)
    rows, changes = [], {m: [] for m in modes}
    print('%-20s %3s %-9s %9s %9s %7s %8s %8s %6s' % ('grain', 'n', 'mode', 'D', 'D polish', 'change', 't/s',
                                                     't polish', 'ratio'))
    with tempfile.TemporaryDirectory() as tmp:
        for name, grain, extra in grains(tmp):
            for n in counts:
                for mode in modes:
                    kw = dict(extra, nSpheres=n, **MODES[mode])
                    try:
                        plain, t0 = timed(grain, **kw)
                        polished, t1 = timed(grain, polish=True, **kw)
                    except ValueError as e:  # a count or bound the grain cannot take (printed, not hidden)
                        print('%-20s %3d %-9s refused: %s' % (name, n, mode, e))
                        continue
                    d0 = yade_mss.score(grain, plain)['dice']
                    d1 = yade_mss.score(grain, polished)['dice']
                    change = d1 / d0 - 1
                    changes[mode].append(change)
                    print('%-20s %3d %-9s %9.5f %9.5f %+6.1f%% %8.3f %8.3f %6.2f' % (
                        name, n, mode, d0, d1, 100 * change, t0, t1, t1 / t0), flush=True)
                    rows.append([name, n, mode, '%.6f' % d0, '%.6f' % d1, '%.4f' % change, '%.4f' % t0,
                                 '%.4f' % t1, plain.metrics['dice'], polished.metrics['dice']])
    for mode, c in changes.items():
        if c:
            won = [x for x in c if x < 0]
            print('%-9s mean change %+.2f%% over %d cases; won %d (mean %+.2f%%), worse on the independent grid %d'
                  % (mode, 100 * np.mean(c), len(c), len(won), 100 * np.mean(won) if won else 0.0,
                     sum(x > 0 for x in c)))
    out = appendRows('polish.csv', ['grain', 'spheres', 'mode', 'dice', 'dice_polish', 'change', 'seconds',
                                    'seconds_polish', 'grid_dice', 'grid_dice_polish'], rows, fmt=None)
    print('wrote', out)


if __name__ == '__main__':
    main()
