"""Heavy requests (pkg/mss/work.hpp): each class gives a refusal with its estimate, a clean error or a result
within 10 s; a long run shows progress and stops on Ctrl-C, publishing nothing. Large cases are made small by
the limits (maxWork), never skipped."""

import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

import yade_mss
from yade_mss import pictures as _pictures

MSS = os.environ.get('MSS_BINARY', 'mss')
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
ELLIPSOID = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
BAR = 10.0  # seconds: each class ends within this


def spheres(path, n, seed=1, r=(0.02, 0.1)):
    """*n* random spheres in the ellipsoid's box, as x,y,z,r with a header."""
    rng = np.random.default_rng(seed)
    rows = np.c_[rng.uniform([-2, -1, -1], [2, 1, 1], (n, 3)), rng.uniform(r[0], r[1], n)]
    np.savetxt(path, rows, delimiter=',', header='x,y,z,r', comments='')
    return path


class CommandLine(unittest.TestCase):
    def run_mss(self, *args):
        t0 = time.perf_counter()
        p = subprocess.run([MSS] + [str(a) for a in args], capture_output=True, text=True, timeout=120)
        return p, time.perf_counter() - t0

    def assertRefused(self, p, seconds, *words):
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertLess(seconds, BAR)
        for w in words:
            self.assertIn(w, p.stderr)

    def test_generation_over_the_limit_is_refused_with_its_estimate(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'g.csv')
            p, t = self.run_mss('generate', ELLIPSOID, '-o', out, '--resolution', 200, '--spheres', 65535,
                                '--max-work', 1)
            self.assertRefused(p, t, 'a grid of', '65535 spheres', 'of work, over the work limit of 1 s',
                               '--max-work', '--spheres')
            self.assertFalse(os.path.exists(out))

    def test_exact_scoring_of_1e9_points_is_refused_at_the_default_limit(self):
        with tempfile.TemporaryDirectory() as d:
            s = spheres(os.path.join(d, 's.csv'), 10)
            p, t = self.run_mss('compare', ELLIPSOID, s, '--exact', '--samples', 1000000000)
            self.assertRefused(p, t, '1e+09 exact-score points', 'over the work limit of 600 s', '--samples')

    def test_many_rows_in_compare_and_surface_are_estimated_first(self):
        with tempfile.TemporaryDirectory() as d:
            s = spheres(os.path.join(d, 's.csv'), 30000)
            p, t = self.run_mss('compare', ELLIPSOID, s, '--max-work', 2)
            self.assertRefused(p, t, 'the protrusions of 30000 spheres')
            p, t = self.run_mss('surface', s, '-o', os.path.join(d, 'x.stl'))
            self.assertRefused(p, t, '30000 spheres', 'subdivisions', 'over the work limit of 600 s')
            self.assertFalse(os.path.exists(os.path.join(d, 'x.stl')))

    def test_surface_bounds_are_judged_before_the_subdivisions(self):
        with tempfile.TemporaryDirectory() as d:
            one = os.path.join(d, 'one.csv')
            with open(one, 'w') as f:
                f.write('x,y,z,r\n0,0,0,1\n')
            p, t = self.run_mss('surface', one, '-o', os.path.join(d, 'x.stl'), '--max-edge', '1e-6')
            self.assertRefused(p, t, 'need about 20 subdivisions', 'more than maxTriangles', '--max-triangles')
            s = spheres(os.path.join(d, 's.csv'), 300, r=(0.1, 0.5))
            p, t = self.run_mss('surface', s, '-o', os.path.join(d, 'x.stl'), '--max-work', 5)
            self.assertRefused(p, t, 'over the work limit of 5 s')

    def test_radii_near_the_ends_of_the_double_range_are_refused_by_name(self):
        with tempfile.TemporaryDirectory() as d:
            for radius in ('1e300', '1e-310', '1e-70'):
                f = os.path.join(d, 'r.csv')
                with open(f, 'w') as out:
                    out.write('x,y,z,r\n0,0,0,%s\n1,0,0,%s\n' % (radius, radius))
                for args in (('surface', f, '-o', os.path.join(d, 'x.stl')), ('compare', ELLIPSOID, f)):
                    with self.subTest(radius=radius, command=args[0]):
                        p, t = self.run_mss(*args)
                        self.assertRefused(p, t, 'sphere 0 (radius', 'outside the range this code computes in')

    def test_a_sparse_fortran_volume_over_the_grid_is_refused_unread(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'sparse.npy')
            m = np.lib.format.open_memmap(path, mode='w+', dtype=np.uint8, shape=(1300, 1300, 1300),
                                          fortran_order=True)
            m[600:700, 600:700, 600:700] = 1
            del m
            p, t = self.run_mss('generate', path, '-o', os.path.join(d, 'g.csv'), '--spheres', 5)
            self.assertRefused(p, t, 'over 2^31 - 1 voxels')
            t0 = time.perf_counter()
            with self.assertRaisesRegex(ValueError, r'over 2\^31 - 1 voxels'):
                yade_mss.generate(np.load(path, mmap_mode='r'), nSpheres=5)
            self.assertLess(time.perf_counter() - t0, BAR)

    def test_a_batch_of_a_volume_over_the_grid_is_refused_before_any_pass(self):
        # each pass over a 1300^3 scan reads the file whole (tens of seconds); the grid's index says no first
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'big.npy')
            m = np.lib.format.open_memmap(path, mode='w+', dtype=np.uint8, shape=(1300, 1300, 1300))
            m[600:610, 600:610, 600:610] = 1
            del m
            p, t = self.run_mss('batch', path, '-o', os.path.join(d, 'out'), '--spheres', 5)
            self.assertRefused(p, t, '1300x1300x1300 voxels', 'over the 2147483647 (2^31 - 1) a grid can index')
            self.assertFalse(os.path.exists(os.path.join(d, 'out')))

    def test_a_mapped_scan_larger_than_its_passes_stays_out_of_resident_memory(self):
        # a batch passes over a memory-mapped scan several times (its values, its pieces, its contacts, its
        # regions): each slab's pages are handed back as it goes, so the peak follows the slabs, not the file
        # (before: the whole file, 8 GB of an 8 GB scan, over an 8 GiB --memory-limit)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'scan.npy')
            m = np.lib.format.open_memmap(path, mode='w+', dtype=np.int64, shape=(480, 480, 480))  # 885 MB
            m[100:112, 100:112, 100:112] = 1
            m[300:312, 300:312, 300:312] = 2
            del m
            out = os.path.join(d, 'out')
            code = ('import resource, subprocess, sys\n'
                    'p = subprocess.run(sys.argv[1:], capture_output=True, text=True)\n'
                    'print(p.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n'
                    'sys.stderr.write(p.stderr)\n')
            p = subprocess.run([sys.executable, '-c', code, MSS, 'batch', path, '-o', out, '--spheres', '5',
                                '--memory-limit', '0.25'], capture_output=True, text=True, timeout=300)
            rc, kib = map(int, p.stdout.split())
            self.assertEqual(rc, 0, p.stderr)
            self.assertLess(kib * 1024, 0.5 * os.path.getsize(path), 'peak resident memory %d KiB' % kib)
            self.assertEqual(len([f for f in os.listdir(os.path.join(out, 'grains')) if f.endswith('.json')]), 2)

    def test_a_triangle_soup_is_refused_before_its_crossings_fill_the_memory(self):
        # 20,000 random triangles in a cube: every ray meets thousands (before: 300k such triangles held 6.4 GiB
        # and ran past 150 s); the mesh's crossings are bounded before a ray is cast
        with tempfile.TemporaryDirectory() as d:
            rng = np.random.default_rng(0)
            path = os.path.join(d, 'soup.obj')
            with open(path, 'w') as f:
                f.writelines('v %.6f %.6f %.6f\n' % tuple(v) for v in rng.random((60000, 3)))
                f.writelines('f %d %d %d\n' % (3 * i + 1, 3 * i + 2, 3 * i + 3) for i in range(20000))
            p, t = self.run_mss('generate', path, '-o', os.path.join(d, 'g.csv'), '--spheres', 5,
                                '--resolution', 200, '--memory-limit', 0.5)
            self.assertRefused(p, t, 'triangle soup', 'over the memory limit of 0.5 GiB')
            p, t = self.run_mss('generate', path, '-o', os.path.join(d, 'g.csv'), '--spheres', 5,
                                '--resolution', 100, '--max-work', 5)
            self.assertRefused(p, t, 'winding number', 'over the work limit of 5 s')
            self.assertFalse(os.path.exists(os.path.join(d, 'g.csv')))
            # the soup of 300k triangles compared with a sphere file: the soup is named as the file at
            # fault (the rows named the sphere file), and refused at the default memory limit
            big = os.path.join(d, 'big_soup.obj')
            with open(big, 'w') as f:
                f.write(''.join('v %.5f %.5f %.5f\n' % tuple(v) for v in rng.random((900000, 3))))
                f.write(''.join('f %d %d %d\n' % (3 * i + 1, 3 * i + 2, 3 * i + 3) for i in range(300000)))
            s = os.path.join(d, 's.csv')
            with open(s, 'w') as f:
                f.write('x,y,z,r\n0.5,0.5,0.5,0.2\n0.3,0.4,0.5,0.1\n')  # in the soup's cube
            p, t = self.run_mss('compare', big, s)
            self.assertRefused(p, t, 'error: %s: voxelizeMesh' % big, 'triangle soup', '(the grain, not %s)' % s)

    def test_ctrl_c_stops_a_long_generation_and_writes_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'g.csv')
            p = subprocess.Popen([MSS, 'generate', ELLIPSOID, '-o', out, '--resolution', '300', '--spheres',
                                  '65535'], stderr=subprocess.PIPE, text=True)
            line = p.stderr.readline()  # the first progress line: the work has begun
            self.assertRegex(line, r'^generate: \d+% .* of about .* s; Ctrl-C stops')
            t0 = time.perf_counter()
            p.send_signal(signal.SIGINT)
            rest = p.stderr.read()
            self.assertEqual(p.wait(timeout=60), 130, rest)
            self.assertLess(time.perf_counter() - t0, BAR)
            self.assertIn('interrupted (Ctrl-C): nothing was written', rest)
            self.assertEqual(os.listdir(d), [])


