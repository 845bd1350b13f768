"""The member loads that make YADE's clump sums exact (yade_mss._loads), checked without YADE."""
import unittest
from unittest import mock

import numpy as np

from yade_mss.yade import _loads
from yade_mss.yade import memberLoads, sumsAsYade, tiltedShares


def yadeSums(x, r, L):
    """YADE's discretization-0 sum over non-spherical members: member 0 carries the tensor V diag(j) V^T."""
    tensors = [L.V.dot(np.diag(L.j)).dot(L.V.T)] + [np.zeros((3, 3))] * (len(r) - 1)
    return sumsAsYade(x, r, L.m, tensors)


class Loads(unittest.TestCase):
    def test_random_clumps_are_exact(self):
        rng = np.random.default_rng(7)
        for n in (4, 10, 70):
            x = rng.normal(size=(n, 3))
            r = 0.3 + rng.random(n)
            M = 10 * rng.random() + 0.1
            C = x.mean(axis=0) + 0.1 * rng.normal(size=3)
            A = rng.normal(size=(3, 3))
            I = A.dot(A.T) + np.eye(3)
            L = memberLoads(x, r, M, C, I)
            Ms, Cs, Is = yadeSums(x, r, L)
            self.assertLess(abs(Ms - M) / M, 1e-13)
            self.assertLess(np.linalg.norm(Cs - C), 1e-12)
            self.assertLess(np.linalg.norm(Is - I) / np.linalg.norm(I), 1e-12)
            # the members keep positive shares adding up to the mass
            self.assertTrue(np.all(L.final > 0))
            self.assertAlmostEqual(L.final.sum() / M, 1.0, places=13)
            self.assertEqual(L.offset, 0.0)

    def test_balls_double_count_overlaps(self):
        # what YADE does with Sphere members: two unit balls one radius apart weigh 2 balls, not the union
        M, C, I = sumsAsYade([[0, 0, 0], [1, 0, 0]], [1, 1], None, None, density=1.0)
        self.assertAlmostEqual(M, 8 * np.pi / 3, places=12)

    def test_tilted_shares_outside_the_hull_are_not_positive(self):
        x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
        m, ok = tiltedShares(x, np.ones(4), 1.0, np.array([0.2, 0.2, 0.2]))
        self.assertTrue(ok)
        self.assertTrue(np.all(m > 0))
        np.testing.assert_allclose(m.dot(x), [0.2, 0.2, 0.2], atol=1e-12)
        m, ok = tiltedShares(x, np.ones(4), 1.0, np.array([2.0, 2.0, 2.0]))
        self.assertFalse(ok)
        # the exact masses then exist with mixed signs: the clump is still exact, members share evenly
        L = memberLoads(x, np.ones(4), 1.0, np.array([2.0, 2.0, 2.0]), np.eye(3))
        Ms, Cs, Is = yadeSums(x, np.ones(4), L)
        np.testing.assert_allclose(Cs, [2, 2, 2], atol=1e-12)
        self.assertTrue(np.all(L.final > 0))

    def test_tilted_shares_take_few_steps_inside_the_hull_and_out(self):
        # Newton's line search once halved its step ~40 times an iteration near the optimum, where f changes by
        # less than its rounding (up to 4734 evaluations of f on these draws; a split spent 36 ms on one piece)
        rng = np.random.default_rng(1)
        calls = [0]
        real = _loads._logsumexp

        def counted(z):
            calls[0] += 1
            return real(z)

        with mock.patch.object(_loads, '_logsumexp', counted):
            for trial in range(200):
                k = int(rng.integers(4, 30))
                x = rng.normal(size=(k, 3))
                r = 0.3 + rng.random(k)
                inside = trial % 2 == 0
                # inside: a mix of the centres with every share >= 1/(4k); else anywhere near them
                share = (1.0 + 3.0 * rng.random(k)) / 4.0
                C = (share / share.sum()).dot(x) if inside else x.mean(0) + 0.5 * rng.normal(size=3)
                calls[0] = 0
                m, ok = tiltedShares(x, r ** 3, 1.0, C)
                self.assertLessEqual(calls[0], 200)
                if inside:
                    self.assertTrue(ok)
                if ok:
                    self.assertTrue(np.all(m > 0))
                    np.testing.assert_allclose(m.dot(x), C, atol=1e-9)
                    self.assertAlmostEqual(m.sum(), 1.0, places=12)

    def test_centroid_off_the_line_of_collinear_spheres(self):
        x = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=float)
        L = memberLoads(x, np.ones(3), 3.0, np.array([1.0, 0.5, 0.0]), np.eye(3))
        self.assertAlmostEqual(L.offset, 0.5, places=12)  # the nearest point of the line is taken
        np.testing.assert_allclose(L.centroid, [1, 0, 0], atol=1e-12)
        Ms, Cs, Is = yadeSums(x, np.ones(3), L)
        np.testing.assert_allclose(Is, np.eye(3), atol=1e-12)  # the tensor is still exact

    def test_bad_mass(self):
        with self.assertRaises(ValueError):
            memberLoads([[0, 0, 0]], [1], 0.0, [0, 0, 0], np.eye(3))


if __name__ == '__main__':
    unittest.main()


class TakenCheck(unittest.TestCase):
    """_checkMany: what YADE's sums gave a clump against what was asked, with its tolerances (the check that
    refuses a clump YADE did not take exactly)."""

    class State(object):
        def __init__(self, mass, pos, inertia):
            self.mass, self.pos, self.inertia = mass, pos, inertia

    def check(self, mass=2.0, pos=(1.0, 2.0, 3.0), inertia=(3.0, 1.0, 2.0)):
        import numpy as np
        from yade_mss.yade._clumps import _checkMany
        _checkMany('f', [7], [self.State(mass, pos, inertia)], np.array([2.0]), np.array([[1.0, 2.0, 3.0]]),
                   np.array([[1.0, 2.0, 3.0]]))

    def test_what_was_asked_passes_in_any_order_of_the_moments(self):
        self.check()
        self.check(mass=2.0 * (1 + 1e-10), pos=(1.0 + 1e-10, 2.0, 3.0))  # within the tolerances

    def test_a_wrong_mass_centre_or_moment_is_refused_naming_the_clump(self):
        for kw in (dict(mass=2.1), dict(pos=(1.0, 2.0, 3.1)), dict(inertia=(3.0, 1.0, 2.5))):
            with self.subTest(**kw):
                with self.assertRaisesRegex(RuntimeError, 'f: YADE did not take the requested mass properties of '
                                                          'clump 7'):
                    self.check(**kw)
