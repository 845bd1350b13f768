"""Pictures (yade_mss._pictures, mss preview / curve): real PNG and CSV files written and read back."""
import csv
import os
import subprocess
import tempfile
import unittest

import numpy as np

from yade_mss import generate
from yade_mss.pictures import counts, curve, preview

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
FEMUR = os.path.join(DATA, 'human_femur.stl')
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')


def png(path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.image as mpimg
    return mpimg.imread(path)


class Preview(unittest.TestCase):
    def test_femur_preview_has_content_and_caption_figures(self):
        r = generate(FEMUR, nSpheres=40, resolution=60)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'p.png')
            row = r.preview(out)
            img = png(out)
            self.assertGreaterEqual(img.shape[1], 800)
            self.assertGreater(img[..., :3].std(), 0.05)  # not a blank canvas
            # the section marks missed grain red and spheres outside blue: both kinds of pixel are there
            red = (img[..., 0] > 0.8) & (img[..., 1] < 0.3) & (img[..., 2] < 0.3)
            blue = (img[..., 2] > 0.8) & (img[..., 0] < 0.3)
            self.assertGreater(red.sum(), 50)
            self.assertGreater(blue.sum(), 50)
            self.assertEqual(row['spheres'], 40)
            self.assertGreater(row['protrusion'], 0)
            self.assertEqual(sorted(os.listdir(d)), ['p.png'])

    def test_bad_output_and_grain(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(ValueError):
                r.preview(os.path.join(d, 'p.jpg'))
            r.grain = None
            with self.assertRaises(ValueError):
                r.preview(os.path.join(d, 'p.png'))


class Curve(unittest.TestCase):
    def test_counts_are_log_spaced_and_unique(self):
        c = counts(5, 100, 12)
        self.assertEqual(c[0], 5)
        self.assertEqual(c[-1], 100)
        self.assertEqual(len(c), len(set(c)))
        with self.assertRaises(ValueError):
            counts(10, 5)

    def test_femur_curve_through_the_command_line(self):
        mss = os.environ.get('MSS_BINARY', 'mss')
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'curve.png')
            subprocess.run([mss, 'curve', FEMUR, '--counts', '5:100', '-o', out, '--compare',
                            os.path.join(DATA, 'clump', 'FA_femur_N70_min.txt')], check=True, capture_output=True)
            self.assertGreaterEqual(png(out).shape[1], 800)
            with open(os.path.join(d, 'curve.csv')) as f:
                rows = list(csv.DictReader(f))
            ours = [r for r in rows if r['generator'] == 'yade-mss']
            self.assertGreaterEqual(len(ours), 8)
            D = [float(r['D']) for r in ours]
            self.assertGreaterEqual(D[0] / D[-1], 3.0)  # D falls at least threefold over 5..100
            self.assertTrue(all(float(r['seconds']) > 0 for r in ours))
            self.assertEqual([r['n'] for r in rows if r['generator'] != 'yade-mss'], ['70'])

    def test_preview_command_and_generate_preview(self):
        mss = os.environ.get('MSS_BINARY', 'mss')
        with tempfile.TemporaryDirectory() as d:
            spheres, pic = os.path.join(d, 's.txt'), os.path.join(d, 's.png')
            subprocess.run([mss, 'generate', ELL, '--spheres', '10', '--resolution', '40', '-o', spheres,
                            '--preview', pic], check=True, capture_output=True)
            self.assertGreaterEqual(png(pic).shape[1], 800)
            # named after the file it became (it showed the pending file's name, .mss-pending-XXXXXX.txt)
            from PIL import Image
            with Image.open(pic) as im:
                self.assertEqual(im.text.get('Title'), 's.txt')
            bad = subprocess.run([mss, 'preview', ELL, spheres], capture_output=True, text=True)
            self.assertNotEqual(bad.returncode, 0)  # -o is required
            self.assertIn('-o', bad.stderr)


if __name__ == '__main__':
    unittest.main()
