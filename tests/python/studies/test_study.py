"""The triaxial study: the analysis on curves of known answers (numpy only), and ``mss triaxial`` end to end in real
YADE at a small size: its files consistent with each other, a rerun that skips, Ctrl-C and SIGTERM that keep what
was recorded and a rerun that resumes, refusals before any work. Run with /usr/bin/python3."""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import numpy as np

from yade_mss.studies import derived, dilatancy, needed, triaxialStudy, verdict

BINARY = os.environ.get('MSS_BINARY', 'mss')
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
GRAIN = os.path.join(DATA, 'grain_voxels_155x157x167.npy')
SMALL = ['--voxel-size', '1.25e-5', '--grains', '12', '--records', '20', '--seed', '2']


def curve(a, qOverP, v, p=1e5):
    """Records of an axisymmetric test with q/p and the volumetric strain given along the axial strain a."""
    rows = []
    for x, eta, ev in zip(a, qOverP, v):
        # p = (sa + 2 sr) / 3, q = sa - sr
        q = eta * p
        sr = p - q / 3
        rows.append(dict(axial_strain=x, volumetric_strain=ev, sigma_axial_Pa=sr + q, sigma_lateral_Pa=sr,
                         q_Pa=q, p_Pa=p, void_ratio=0.6, void_ratio_union=0.7, inertial_number=1e-4,
                         unbalanced=0.01))
    return rows


class Analysis(unittest.TestCase):
    def test_the_peak_angle_of_a_known_curve(self):
        a = np.linspace(0, 0.1, 101)
        eta = 1.2 * np.sin(np.pi * a / 0.1)  # the largest q/p, 1.2, at a = 0.05
        d = derived(curve(a, eta, -0.3 * a))
        # Mohr-Coulomb: sin(phi) = 3 eta / (6 + eta)
        self.assertAlmostEqual(d['phi_peak_deg'], math.degrees(math.asin(3.6 / 7.2)), places=9)
        self.assertAlmostEqual(d['strain_at_peak'], 0.05, places=12)
        self.assertTrue(d['peak_reached'])

    def test_dilatancy_of_a_straight_volume_curve(self):
        a = np.linspace(0, 0.05, 51)
        # d eps_v / d eps_a = -0.5: sin(psi) = 0.5 / 2.5
        psi = dilatancy(a, -0.5 * a, 0.01)
        self.assertTrue(np.allclose(psi[np.isfinite(psi)], math.degrees(math.asin(0.2)), atol=1e-9))
        d = derived(curve(a, np.full(51, 0.9), -0.5 * a))
        self.assertAlmostEqual(d['psi_max_deg'], math.degrees(math.asin(0.2)), places=9)
        self.assertAlmostEqual(d['dvol_rate_end'], -0.5, places=9)
        self.assertFalse(d['critical_state'])  # still dilating

    def test_e50_of_a_linear_then_flat_curve(self):
        a = np.linspace(0, 0.02, 201)
        p = 1e5
        q = np.minimum(2e7 * a, 2e5)  # E = 2e7 Pa up to q = 2e5, then flat
        d = derived(curve(a, q / p, 0 * a, p))
        self.assertAlmostEqual(d['E50_Pa'] / 2e7, 1.0, places=9)
        self.assertTrue(d['critical_state'])

    def test_too_few_records_are_refused(self):
        with self.assertRaises(ValueError) as e:
            derived(curve([0, 0.01], [0, 1], [0, 0]))
        self.assertIn('at least 3', str(e.exception))

    def test_the_count_needed(self):
        rows = [dict(n=n, phi_peak_deg=phi, wall_s=n, steps=100 * n) for n, phi in
                ((5, 30.0), (10, 33.8), (20, 34.2), (40, 34.6))]
        self.assertEqual(needed(rows)['n'], 10)
        self.assertIn('n = 10', verdict(rows))
        rows[1]['phi_peak_deg'] = 32.0  # 10 off by 2.6: 20 is the first from which all are within 1 degree
        self.assertEqual(needed(rows)['n'], 20)
        rows[2]['phi_peak_deg'] = 36.0
        self.assertIsNone(needed(rows))
        self.assertIn('has not settled', verdict(rows))


