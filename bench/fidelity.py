#!/usr/bin/python3
"""Fidelity figures, through the mss command line, scored on an independent grid (mss compare:
100 voxels along the shortest edge, offset 0.37 voxel):

1. the regular tetrahedron inscribed in [-1/2, 1/2]^3 at 30 spheres in several orientations (axis-aligned,
   0.5 and 10 degrees about z, four seeded random rotations), bounded (the default) and unbounded;
2. the shared octahedron at 30 spheres over resolutions 97-110;
3. problem (ii): --dice X on the femur (resolution 103): its count against the fewest with which a run at a
   fixed count meets X, and its time against a run at its own count (median of 5, alternating); the rows go to
   bench/results/problem_two.csv.

usage: bench/fidelity.py [--quick]   (build first: scripts/setup.sh; MSS_BINARY overrides ./build/mss)
"""
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from batch_scale import appendRows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MSS = os.environ.get('MSS_BINARY', os.path.join(ROOT, 'build', 'mss'))
DATA = os.path.join(ROOT, 'tests', 'data')


def run(*args):
    """mss with these arguments: its output lines as {first word: the rest}; its own message if it fails."""
    p = subprocess.run([MSS] + [str(a) for a in args], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError('mss %s: %s' % (' '.join(str(a) for a in args), p.stderr.strip() or p.stdout.strip()))
    return {line.split()[0]: line.split()[1:] for line in p.stdout.splitlines() if line.strip()}


def generate(mesh, out, *opts):
    g = run('generate', mesh, '-o', out, *opts)
    return {'dice': float(g['dice'][0]), 'spheres': int(g['spheres'][0]), 'h': float(g['grid'][-1]),
            'seconds': float(g['seconds'][-1])}


def scored(mesh, spheres):
    c = run('compare', mesh, spheres)
    return float(c['dice'][0]), float(c['protrusion'][0])


def tetrahedron(path, R):
    V = np.array([[.5, .5, .5], [.5, -.5, -.5], [-.5, .5, -.5], [-.5, -.5, .5]]) @ R.T
    with open(path, 'w') as f:
        f.write('solid t\n')
        for a, b, c in ((0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)):
            n = np.cross(V[b] - V[a], V[c] - V[a])
            f.write('facet normal %r %r %r\nouter loop\n' % tuple(n / np.linalg.norm(n)))
            for k in (a, b, c):
                f.write('vertex %r %r %r\n' % tuple(V[k]))
            f.write('endloop\nendfacet\n')
        f.write('endsolid t\n')


def rotation(axis, deg):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    t = np.radians(deg)
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def randomRotation(rng):
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def orientations(tmp):
    print('1. tetrahedron, 30 spheres, resolution 103 (bar: D <= 0.09 in every orientation, worst <= 1.25 x best)')
    print('%-16s %10s %10s %10s %10s' % ('orientation', 'D bounded', 'prot/vox', 'D unbound', 'prot/vox'))
    rng = np.random.default_rng(1)
    turns = [('axis-aligned', np.eye(3)), ('0.5 deg about z', rotation([0, 0, 1], 0.5)),
             ('10 deg about z', rotation([0, 0, 1], 10))] + [('random %d' % i, randomRotation(rng)) for i in range(4)]
    cols = {'bounded': [], 'unbounded': []}
    for name, R in turns:
        mesh = os.path.join(tmp, 'tet.stl')
        tetrahedron(mesh, R)
        row = []
        for mode, extra in (('bounded', ()), ('unbounded', ('--max-protrusion', 'inf'))):
            g = generate(mesh, os.path.join(tmp, 's.csv'), '--spheres', 30, '--resolution', 103, *extra)
            d, p = scored(mesh, os.path.join(tmp, 's.csv'))
            cols[mode].append(d)
            row += [d, p / g['h']]
        print('%-16s %10.4f %10.2f %10.4f %10.2f' % (name, *row))
    for mode, d in cols.items():
        print('%-9s worst %.4f best %.4f ratio %.3f' % (mode, max(d), min(d), max(d) / min(d)))


def resolutions(tmp, quick):
    print('\n2. octahedron, 30 spheres, resolutions 97-110 (bar: D <= 0.06, worst <= 1.3 x best)')
    mesh = os.path.join(DATA, 'octahedron.stl')
    ds = []
    for n in range(97, 111, 3 if quick else 1):
        generate(mesh, os.path.join(tmp, 's.csv'), '--spheres', 30, '--resolution', n)
        ds.append(scored(mesh, os.path.join(tmp, 's.csv'))[0])
        print('resolution %3d D %.4f' % (n, ds[-1]))
    print('worst %.4f best %.4f ratio %.3f' % (max(ds), min(ds), max(ds) / min(ds)))


def median(mesh, out, *opts):
    runs = [generate(mesh, out, *opts) for _ in range(3)]
    return runs[0], statistics.median(r['seconds'] for r in runs)


def problemTwo(tmp, quick):
    """Rows (target, spheres, D, seconds, seconds at the same count, fewest) of bench/results/problem_two.csv."""
    print('\n3. problem (ii): femur, resolution 103 (bars: at most 10% (+1) over the fewest, time <= 2x one run at'
          ' the final count)')
    print('%6s %8s %9s %8s %12s %7s %8s' % ('target', 'spheres', 'D', 'seconds', 'seconds(n)', 'ratio', 'fewest'))
    mesh = os.path.join(DATA, 'human_femur.stl')
    out = os.path.join(tmp, 's.csv')
    rows = []
    for target in ((0.05,) if quick else (0.05, 0.04, 0.03)):
        # the two runs alternate, so that a change of load falls on both; median of 5 of each
        grow, fixed = [], []
        for _ in range(5):
            g = generate(mesh, out, '--dice', target, '--resolution', 103)
            grow.append(g['seconds'])
            fixed.append(generate(mesh, out, '--spheres', g['spheres'], '--resolution', 103)['seconds'])
        t, tn = statistics.median(grow), statistics.median(fixed)
        # the fewest count from which every fixed count up to the result's (and one beyond) meets the target
        n = max(g['spheres'], 1)
        while generate(mesh, out, '--spheres', n, '--resolution', 103)['dice'] > target:
            n += 1
        fewest = n
        while fewest > 1 and generate(mesh, out, '--spheres', fewest - 1, '--resolution', 103)['dice'] <= target:
            fewest -= 1
        print('%6.3f %8d %9.5f %8.3f %12.3f %7.2f %8d' % (target, g['spheres'], g['dice'], t, tn, t / tn, fewest))
        rows.append((target, g['spheres'], g['dice'], t, tn, fewest))
    return rows


def save(rows):
    appendRows('problem_two.csv', ['grain', 'resolution', 'target', 'spheres', 'dice', 'seconds',
                                   'seconds_fixed_same_count', 'ratio', 'fewest_fixed_count'],
               [['femur', 103, target, n, '%.5f' % d, '%.3f' % t, '%.3f' % tn, '%.2f' % (t / tn), fewest]
                for target, n, d, t, tn, fewest in rows])


def main():
    quick = '--quick' in sys.argv
    print('load: %s' % open('/proc/loadavg').read().strip())
    with tempfile.TemporaryDirectory() as tmp:
        orientations(tmp)
        resolutions(tmp, quick)
        save(problemTwo(tmp, quick))


if __name__ == '__main__':
    main()