class Python(unittest.TestCase):
    def test_a_broadcast_volume_is_sized_by_its_shape(self):
        v = np.broadcast_to(np.ones(1, np.uint8), (3000, 3000, 3000))
        t0 = time.perf_counter()
        with self.assertRaisesRegex(ValueError, '3000x3000x3000'):  # before: 9 s, then a MemoryError
            yade_mss.generate(v, nSpheres=5)
        self.assertLess(time.perf_counter() - t0, BAR)  # refused before any copy (a bar loose enough for load)

    def test_segmenting_a_scan_past_the_memory_limit_is_refused_before_allocating(self):
        scan = np.zeros((400, 400, 400), np.uint8)  # 64 MB; segmented, about 128 bytes a voxel: 7.6 GiB
        scan[100:200, 100:200, 100:200] = 1
        t0 = time.perf_counter()
        with self.assertRaisesRegex(ValueError, r'segment: segmenting a scan of 400x400x400 voxels needs about '
                                                r'7.63 GiB .* over the memory limit of 2 GiB'):
            yade_mss.grains.segmentBinary(scan, memoryLimit=2)
        self.assertLess(time.perf_counter() - t0, BAR)

    def test_sweeps_are_estimated_after_their_first_point(self):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            with self.assertRaisesRegex(ValueError, r'curve: \d+ generations of .* over the work limit of 5 s'):
                _pictures.curve(ELLIPSOID, 1, 5000, os.path.join(d, 'c.png'), points=1000, resolution=40, maxWork=5)
            with self.assertRaisesRegex(ValueError, r'ochart: \d+ generations .* radius points'):
                yade_mss.clumpOchart(ELLIPSOID, os.path.join(d, 'o.png'), points=100, radiusPoints=100,
                                     resolution=40, maxWork=5)
            self.assertLess(time.perf_counter() - t0, 2 * BAR)
            self.assertEqual(os.listdir(d), [])

    def test_a_sweep_is_estimated_through_its_measured_steps(self):
        # steps measured at 1, 100 and 10,000 spheres (0.1, 1 and 1 s: the cost capped, as a grain's count is at
        # a resolution): a step of 10 costs the log-log chord's 0.316 s, one of 1,000 the cap's 1 s; x 1.25
        checkSweep = yade_mss.base.checkSweep
        self.assertAlmostEqual(checkSweep('curve', 0.1, 1, [10, 1000], 600, '', [(100, 1.0), (10000, 1.0)]),
                               1.25 * (0.1 * 10 ** 0.5 + 1.0), places=9)
        with self.assertRaisesRegex(ValueError, r'curve: 2 generations of 10 to 1000 spheres .* about 1.6 s of '
                                                r'work, over the work limit of 1 s: fewer'):
            checkSweep('curve', 0.1, 1, [10, 1000], 1, 'fewer', [(100, 1.0), (10000, 1.0)])
        # the model alone (no measured step) scales the first step by the core's log model: far less
        self.assertLess(checkSweep('curve', 0.1, 1, [10, 1000], 600, ''), 0.5)

    def test_a_curve_runs_its_dearest_step_before_it_estimates_the_rest(self):
        # 1 to 1,000 spheres at resolution 40: the log model scaled the cheap first step to about 26 s of the 128
        # steps and let it start at a 40 s limit; the dearest step (1,000 asked), run second, shows the steps
        # cost several times that (scoring grows with the spheres): refused, and only 3 steps run
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            with self.assertRaisesRegex(ValueError, r'curve: 1\d\d generations .* over the work limit of 40 s'):
                _pictures.curve(ELLIPSOID, 1, 1000, os.path.join(d, 'c.png'), points=200, resolution=40, maxWork=40)
            self.assertLess(time.perf_counter() - t0, BAR)
            self.assertEqual(os.listdir(d), [])

    def test_preview_of_many_spheres_is_estimated(self):
        with tempfile.TemporaryDirectory() as d:
            s = spheres(os.path.join(d, 's.csv'), 30000)
            t0 = time.perf_counter()
            with self.assertRaisesRegex(ValueError, 'over the work limit of 1 s'):
                _pictures.preview(ELLIPSOID, s, os.path.join(d, 'p.png'), maxWork=1)
            self.assertLess(time.perf_counter() - t0, BAR)
            self.assertFalse(os.path.exists(os.path.join(d, 'p.png')))

    def test_a_spheropolygon_of_many_vertices_on_a_large_image_is_refused(self):
        n = 4000
        y, x = np.mgrid[:n, :n]
        disk = np.hypot(x - n / 2, y - n / 2) < 0.4 * n
        t0 = time.perf_counter()
        with self.assertRaisesRegex(ValueError, r'fits of 10000 vertices to a particle of \d+ x \d+ pixels'):
            yade_mss.spheropolygon(disk, vertices=10000)
        self.assertLess(time.perf_counter() - t0, BAR)

    def test_ctrl_c_inside_the_core_is_python_s_keyboard_interrupt(self):
        code = ('import signal, sys, time, yade_mss\n'
                'signal.signal(signal.SIGINT, signal.default_int_handler)\n'
                'print("ready", flush=True)\n'
                't = time.perf_counter()\n'
                'try:\n'
                '    yade_mss.generate(%r, nSpheres=65535, resolution=300)\n'
                'except KeyboardInterrupt:\n'
                '    print("interrupted %%.2f" %% (time.perf_counter() - t), flush=True)\n' % ELLIPSOID)
        p = subprocess.Popen([sys.executable, '-c', code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        self.assertEqual(p.stdout.readline().strip(), 'ready')
        time.sleep(3)  # inside the core by now (its distance transform alone takes longer)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 0, err)
        self.assertRegex(out, r'interrupted \d')
        self.assertLess(float(out.split()[-1]), 3 + BAR)

    def test_wrong_kinds_of_argument_are_named(self):
        with self.assertRaisesRegex(TypeError, 'spheres must be a sphere file .* got ndarray'):
            yade_mss.score(ELLIPSOID, np.zeros((3, 4)))
        with self.assertRaisesRegex(TypeError, 'outdir must be a folder path, got int'):
            yade_mss.batch([ELLIPSOID], outdir=5)
        with self.assertRaisesRegex(ValueError, 'source must be a mesh file.*got NoneType'):
            yade_mss.generate(None, nSpheres=3)
        # the bug: numpy's "cannot reshape array of size 4 into shape (3)", naming neither array
        with self.assertRaisesRegex(ValueError, r'mesh: vertices must have shape \(n, 3\).*got shape 4x2'):
            yade_mss.generate((np.zeros((4, 2)), np.zeros((1, 3), int)), nSpheres=2)
        with self.assertRaisesRegex(ValueError, r'mesh: triangles must have shape \(n, 3\).*got shape 4'):
            yade_mss.generate((np.zeros((4, 3)), np.zeros(4, int)), nSpheres=2)
        with self.assertRaisesRegex(TypeError, r'mesh: triangles are missing \(None\)'):
            yade_mss.generate((np.zeros((4, 3)), None), nSpheres=2)


if __name__ == '__main__':
    unittest.main()