def run(args, **kw):
    return subprocess.run([BINARY, 'triaxial'] + args, capture_output=True, text=True, timeout=900, **kw)


def readCsv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


class Command(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.dir.name, 'OUT')
        t = time.time()
        cls.first = run([GRAIN, '-o', cls.out, '--spheres', '4,6', '--strain', '0.006'] + SMALL)
        cls.seconds = time.time() - t

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_the_files_agree(self):
        self.assertEqual(self.first.returncode, 0, self.first.stderr)
        summary = readCsv(os.path.join(self.out, 'summary.csv'))
        self.assertEqual([int(r['n']) for r in summary], [4, 6])
        records = readCsv(os.path.join(self.out, 'triaxial.csv'))
        for col in ('n', 'axial_strain', 'volumetric_strain', 'p_Pa', 'q_Pa'):
            self.assertIn(col, records[0])
        for row in summary:
            mine = [dict((k, float(v)) for k, v in r.items() if k != 'phase') for r in records if r['n'] == row['n']]
            self.assertGreaterEqual(len(mine), 20)
            # the summary's figures are the records' own
            d = derived(mine)
            for k in ('phi_peak_deg', 'phi_cs_deg', 'psi_max_deg', 'e0', 'E50_Pa'):
                self.assertEqual(float(row[k]), d[k], k)
            self.assertGreaterEqual(mine[-1]['axial_strain'], 0.006)
            self.assertEqual(int(row['clumps']), 12)
            self.assertGreater(int(row['steps']), 0)
        with open(os.path.join(self.out, 'summary.json')) as f:
            js = json.load(f)
        self.assertEqual([r['phi_peak_deg'] for r in js['summary']], [float(r['phi_peak_deg']) for r in summary])
        for png in ('curves.png', 'sphere_count.png'):
            with open(os.path.join(self.out, png), 'rb') as f:
                self.assertEqual(f.read(8), b'\x89PNG\r\n\x1a\n')
        with open(os.path.join(self.out, 'report.html')) as f:
            page = f.read()
        self.assertIn(verdict(js['summary']).replace("'", '&#x27;'), page)
        self.assertIn('phi_peak', self.first.stdout)

    def test_a_rerun_skips_what_is_done(self):
        before = os.stat(os.path.join(self.out, 'runs', 'n4', 'result.json')).st_mtime_ns
        again = run([GRAIN, '-o', self.out, '--spheres', '4,6', '--strain', '0.006'] + SMALL)
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertEqual(os.stat(os.path.join(self.out, 'runs', 'n4', 'result.json')).st_mtime_ns, before)
        self.assertNotIn('to run', again.stderr)
        # another option is another test: n=4 runs again (in a copy: the other tests read this one)
        copy = os.path.join(self.dir.name, 'copy')
        shutil.copytree(self.out, copy)
        other = run([GRAIN, '-o', copy, '--spheres', '4', '--strain', '0.004'] + SMALL)
        self.assertEqual(other.returncode, 0, other.stderr)
        self.assertIn('1 to run', other.stderr)


