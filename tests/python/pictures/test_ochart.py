"""mss ochart: the clumps' O-chart (D, the cost T = n / r_min, O = T x D) over sphere counts and radius bounds,
and the cheapest clump meeting a fidelity (problem (iii)), through the command line. Run with /usr/bin/python3."""
import csv
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

from yade_mss import clumpOchart, massProperties, readSpheres
from yade_mss.pictures import cheapest, pareto

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
BINARY = os.environ.get('MSS_BINARY', 'mss')


class Ochart(unittest.TestCase):
    def test_the_femur_chart_and_the_cheapest_clump_meeting_D(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'femur.png')
            femur = os.path.join(DATA, 'human_femur.stl')
            p = subprocess.run([BINARY, 'ochart', femur, '-o', out, '--counts', '4:48', '--points', '5',
                                '--radius-points', '4', '--resolution', '70', '--dice', '0.08', '--min-cost'],
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertGreater(os.path.getsize(out), 50000)
            with open(os.path.join(d, 'femur.csv')) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), 5 * 4)
            done = [r for r in rows if r['D']]
            meeting = [r for r in done if float(r['D']) <= 0.08]
            self.assertGreater(len(meeting), 0)
            self.assertLess(len(meeting), len(done))  # the target is one some points miss
            least = min(float(r['T']) for r in meeting)
            best = readSpheres(os.path.join(d, 'femur_best.csv'))
            # the clump written is the chart's point of least cost among those meeting D <= 0.08
            volume = massProperties(femur).volume
            T = len(best) * (3 * volume / (4 * math.pi)) ** (1 / 3) / best.radii.min()
            self.assertAlmostEqual(T, least, delta=1e-6 * least)
            self.assertIn('least cost  n %d' % len(best), p.stdout)
            # every point's cost is n / r_min relative to one sphere of the volume; the front is not beaten
            for r in done:
                self.assertAlmostEqual(float(r['T']), int(r['n']) * (3 * volume / (4 * math.pi)) ** (1 / 3)
                                       / float(r['r_min']), delta=1e-9 * float(r['T']))
                self.assertAlmostEqual(float(r['O']), float(r['T']) * float(r['D']), delta=1e-9 * float(r['O']))
            front = [r for r in done if r['pareto'] == '1']
            self.assertGreater(len(front), 1)
            for r in front:
                self.assertFalse(any(float(q['T']) < float(r['T']) and float(q['D']) < float(r['D']) for q in done))
            # the radius bound binds somewhere: a larger bound gave a larger smallest radius at the same count
            by = {}
            for r in done:
                by.setdefault(r['n_asked'], []).append((float(r['rmin_fraction_asked']), float(r['r_min'])))
            self.assertTrue(any(sorted(v)[-1][1] > sorted(v)[0][1] * 1.05 for v in by.values()))

    def test_a_fidelity_no_point_meets(self):
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.run([BINARY, 'ochart', os.path.join(DATA, 'cube.stl'), '-o', os.path.join(d, 'c.png'),
                                '--counts', '2:4', '--points', '2', '--radius-points', '2', '--resolution', '30',
                                '--dice', '0.0001', '--min-cost'], capture_output=True, text=True)
            self.assertEqual(p.returncode, 1)
            self.assertIn('no point of the chart meets D <= 0.0001', p.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, 'c_best.csv')))

    def test_bad_options_are_named(self):
        with tempfile.TemporaryDirectory() as d:
            for args, message in ((['--radii', '0.5:2'], 'at most 1'), (['--counts', '8:2'], 'A <= B'),
                                  (['--min-cost'], 'minCost needs dice'), (['--radii', 'x'], 'radii takes A:B')):
                p = subprocess.run([BINARY, 'ochart', os.path.join(DATA, 'cube.stl'), '-o', os.path.join(d, 'c.png')]
                                   + args, capture_output=True, text=True)
                self.assertEqual(p.returncode, 1, args)
                self.assertIn(message, p.stderr, args)

    def test_a_table_of_the_users_beside_the_png_is_kept(self):
        # the bug: -o s.png wrote over the user's s.csv; a rerun still replaces the chart's own table
        with tempfile.TemporaryDirectory() as d:
            mine = os.path.join(d, 's.csv')
            with open(mine, 'w') as f:
                f.write('my,data\n1,2\n')
            args = [BINARY, 'ochart', os.path.join(DATA, 'octahedron.stl'), '-o', os.path.join(d, 's.png'),
                    '--counts', '2:4', '--points', '2', '--radius-points', '2', '--resolution', '30']
            p = subprocess.run(args, capture_output=True, text=True)
            self.assertEqual(p.returncode, 1)
            self.assertIn('is not an O-chart table', p.stderr)
            with open(mine) as f:
                self.assertEqual(f.read(), 'my,data\n1,2\n')
            self.assertFalse(os.path.exists(os.path.join(d, 's.png')))
            os.remove(mine)
            for _ in range(2):
                p = subprocess.run(args, capture_output=True, text=True)
                self.assertEqual(p.returncode, 0, p.stderr)

    def test_pareto_and_cheapest(self):
        pts = [(1.0, 0.5), (2.0, 0.3), (2.0, 0.4), (3.0, 0.3), (2.0, 0.3), (5.0, 0.1)]
        self.assertEqual(pareto(pts), [0, 1, 5])
        rows = [{'T': t, 'D': dd} for t, dd in pts]
        self.assertEqual(cheapest(rows, 0.3), rows[1])
        self.assertIsNone(cheapest(rows, 0.05))

    def test_a_voxel_grain_in_python(self):
        g = np.indices((30, 24, 20)).transpose(1, 2, 3, 0) - np.array([15, 12, 10])
        solid = ((g / np.array([12.0, 8.0, 6.0])) ** 2).sum(axis=-1) <= 1
        with tempfile.TemporaryDirectory() as d:
            rows, best = clumpOchart(solid, os.path.join(d, 'e.png'), counts=(2, 16), points=3, radiusPoints=3,
                                     dice=0.2, minCost=True)
            self.assertEqual(len(rows), 9)
            self.assertIsNotNone(best)
            self.assertLessEqual(best['D'], 0.2)
            self.assertEqual(len(best['result']), best['n'])


if __name__ == '__main__':
    unittest.main()
