"""No output over an input, no output through a planted link, worker pools that end without tracebacks, a Dask
scheduler that does not answer named within seconds (issue 50). Run with /usr/bin/python3."""
import os
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from yade_mss import batch, packedSpecimen

BINARY = os.environ.get('MSS_BINARY', 'mss')
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')


def read(path):
    with open(path, 'rb') as f:
        return f.read()


class BatchOutputs(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name
        self.L = packedSpecimen((30, 30, 30), grains=8, size=(4, 6), seed=1)
        self.path = os.path.join(self.d, 'labels.npy')
        np.save(self.path, self.L)

    def tearDown(self):
        self.dir.cleanup()

    def test_a_grains_folder_planted_as_a_link_is_refused(self):
        out, elsewhere = os.path.join(self.d, 'out'), os.path.join(self.d, 'elsewhere')
        os.makedirs(out)
        os.makedirs(elsewhere)
        os.symlink(elsewhere, os.path.join(out, 'grains'))
        with self.assertRaises(ValueError) as e:
            batch([self.path], out, workers=1, progress=False, nSpheres=3)
        self.assertIn('symbolic link', str(e.exception))
        self.assertEqual(os.listdir(elsewhere), [])  # nothing written where it points
        os.symlink(out, os.path.join(self.d, 'linked'))
        with self.assertRaises(ValueError):  # the output folder itself
            batch([self.path], os.path.join(self.d, 'linked'), workers=1, progress=False, nSpheres=3)

    def test_an_output_that_is_the_input_is_refused(self):
        # the labels given as the folder's own grains.csv name: the batch would write over them
        out = os.path.join(self.d, 'out')
        os.makedirs(out)
        inside = os.path.join(out, 'labels.npy')
        np.save(inside, (self.L != 0).astype(np.uint8))
        before = read(inside)
        with self.assertRaises(ValueError) as e:
            batch([inside], out, workers=1, progress=False, nSpheres=3, segment=True)
        self.assertIn('is the input', str(e.exception))
        self.assertEqual(read(inside), before)
        os.makedirs(os.path.join(out, 'grains'))
        moved = os.path.join(out, 'grains', 'labels.npy')
        os.rename(self.path, moved)
        with self.assertRaises(ValueError) as e:
            batch([moved], out, workers=1, progress=False, nSpheres=3)
        self.assertIn("grains/", str(e.exception))

    def test_warnings_are_the_command_s_lines_not_python_s(self):
        # the issue: Python UserWarning lines with source paths on stderr
        p = subprocess.run([BINARY, 'batch', os.path.join(DATA, 'stanford_bunny_open.stl'), '-o',
                            os.path.join(self.d, 'w'), '--spheres', '5', '--resolution', '30', '--workers', '1'],
                           capture_output=True, text=True, timeout=300)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn('mss batch: warning: stanford_bunny_open.stl: the mesh is not closed', p.stderr)
        self.assertNotIn('UserWarning', p.stderr)
        self.assertNotIn('.py:', p.stderr)

    def test_the_report_s_table_fits_the_page(self):
        b = batch([self.path], os.path.join(self.d, 'r'), workers=1, progress=False, nSpheres=3)
        page = read(os.path.join(self.d, 'r', 'report.html')).decode()
        self.assertIn('<div class="grains"><table>', page)  # scrolls within the page, not the page sideways
        self.assertIn('td.problems{min-width:22em}', page)  # the problems wide enough to read
        self.assertEqual(page.count('<td class="problems">'), len(b.rows))
        self.assertIn('This run, up to this report:', page)  # not the console's total, which counts the writing

    def test_worker_processes_end_without_tracebacks(self):
        out = os.path.join(self.d, 'out')
        p = subprocess.run([BINARY, 'batch', self.path, '-o', out, '--spheres', '3', '--workers', '2'],
                           capture_output=True, text=True, timeout=300)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertNotIn('Traceback', p.stderr)
        self.assertNotIn('KeyboardInterrupt', p.stderr)

    def test_a_scheduler_that_does_not_answer_is_named_within_seconds(self):
        t = time.perf_counter()
        with self.assertRaises(RuntimeError) as e:
            batch([self.path], None, progress=False, nSpheres=3, scheduler='tcp://127.0.0.1:9', connectTimeout=2)
        self.assertLess(time.perf_counter() - t, 10)
        self.assertIn('tcp://127.0.0.1:9', str(e.exception))
        self.assertIn('did not answer within 2 s', str(e.exception))
        with self.assertRaises(ValueError):
            batch([self.path], None, progress=False, nSpheres=3, connectTimeout=0)


class CommandOutputs(unittest.TestCase):
    def test_export_over_its_mesh_through_a_link_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            mesh = os.path.join(d, 'cube.stl')
            with open(os.path.join(DATA, 'cube.stl'), 'rb') as f:
                data = f.read()
            with open(mesh, 'wb') as f:
                f.write(data)
            os.symlink(mesh, os.path.join(d, 'out.p3dat'))
            p = subprocess.run([sys.executable, '-m', 'yade_mss', 'export', mesh, '--spheres', '2', '--format', 'pfc',
                                '-o', os.path.join(d, 'out.p3dat')], capture_output=True, text=True, timeout=120)
            self.assertEqual(p.returncode, 1)
            self.assertIn('through a link', p.stderr)
            with open(mesh, 'rb') as f:
                self.assertEqual(f.read(), data)


    def test_no_abbreviated_option_is_taken_for_another(self):
        # the bug: `mss batch --label 1` was read as --labels 1 (argparse's abbreviations)
        for args in (['batch', self_path(), '--label', '1', '-o', 'x'], ['triaxial', self_path(), '--confin', '1e5',
                                                                            '-o', 'x'],
                     ['preview', self_path(), 's.csv', '--voxel', '3', '-o', 'x.png'],
                     ['curve', self_path(), '--count', '4', '-o', 'x.png'],
                     ['export', self_path(), '--format', 'pfc', '--sph', '4', '-o', 'x.p3dat'],
                     ['ochart', self_path(), '--count', '4', '-o', 'x.png'],
                     ['spheropolygon', self_path(), '--vert', '4', '-o', 'x.json']):
            with self.subTest(args[0]):
                p = subprocess.run([sys.executable, '-m', 'yade_mss'] + args, capture_output=True, text=True,
                                   timeout=60)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertIn('unrecognized arguments', p.stderr)


def self_path():
    return os.path.join(DATA, 'octahedron.stl')


if __name__ == '__main__':
    unittest.main()
