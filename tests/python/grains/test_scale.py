"""--scale / scale=: a grain in millimetres becomes an SI template without editing it elsewhere. The scaled run must
be the unscaled one times the factor, on every command that reads a grain."""

import os
import subprocess
import tempfile
import unittest

import numpy as np

import yade_mss

MSS = os.environ.get('MSS_BINARY', 'mss')
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
FEMUR = os.path.join(DATA, 'human_femur.stl')  # millimetres
LABELS = os.path.join(DATA, 'two_grains_labels.npy')


def spheres(path):
    return np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)


def run(*args):
    p = subprocess.run([MSS] + [str(a) for a in args], capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        raise AssertionError('mss %s: %s' % (' '.join(map(str, args)), p.stderr))
    return p.stdout


class Scale(unittest.TestCase):
    def test_generate_in_metres_is_the_millimetre_result_scaled(self):
        with tempfile.TemporaryDirectory() as d:
            run('generate', FEMUR, '--spheres', 12, '-o', os.path.join(d, 'mm.csv'))
            run('generate', FEMUR, '--spheres', 12, '--scale', '1e-3', '-o', os.path.join(d, 'm.csv'))
            mm, m = spheres(os.path.join(d, 'mm.csv')), spheres(os.path.join(d, 'm.csv'))
            np.testing.assert_allclose(m, 1e-3 * mm, rtol=1e-12, atol=1e-15)
            # the Python keyword is the same option
            r = yade_mss.generate(FEMUR, nSpheres=12, scale=1e-3)
            np.testing.assert_allclose(np.c_[r.centers, r.radii], m, rtol=1e-9, atol=1e-12)
            self.assertAlmostEqual(r.targetMass.volume, 1e-9 * yade_mss.massProperties(FEMUR).volume,
                                   delta=1e-12 * r.targetMass.volume)
            # compare and info read the grain scaled as well
            self.assertIn('volume        0.000125', run('info', FEMUR, '--scale', '1e-3'))
            out = run('compare', FEMUR, os.path.join(d, 'm.csv'), '--scale', '1e-3')
            self.assertAlmostEqual(float(out.split('dice')[1].split()[0]), yade_mss.score(FEMUR, r, scale=1e-3)['dice'],
                                   4)
            with self.assertRaisesRegex(ValueError, 'scale must be'):
                yade_mss.score(FEMUR, r, scale=-1)

    def test_a_volume_scales_its_voxel_size_and_origin(self):
        a = yade_mss.generate(LABELS, label=1, nSpheres=4, voxelSize=2.0, origin=(10, 0, 0))
        b = yade_mss.generate(LABELS, label=1, nSpheres=4, voxelSize=2.0, origin=(10, 0, 0), scale=0.25)
        np.testing.assert_allclose(b.centers, 0.25 * a.centers, rtol=1e-12)
        np.testing.assert_allclose(b.radii, 0.25 * a.radii, rtol=1e-12)
        self.assertAlmostEqual(b.grid['voxelSize'], 0.5)

    def test_export_and_batch_take_it(self):
        with tempfile.TemporaryDirectory() as d:
            run('export', FEMUR, '--spheres', 8, '--scale', '1e-3', '--format', 'yade', '--density', 2650,
                '-o', os.path.join(d, 't.txt'))
            rows = np.loadtxt(os.path.join(d, 't.txt'), comments='#', ndmin=2)
            self.assertLess(rows[:, 3].max(), 0.05)  # metres: the femur is about 0.45 long
            self.assertGreater(rows[:, 3].max(), 0.005)
            run('batch', LABELS, '--spheres', 4, '-o', os.path.join(d, 'mm'))
            run('batch', LABELS, '--spheres', 4, '--scale', '1e-3', '-o', os.path.join(d, 'm'))
            a = np.loadtxt(os.path.join(d, 'mm', 'assembly.txt'), comments='#', ndmin=2)
            b = np.loadtxt(os.path.join(d, 'm', 'assembly.txt'), comments='#', ndmin=2)
            np.testing.assert_allclose(b[:, :4], 1e-3 * a[:, :4], rtol=1e-9, atol=1e-15)
            np.testing.assert_array_equal(b[:, 4], a[:, 4])

    def test_a_bad_scale_is_named(self):
        with self.assertRaisesRegex(ValueError, 'scale must be'):
            yade_mss.generate(FEMUR, nSpheres=3, scale=0)
        p = subprocess.run([MSS, 'generate', FEMUR, '--spheres', '3', '--scale', '-1', '-o', 'x.csv'],
                           capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 1)
        self.assertIn('--scale must be', p.stderr)


if __name__ == '__main__':
    unittest.main()