class Stopping(unittest.TestCase):
    def stopAndResume(self, sig, group):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'OUT')
            args = [BINARY, 'triaxial', GRAIN, '-o', out, '--spheres', '5', '--strain', '0.02'] + SMALL
            proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                    start_new_session=True)
            progress = os.path.join(out, 'runs', 'n5', 'progress.json')
            deadline = time.time() + 300
            while time.time() < deadline:
                try:
                    with open(progress) as f:
                        s = json.load(f)
                    if s['phase'] == 'shear' and s['fraction'] > 0.2:
                        break
                except (OSError, ValueError):
                    pass
                time.sleep(0.2)
            if group:
                os.killpg(proc.pid, sig)
            else:
                os.kill(proc.pid, sig)
            out_, err = proc.communicate(timeout=120)
            self.assertIn(proc.returncode, (130, 128 + sig), err)
            # what was recorded is written
            records = readCsv(os.path.join(out, 'triaxial.csv'))
            self.assertGreater(len(records), 2)
            self.assertTrue(os.path.isfile(os.path.join(out, 'runs', 'n5', 'checkpoint.yade.gz')))
            self.assertFalse(os.path.exists(os.path.join(out, 'runs', 'n5', 'result.json')))
            with open(os.path.join(out, 'runs', 'n5', 'checkpoint.json')) as f:
                compaction = json.load(f)['compaction']
            self.assertIsNotNone(compaction)
            again = subprocess.run(args, capture_output=True, text=True, timeout=600)
            self.assertEqual(again.returncode, 0, again.stderr)
            with open(os.path.join(out, 'runs', 'n5', 'yade.log')) as f:
                log = f.read()
            with open(os.path.join(out, 'runs', 'n5', 'result.json')) as f:
                self.assertEqual(json.load(f)['compaction'], compaction)  # not compacted again
            final = readCsv(os.path.join(out, 'triaxial.csv'))
            self.assertGreaterEqual(float(final[-1]['axial_strain']), 0.02)
            # the records before the stop are kept as they were: the rerun went on from the checkpoint
            self.assertEqual(final[0], records[0])
            self.assertIn('Running script', log)

    def test_ctrl_c_to_the_group(self):
        self.stopAndResume(signal.SIGINT, True)

    def test_sigterm_to_the_command_alone(self):
        self.stopAndResume(signal.SIGTERM, False)


class Inputs(unittest.TestCase):
    """What a study is made of: files, folders, labelled scans, batch folders, other generators' spheres."""

    def test_a_folder_of_meshes_and_a_labelled_scan(self):
        from yade_mss.studies import resolveInputs
        with tempfile.TemporaryDirectory() as d:
            for f in ('ellipsoid_2_1_1.stl', 'octahedron.stl'):
                shutil.copy(os.path.join(DATA, f), d)
            self.assertEqual([g.name for g in resolveInputs(d, None, {})], ['ellipsoid_2_1_1.stl', 'octahedron.stl'])
        labels = os.path.join(DATA, 'two_grains_labels.npy')
        grains = resolveInputs(labels, None, dict(voxelSize=1e-3))
        self.assertEqual([g.label for g in grains], [1, 2])  # each label a grain, once: the scan's proportions
        with self.assertRaises(ValueError) as e:
            resolveInputs(labels, None, {})
        self.assertIn('voxel edge in metres', str(e.exception))

    def test_a_batch_folder_is_its_grains_with_its_voxel_size(self):
        from yade_mss import batch
        from yade_mss.studies import resolveInputs
        with tempfile.TemporaryDirectory() as d:
            batch([os.path.join(DATA, 'two_grains_labels.npy')], d, nSpheres=6, voxelSize=1e-3, workers=1)
            gen = {}
            grains = resolveInputs(d, None, gen)
            self.assertEqual([(g.name, g.label) for g in grains], [('label_1', 1), ('label_2', 2)])
            self.assertEqual(gen['voxelSize'], 1e-3)
            r = grains[0].at(5, gen)
            self.assertLessEqual(len(r), 5)
            self.assertIsNotNone(r.targetMass)

    def test_another_generators_spheres_with_their_grain(self):
        from yade_mss import massProperties
        from yade_mss.studies import resolveInputs
        ell = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
        clump = os.path.join(DATA, 'clump', 'FA_ellipsoid_N10_min.txt')
        g, = resolveInputs(clump, ell, dict(scale=1e-3))
        self.assertEqual(len(g.fixed), 10)
        # the grain's exact volume, scaled, carries the mass
        self.assertAlmostEqual(g.fixed.targetMass.volume / (massProperties(ell).volume * 1e-9), 1.0, places=12)
        for args, words in (((clump, None, {}), 'name the grain'),
                            ((ell, ell, {}), 'none is'),
                            ((os.path.join(DATA, 'clump', 'EU_femur_N70_div150_rMin4_ov0.95.txt'),
                              os.path.join(DATA, 'human_femur.stl'), {}), 'another frame')):
            with self.subTest(args=args[0]):
                with self.assertRaises(ValueError) as e:
                    resolveInputs(*args)
                self.assertIn(words, str(e.exception))

    def test_a_sphere_file_study_and_dask(self):
        """Another generator's clump through the whole test, its own count labelling it; run as a task of a Dask
        cluster (a local one: the scheduler's address as a user gives it)."""
        from distributed import LocalCluster
        ell = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
        clump = os.path.join(DATA, 'clump', 'FA_ellipsoid_N10_min.txt')
        with tempfile.TemporaryDirectory() as d, LocalCluster(n_workers=1, threads_per_worker=1,
                                                              dashboard_address=None) as cluster:
            r = triaxialStudy(clump, d, grain=ell, scale=1e-3, grains=10, strain=0.004, records=20, seed=4,
                              scheduler=cluster.scheduler_address, quiet=True)
            self.assertEqual(r['failed'], {})
            self.assertEqual([row['n'] for row in r['summary']], [10])
            self.assertTrue(os.path.isfile(os.path.join(d, 'runs', 'n10', 'result.json')))
            self.assertGreaterEqual(r['records'][-1]['axial_strain'], 0.004)
            with self.assertRaises(ValueError) as e:
                triaxialStudy(clump, d, grain=ell, nSpheres=[5, 10], scale=1e-3)
            self.assertIn('its own count', str(e.exception))


