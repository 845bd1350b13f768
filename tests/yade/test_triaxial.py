"""The triaxial test in real YADE at a small size: the records against the derived figures, the stress at the start
of shearing, the drained and undrained paths, Ctrl-C and resume, bad options named.
Run: yade -n -x tests/yade/test_triaxial.py"""
import math
import os
import shutil
import sys
import tempfile
import unittest

import numpy as np

from yade.wrapper import Omega

from yade_mss import mssTemplate, porosity
from yade_mss.studies import derived, mobilized, placements, triaxial

O = Omega()
DATA = os.environ.get('MSS_TEST_DATA', os.path.join('tests', 'data'))
GRAIN = os.path.join(DATA, 'grain_voxels_155x157x167.npy')
P0 = 1e5
# small: 16 grains of 5 spheres, 1 % axial strain, 40 records (about 10 s each run)
SMALL = dict(grains=16, strain=0.01, records=40, confining=P0, seed=3)
TEMPLATE = []


def template():
    if not TEMPLATE:
        TEMPLATE.append(mssTemplate(GRAIN, nSpheres=5, voxelSize=1.25e-5))
    return TEMPLATE[0]


class Drained(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        O.reset()
        cls.r = triaxial([template()], **SMALL)
        cls.porosity = porosity()

    def test_shearing_starts_at_the_confining_pressure(self):
        first = self.r.records[0]
        self.assertEqual(first['axial_strain'], 0.0)
        # the compaction is done within 1 % of p0 (COMPACTION_STRESS_TOL); the axial and lateral stresses too,
        # to 3 % (16 grains: the stress tensor is not isotropic to better than that)
        self.assertAlmostEqual(first['p_Pa'] / P0, 1.0, delta=0.011)
        self.assertAlmostEqual(first['sigma_axial_Pa'] / P0, 1.0, delta=0.03)
        self.assertAlmostEqual(first['sigma_lateral_Pa'] / P0, 1.0, delta=0.03)
        self.assertLess(abs(first['q_Pa']) / P0, 0.05)

    def test_drained_holds_the_lateral_stress(self):
        lateral = np.array([r['sigma_lateral_Pa'] for r in self.r.records])
        self.assertLess(np.max(np.abs(lateral / P0 - 1)), 0.03)
        # and the axial stress rises: the specimen carries the load
        self.assertGreater(max(r['q_Pa'] for r in self.r.records), 0.3 * P0)

    def test_the_strain_goal_is_reached_in_order(self):
        a = [r['axial_strain'] for r in self.r.records]
        self.assertTrue(all(y > x for x, y in zip(a, a[1:])))
        self.assertGreaterEqual(a[-1], SMALL['strain'])
        self.assertLess(a[-1], SMALL['strain'] * 1.1)
        self.assertGreaterEqual(len(a), SMALL['records'])

    def test_the_peak_angle_is_the_curves(self):
        rows = self.r.records
        s1 = np.array([r['sigma_axial_Pa'] for r in rows])
        s3 = np.array([r['sigma_lateral_Pa'] for r in rows])
        # independently: Mohr-Coulomb's sin(phi) = (s1 - s3) / (s1 + s3) at each record, the largest
        phi = np.degrees(np.arcsin((s1 - s3) / (s1 + s3)))
        self.assertAlmostEqual(self.r.derived['phi_peak_deg'], phi.max(), places=9)
        # and from the largest q/p, as a triaxial lab reads it: sin(phi) = 3 eta / (6 + eta) (rounding only)
        eta = max(r['q_over_p'] for r in rows)
        self.assertAlmostEqual(self.r.derived['phi_peak_deg'], math.degrees(math.asin(3 * eta / (6 + eta))),
                               delta=1e-9)
        # the principal stresses bound the axial and lateral ones (the cell's shear stresses only widen them)
        for r in rows:
            self.assertGreaterEqual(r['sigma1_Pa'], r['sigma_axial_Pa'] - 1e-6 * P0)
            self.assertLessEqual(r['sigma3_Pa'], min(r['sigma_lateral_Pa'], r['sigma_axial_Pa']) + 1e-6 * P0)
        self.assertEqual(derived(rows)['phi_peak_deg'], self.r.derived['phi_peak_deg'])

    def test_void_ratios_are_the_cells(self):
        last = self.r.records[-1]
        # porosity() takes the grains' exact volumes: e = n / (1 - n)
        self.assertAlmostEqual(last['void_ratio'], self.porosity / (1 - self.porosity), delta=1e-9)
        # the clumps' union is smaller than the grain at 5 spheres: a larger void ratio on it
        self.assertGreater(last['void_ratio_union'], last['void_ratio'])
        self.assertEqual(self.r.derived['e0'], self.r.records[0]['void_ratio'])

    def test_quasi_static_is_measured(self):
        d = self.r.derived
        self.assertLessEqual(d['I_max'], 1e-3)
        self.assertTrue(d['quasi_static'])
        self.assertEqual(self.r.cost['clumps'], SMALL['grains'])
        self.assertEqual(self.r.cost['spheres'], SMALL['grains'] * len(template().result))


class Undrained(unittest.TestCase):
    def test_the_volume_is_constant(self):
        O.reset()
        r = triaxial([template()], undrained=True, **SMALL)
        v = np.array([x['volumetric_strain'] for x in r.records])
        self.assertLess(np.max(np.abs(v)), 1e-6)
        self.assertGreaterEqual(r.records[-1]['axial_strain'], SMALL['strain'])
        # the lateral stress is free: it moves away from p0 (the effective stress path of a dense specimen)
        lateral = np.array([x['sigma_lateral_Pa'] for x in r.records])
        self.assertGreater(np.max(np.abs(lateral / P0 - 1)), 0.03)


class StopAndResume(unittest.TestCase):
    def test_ctrl_c_keeps_a_checkpoint_and_a_rerun_resumes_it(self):
        folder = tempfile.mkdtemp()
        try:
            O.reset()
            seen = []

            def stopMidway(phase, fraction, text):
                seen.append(phase)
                if phase == 'shear' and fraction > 0.4:
                    raise KeyboardInterrupt
            with self.assertRaises(KeyboardInterrupt):
                triaxial([template()], checkpoint=folder, progress=stopMidway, **SMALL)
            self.assertIn('compaction', seen)
            self.assertTrue(os.path.isfile(os.path.join(folder, 'checkpoint.yade.gz')))
            O.reset()
            phases = []
            r = triaxial([template()], checkpoint=folder, progress=lambda p, f, t: phases.append((p, f)), **SMALL)
            # no compaction again: it went on shearing from where it stopped
            self.assertNotIn('compaction', [p for p, f in phases])
            self.assertGreater(phases[0][1], 0.4)
            self.assertGreaterEqual(r.records[-1]['axial_strain'], SMALL['strain'])
            a = [x['axial_strain'] for x in r.records]
            self.assertTrue(all(y > x for x, y in zip(a, a[1:])))
            # other options: not this checkpoint's run, a new one
            O.reset()
            phases = []
            triaxial([template()], checkpoint=folder, progress=lambda p, f, t: phases.append(p),
                     **dict(SMALL, strain=0.004))
            self.assertIn('compaction', phases)
        finally:
            shutil.rmtree(folder)


class BadOptions(unittest.TestCase):
    def setUp(self):
        O.reset()

    def test_each_is_named(self):
        t = template()
        for kw, word, kind in ((dict(grains=1), 'grains', ValueError), (dict(state='medium'), 'state', ValueError),
                               (dict(strain=-0.1), 'strain', ValueError), (dict(confining=0), 'confining', ValueError),
                               (dict(undrained='no'), 'undrained', TypeError),
                               (dict(frictionAngle=2.0), 'frictionAngle', ValueError),
                               (dict(weights=[1, 2]), 'weights', ValueError)):
            with self.subTest(kw=kw):
                with self.assertRaises(kind) as e:
                    triaxial([t], **kw)
                self.assertIn(word, str(e.exception))
        with self.assertRaises(TypeError) as e:
            triaxial([GRAIN])
        self.assertIn('MssTemplate', str(e.exception))
        self.assertEqual(len(O.bodies), 0)

    def test_a_scene_with_bodies_is_refused(self):
        from yade import utils
        O.bodies.append(utils.sphere((0, 0, 0), 1))
        with self.assertRaises(ValueError) as e:
            triaxial([template()], **SMALL)
        self.assertIn('O.reset()', str(e.exception))

    def test_a_compaction_that_fails_says_so(self):
        with self.assertRaises(RuntimeError) as e:
            triaxial([template()], compactionSteps=400, **SMALL)
        self.assertIn('did not reach the confining pressure in 400 steps', str(e.exception))
        self.assertIn('compactionSteps', str(e.exception))


class SameSpecimen(unittest.TestCase):
    def test_places_and_orientations_do_not_depend_on_the_count(self):
        # the draws come from the seed alone; the clumps' centres of mass go to the sites
        a = placements(20, 1e-3, np.array([0.5, 0.5]), 7)
        b = placements(20, 1e-3, np.array([0.5, 0.5]), 7)
        for x, y in zip(a[1:], b[1:]):
            np.testing.assert_array_equal(x, y)
        c = placements(20, 1e-3, np.array([0.5, 0.5]), 8)
        self.assertFalse(np.array_equal(a[1], c[1]))
        # no two sites closer than the spacing (the clumps cannot overlap at the start)
        d = np.linalg.norm(a[1][:, None] - a[1][None], axis=2) + np.eye(20)
        self.assertGreaterEqual(d.min(), 1e-3 * (1 - 1e-12))
        self.assertTrue(np.allclose(mobilized([3.0], [1.0]), [30.0]))


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
