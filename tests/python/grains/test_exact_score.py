"""mss compare --exact and score(exact=True): the Monte Carlo score on the exact shapes against an independent
Monte Carlo written here with numpy (other points, other generator), on the axis-aligned tetrahedron whose flat
faces lie on lattice planes, where the grid score is biased."""
import os
import subprocess
import tempfile
import unittest

import numpy as np

import yade_mss

MSS = os.environ.get('MSS_BINARY', 'mss')
V = np.array([[.5, .5, .5], [.5, -.5, -.5], [-.5, .5, -.5], [-.5, -.5, .5]])  # inscribed in the unit cube
FACES = ((0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2))


def writeTetrahedron(path):
    with open(path, 'w') as f:
        f.write('solid t\n')
        for a, b, c in FACES:
            n = np.cross(V[b] - V[a], V[c] - V[a])
            f.write('facet normal %r %r %r\nouter loop\n' % tuple(n / np.linalg.norm(n)))
            for k in (a, b, c):
                f.write('vertex %r %r %r\n' % tuple(V[k]))
            f.write('endloop\nendfacet\n')
        f.write('endsolid t\n')


def independentDice(centers, radii, n=1000000, seed=12345):
    """D (eq. 27) of the tetrahedron and the spheres by numpy's own points: the tetrahedron by its four
    half-spaces, the spheres by their distances; the delta method's standard error."""
    rng = np.random.default_rng(seed)
    lo = np.minimum(V.min(axis=0), (centers - radii[:, None]).min(axis=0))
    hi = np.maximum(V.max(axis=0), (centers + radii[:, None]).max(axis=0))
    a = b = None
    for chunk in range(10):
        p = lo + rng.random((n // 10, 3)) * (hi - lo)
        inT = np.ones(len(p), bool)
        for i, j, k in FACES:
            nrm = np.cross(V[j] - V[i], V[k] - V[i])  # outward
            inT &= (p - V[i]) @ nrm <= 0
        inS = np.zeros(len(p), bool)
        for c, r in zip(centers, radii):
            inS |= ((p - c) ** 2).sum(axis=1) < r * r
        a = inT if a is None else np.concatenate([a, inT])
        b = inS if b is None else np.concatenate([b, inS])
    x, y = (a ^ b).astype(float), a.astype(float) + b
    D = x.mean() / y.mean()
    return D, (x - D * y).std() / np.sqrt(len(x)) / y.mean()


class ExactScore(unittest.TestCase):
    def test_tetrahedron_within_two_standard_errors_of_an_independent_monte_carlo(self):
        with tempfile.TemporaryDirectory() as d:
            tet, out = os.path.join(d, 'tet.stl'), os.path.join(d, 'tet30.csv')
            writeTetrahedron(tet)
            r = yade_mss.generate(tet, nSpheres=30)
            r.save(out)
            p = subprocess.run([MSS, 'compare', tet, out, '--exact'], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = {l.split()[0]: l.split()[1:] for l in p.stdout.splitlines() if l.split()}
            grid = [float(subprocess.run([MSS, 'compare', tet, out, '--offset', o], capture_output=True, text=True,
                                         timeout=600).stdout.split('dice')[1].split()[0]) for o in ('0', '0.37', '0.5')]
            s = yade_mss.score(tet, r, exact=True)
        D, se = float(rows['dice_exact'][0]), float(rows['dice_exact'][2])
        self.assertEqual(rows['dice_exact'][1], '+-')
        Dn, sen = independentDice(r.centers, r.radii)
        print('tetrahedron, 30 spheres: exact D %.5f +- %.5f (mss), %.5f +- %.5f (numpy); grid D %s at offsets '
              '0 / 0.37 / 0.5' % (D, se, Dn, sen, ' / '.join('%.4f' % g for g in grid)))
        self.assertLess(abs(D - Dn), 2 * np.hypot(se, sen))
        self.assertLess(se, 0.002)
        # the grid's figure moves with its offset; the exact one does not depend on a lattice
        self.assertGreater(max(grid) - min(grid), 4 * se)
        # the Python face gives the same figures
        self.assertEqual(s['exact']['samples'], 1000000)
        self.assertAlmostEqual(s['exact']['dice'], D, delta=1e-5)
        self.assertAlmostEqual(s['exact']['targetVolume'], 1 / 3, delta=4 * s['exact']['targetVolumeError'])

    def test_options_are_checked(self):
        with tempfile.TemporaryDirectory() as d:
            tet = os.path.join(d, 'tet.stl')
            writeTetrahedron(tet)
            r = yade_mss.generate(tet, nSpheres=5)
            with self.assertRaises(ValueError):
                yade_mss.score(tet, r, exact=True, samples=10)
            with self.assertRaises(ValueError):
                yade_mss.score(tet, r, exact=True, seed=-1)
            with self.assertRaises(ValueError):
                yade_mss.score(tet, r, exact=True, samples=1.5)
            rows = yade_mss.compareMany(tet, [r], exact=True, samples=20000, seed=4)
            self.assertEqual(rows[0]['exact']['seed'], 4)
            self.assertNotIn('exact', yade_mss.compareMany(tet, [r])[0])
            csv = os.path.join(d, 'rows.csv')
            out = os.path.join(d, 'r.csv')
            r.save(out)
            p = subprocess.run([MSS, 'compare', tet, out, out, '--exact', '--samples', '20000', '--csv', csv],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn('D_exact +- se', p.stdout)
            with open(csv) as f:
                head, first = f.readline().strip().split(','), f.readline().strip().split(',')
            self.assertEqual(head[-3:], ['dice_exact', 'dice_exact_se', 'error'])
            self.assertEqual(len(first), len(head))
            p = subprocess.run([MSS, 'compare', tet, out, '--exact', '--samples', '10'], capture_output=True,
                               text=True, timeout=600)
            self.assertEqual(p.returncode, 1)
            self.assertIn('--samples', p.stderr)


if __name__ == '__main__':
    unittest.main()