class Refusals(unittest.TestCase):
    def test_before_any_work(self):
        with tempfile.TemporaryDirectory() as d:
            spheres = os.path.join(d, 's.csv')
            with open(spheres, 'w') as f:
                f.write('0,0,0,1\n1,0,0,1\n')
            for args, words in (([GRAIN, '-o', d + '/o'], 'voxel edge in metres'),
                                ([spheres, '-o', d + '/o'], '--grain'),
                                ([GRAIN, '-o', d + '/o', '--voxel-size', '1.25e-5', '--max-work', '1'],
                                 'would take about'),
                                ([GRAIN, '-o', d + '/o', '--state', 'medium'], '--state'),
                                ([GRAIN, '-o', d + '/o', '--spheres', '4,x'], "--spheres: 'x' is not an integer"),
                                ([os.path.join(d, 'nothing.stl'), '-o', d + '/o'], 'no such file')):
                with self.subTest(args=args):
                    r = run(args)
                    self.assertEqual(r.returncode, 1, r.stderr)
                    self.assertIn(words, r.stderr)
                    self.assertNotIn('Traceback', r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, 'o', 'runs')))
            r = run([GRAIN, '-o', d + '/o', '--spheres', '4', '--grian', 'x'])
            self.assertEqual(r.returncode, 2)  # no abbreviations, no misspellings
            self.assertIn('--grian', r.stderr)

    def test_the_defaults_are_the_option_tables(self):
        import inspect
        from yade_mss.studies import TEST_DEFAULTS, triaxial
        params = inspect.signature(triaxial).parameters
        for k, v in TEST_DEFAULTS.items():
            self.assertEqual(params[k].default, v, k)

    def test_the_python_function_checks_its_keywords(self):
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(TypeError) as e:
                triaxialStudy(GRAIN, d, nSpheres=4, voxelSize=1.25e-5, grainz=5)
            self.assertIn('grainz', str(e.exception))
            with self.assertRaises(TypeError):
                triaxialStudy(GRAIN, d, nSpheres=4, voxelSize=1.25e-5, undrained='no')
            with self.assertRaises(ValueError) as e:
                triaxialStudy(GRAIN, d, nSpheres=[4, 0], voxelSize=1.25e-5)
            self.assertIn('nSpheres', str(e.exception))


if __name__ == '__main__':
    unittest.main()
