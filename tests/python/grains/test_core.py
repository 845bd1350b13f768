"""yade_mss without YADE: generation, scoring, mass properties, files. Run with /usr/bin/python3."""
import math
import os
import re
import sys
import tempfile
import unittest
import warnings

import numpy as np

import yade_mss
from yade_mss import generate, massProperties, readSpheres, score, MssResult

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
FEMUR = os.path.join(DATA, 'human_femur.stl')


class Generate(unittest.TestCase):
    def test_mesh_file(self):
        r = generate(ELL, nSpheres=6, resolution=40)
        self.assertEqual(len(r), 6)
        self.assertEqual(r.centers.shape, (6, 3))
        self.assertLess(r.metrics['dice'], 0.05)
        self.assertAlmostEqual(r.targetMass.volume, 8.373, places=2)

    def test_mesh_in_memory_gives_the_same_spheres(self):
        from yade_mss import _mss
        v, t = _mss.readMesh(ELL)
        a = generate((np.array(v).reshape(-1, 3), np.array(t).reshape(-1, 3)), nSpheres=5, resolution=30)
        b = generate(ELL, nSpheres=5, resolution=30)
        np.testing.assert_array_equal(a.centers, b.centers)
        np.testing.assert_array_equal(a.radii, b.radii)

    def test_binding_reads_number_buffers_as_it_reads_lists(self):
        # the binding copies a contiguous buffer of float64, float32, int32 or int64 at once; other layouts
        # (strided, big endian) go through tolist(): every one gives what the list gives
        from yade_mss import _mss
        v, t = _mss.readMesh(FEMUR)
        V, T = np.array(v), np.array(t, dtype=np.int64)
        want = _mss.massMesh(list(v), list(t), [])
        for vv, tt in ((V, T), (V, T.astype(np.int32)), (V.astype('>f8'), T.astype('>i8')),
                       (np.repeat(V, 2)[::2], np.repeat(T, 2)[::2]), (V.reshape(-1, 3), T.reshape(-1, 3))):
            got = _mss.massMesh(vv, tt, [])
            self.assertEqual(got['volume'], want['volume'])
            self.assertEqual(list(got['inertia']), list(want['inertia']))
        f32 = _mss.massMesh(V.astype(np.float32), T, [])  # float32 values widened exactly
        self.assertEqual(f32['volume'], _mss.massMesh(V.astype(np.float32).astype(float), T, [])['volume'])
        with self.assertRaisesRegex(ValueError, 'indices must be integers'):
            _mss.massMesh(V, T + 0.5, [])
        with self.assertRaisesRegex(ValueError, 'triples'):
            _mss.massMesh(V[:-1], T, [])
        with self.assertRaisesRegex(ValueError, 'not a number'):
            _mss.massMesh(np.array(['a'] * 9), T[:3], [])

    def test_voxel_array_keeps_world_positions(self):
        # a ball of radius 8 voxels centred at voxel (20, 18, 16), voxel size 0.5, origin (1, 2, 3)
        i, j, k = np.mgrid[0:40, 0:36, 0:32]
        ball = (i - 20) ** 2 + (j - 18) ** 2 + (k - 16) ** 2 <= 64
        r = generate(ball, nSpheres=1, voxelSize=0.5, origin=(1, 2, 3))
        np.testing.assert_allclose(r.centers[0], [1 + 10, 2 + 9, 3 + 8], atol=0.25)  # half a voxel
        self.assertAlmostEqual(r.radii[0], 4.0, delta=0.25)
        self.assertAlmostEqual(r.targetMass.volume, ball.sum() * 0.125)

    def test_labelled_volume(self):
        a = np.zeros((20, 20, 20), dtype=np.uint8)
        a[3:8, 3:8, 3:8] = 1
        a[10:18, 10:18, 10:18] = 2
        r = generate(a, nSpheres=1, label=2)
        self.assertTrue(np.all(r.centers[0] > 10) and np.all(r.centers[0] < 18))

    def test_eta_target(self):
        r = generate(FEMUR, eta=0.1, resolution=40)
        self.assertLessEqual(r.metrics['eta'], 0.1)

    def test_bad_input_is_a_value_error_naming_the_problem(self):
        cases = [
            (lambda: generate(ELL, nSpheres=0), 'nSpheres'),
            (lambda: generate(ELL, nSpheres=3, resolution=0), 'resolution'),
            (lambda: generate(ELL, nSpheres=3, resolution=10 ** 6), 'would need'),
            (lambda: generate(ELL), 'termination criterion'),
            (lambda: generate('missing.stl', nSpheres=3), 'cannot open'),
            (lambda: generate('grain.xyz', nSpheres=3), 'unknown mesh extension'),
            (lambda: generate(np.zeros((4, 4)), nSpheres=3), '3-D'),
            (lambda: generate(np.zeros((4, 4, 4), dtype=bool), nSpheres=3), 'no solid voxel'),
            (lambda: generate(np.ones((4, 4, 4), dtype=float), nSpheres=3), 'not boolean or integer'),
            (lambda: generate(ELL, nSpheres=3, method='best'), 'method'),
            (lambda: generate(42, nSpheres=3), 'source must be'),
        ]
        for f, fragment in cases:
            with self.assertRaises(ValueError) as ctx:
                f()
            self.assertIn(fragment, str(ctx.exception))


class Clipping(unittest.TestCase):
    def test_protrusion_bound(self):
        femur = os.path.join(DATA, 'human_femur.stl')
        r = generate(femur, nSpheres=15, resolution=30)  # default: one voxel of the generation grid
        h = r.grid['voxelSize']
        self.assertAlmostEqual(r.metrics['protrusionLimit'], h)
        self.assertLessEqual(r.metrics['protrusion'], h * (1 + 1e-9))
        self.assertLessEqual(yade_mss.compareMany(femur, [r], resolution=40)[0]['protrusion'], h * (1 + 1e-9))
        free = generate(femur, nSpheres=15, resolution=30, maxProtrusion=float('inf'))
        self.assertEqual(free.metrics['protrusionLimit'], float('inf'))
        self.assertGreater(free.metrics['protrusion'], 1.3 * h)
        two = generate(femur, nSpheres=15, resolution=30, maxProtrusion=2.0)
        self.assertLessEqual(two.metrics['protrusion'], 2.0 * (1 + 1e-9))
        with tempfile.TemporaryDirectory() as d:  # an infinite limit survives saving
            free.save(os.path.join(d, 'f.npz'))
            self.assertEqual(MssResult.load(os.path.join(d, 'f.npz')).metrics['protrusionLimit'], float('inf'))
        for bad, msg in ((-1, 'maxProtrusion must be >= 0'), (float('nan'), 'maxProtrusion must be >= 0')):
            with self.assertRaisesRegex(ValueError, msg):
                generate(femur, nSpheres=3, resolution=20, maxProtrusion=bad)
        with self.assertRaisesRegex(ValueError, 'clip means maxProtrusion 0'):
            generate(femur, nSpheres=3, resolution=20, clip=True, maxProtrusion=1.0)

    def test_clip_and_planes(self):
        r = generate(FEMUR, nSpheres=20, resolution=40, clip=True,
                     planes=[((0, 0, -90), (0, 0, 1))])
        self.assertGreater(len(r), 5)
        self.assertTrue(np.all(r.centers[:, 2] - r.radii >= -90 - 1e-9))
        self.assertEqual(score(FEMUR, r, resolution=40)['outside'], 0.0)
        with self.assertRaises(ValueError):
            generate(FEMUR, nSpheres=3, planes=[((0, 0, 0), (0, 0))])

    def test_fragment(self):
        # a plane through the grain: the target is the part on its allowed side (mass, mismatch, targets)
        whole = massProperties(FEMUR)
        up, down = ((whole.centroid, (0.1, 0.2, 1.0)), (whole.centroid, (-0.1, -0.2, -1.0)))
        a, b = massProperties(FEMUR, planes=[up]), massProperties(FEMUR, planes=[down])
        self.assertAlmostEqual(a.volume + b.volume, whole.volume, delta=1e-9 * whole.volume)
        self.assertGreater(a.volume, 0.2 * whole.volume)
        r = generate(FEMUR, dice=0.06, resolution=40, planes=[up])
        self.assertAlmostEqual(r.targetMass.volume, a.volume, delta=1e-9 * a.volume)
        self.assertLessEqual(r.metrics['dice'], 0.06)  # reachable: the whole grain would leave D near 0.5
        n = np.array([0.1, 0.2, 1.0]) / np.linalg.norm([0.1, 0.2, 1.0])
        self.assertTrue(np.all((r.centers - whole.centroid) @ n - r.radii >= -1e-9))
        # scored against the same fragment on an independent grid, and against the whole grain
        self.assertLess(score(FEMUR, r, planes=[up])['dice'], 0.08)
        self.assertGreater(score(FEMUR, r)['dice'], 0.2)
        v = np.load(os.path.join(DATA, 'grain_voxels_155x157x167.npy'))
        g = massProperties(v)
        h = massProperties(v, planes=[(g.centroid, (1, 0, 0))])
        self.assertGreater(h.volume, 0.3 * g.volume)
        self.assertLess(h.volume, 0.7 * g.volume)
        self.assertGreater(h.centroid[0], g.centroid[0])
        with self.assertRaises(ValueError) as ctx:
            generate(FEMUR, nSpheres=3, resolution=20, planes=[((0, 0, 1e6), (0, 0, 1))])
        self.assertIn('allowed side of the planes', str(ctx.exception))
        for src in (FEMUR, v):
            with self.assertRaises(ValueError) as ctx:
                massProperties(src, planes=[((0, 0, 1e6), (0, 0, 1))])
            self.assertIn('allowed side of the planes', str(ctx.exception))

    def test_open_mesh_warns(self):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter('always')
            generate(os.path.join(DATA, 'stanford_bunny_open.stl'), nSpheres=5, resolution=30)
        self.assertTrue(any('not closed' in str(x.message) for x in w))


class Files(unittest.TestCase):
    def test_save_and_load(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, 'r.npz')
            r.save(p)
            q = MssResult.load(p)
        np.testing.assert_array_equal(q.centers, r.centers)
        np.testing.assert_array_equal(q.radii, r.radii)
        self.assertEqual(q.metrics['dice'], r.metrics['dice'])
        np.testing.assert_array_equal(q.targetMass.inertia, r.targetMass.inertia)
        with self.assertRaises(ValueError):
            MssResult.load(ELL)

    def test_our_stored_npz_is_what_numpy_reads_and_zip_checks(self):
        # a batch writes one .npz a grain through storedNpz (np.savez's ZipFile was a third of its time a
        # grain): numpy gives the arrays back, bit for bit, and the zip's own checks (CRCs, directory) pass
        import io
        import zipfile
        from yade_mss.grains._results import storedNpz
        arrays = {'centers': np.random.default_rng(1).normal(size=(7, 3)), 'radii': np.arange(7.0),
                  'empty': np.zeros((0, 3)), 'ints': np.arange(-3, 3, dtype=np.int32).reshape(2, 3),
                  'meta': np.array('{"text": "\u00e9\u4e2d", "n": 1}'), 'scalar': np.float64(2.5)}
        data = storedNpz(arrays)
        with zipfile.ZipFile(io.BytesIO(data)) as z:
            self.assertIsNone(z.testzip())
            self.assertEqual(z.namelist(), [k + '.npy' for k in arrays])
        with np.load(io.BytesIO(data), allow_pickle=False) as f:
            for k, a in arrays.items():
                self.assertEqual(f[k].dtype, np.asarray(a).dtype, k)
                np.testing.assert_array_equal(f[k], a)
        self.assertEqual(storedNpz(arrays), data)  # no date in it: the same arrays, the same bytes
        with self.assertRaisesRegex(ValueError, 'storedNpz: odd holds Python objects'):
            storedNpz({'odd': np.array([{'a': 1}], dtype=object)})  # its bytes would be pointers
        r = generate(ELL, nSpheres=4)
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, 'r.npz')
            with open(p, 'wb') as f:
                f.write(r._npzBytes())
            q = MssResult.load(p)  # the saved result's own checks (_checkArchive) pass
        np.testing.assert_array_equal(q.centers, r.centers)
        self.assertEqual(q.metrics['dice'], r.metrics['dice'])

    def test_read_clump_and_yade_files(self):
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, 'clump.csv')
            with open(csv, 'w') as f:
                f.write('x,y,z,r\n0,0,0,1\n1,0,0,1\n')
            txt = os.path.join(d, 'yade.txt')
            with open(txt, 'w') as f:
                f.write('# x y z r id\n0 0 0 1 0\n1 0 0 1 0\n')
            for p in (csv, txt):
                s = readSpheres(p)
                self.assertEqual(len(s), 2)
                self.assertIsNone(s.targetMass)
                # union of two unit spheres one radius apart: 2 * 4/3 pi - 5 pi / 12
                self.assertAlmostEqual(s.unionMass().volume, 8 * math.pi / 3 - 5 * math.pi / 12, delta=0.01)


    def test_save_sphere_files_as_the_command_line_does(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        with tempfile.TemporaryDirectory() as d:
            for ext in ('.csv', '.txt'):
                p = os.path.join(d, 'r' + ext)
                r.save(p)
                q = readSpheres(p)
                np.testing.assert_array_equal(q.centers, r.centers)  # full precision
                np.testing.assert_array_equal(q.radii, r.radii)
            r.save(os.path.join(d, 'r.vtk'))
            text = open(os.path.join(d, 'r.vtk')).read()
            self.assertIn('POINTS 4 double', text)
            self.assertIn('SCALARS radius', text)
            with self.assertRaises(ValueError):
                r.save(os.path.join(d, 'r.xyz'))
            self.assertEqual(sorted(os.listdir(d)), ['r.csv', 'r.txt', 'r.vtk'])  # no temporary left

    def test_yade_file_of_several_clumps_is_never_merged(self):
        with tempfile.TemporaryDirectory() as d:
            txt = os.path.join(d, 'clumps.txt')
            with open(txt, 'w') as f:
                f.write('#format x_y_z_r_clumpId\n0\t0\t0\t1\t4\n1\t0\t0\t1\t4\n9\t0\t0\t2\t12\n')
            with self.assertRaises(ValueError) as ctx:
                readSpheres(txt)
            self.assertIn('holds 2 clumps (ids 4, 12)', str(ctx.exception))
            self.assertEqual(len(readSpheres(txt, clumpId=4)), 2)
            self.assertEqual(readSpheres(txt, clumpId=12).radii.tolist(), [2.0])
            with self.assertRaises(ValueError) as ctx:
                readSpheres(txt, clumpId=5)
            self.assertIn('no clump with id 5', str(ctx.exception))

    def test_error_messages_are_text_whatever_the_bytes(self):
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, 'mu.csv')
            with open(p, 'wb') as f:
                f.write(b'x,y,z,r\n0,0,\xb5,1\n')
            with self.assertRaises(ValueError) as ctx:
                readSpheres(p)
            self.assertIn("'\\xb5' is not a number", str(ctx.exception))

    def test_labelled_volume_needs_a_label(self):
        a = np.zeros((10, 10, 10), dtype=np.uint16)
        a[1:4, 1:4, 1:4] = 3
        a[6:9, 6:9, 6:9] = 9
        with self.assertRaises(ValueError) as ctx:
            generate(a, nSpheres=2)
        self.assertIn('2 labels (3, 9)', str(ctx.exception))
        self.assertEqual(len(generate(a, nSpheres=1, label=9)), 1)
        b = (a > 0).astype(np.uint8) * 255  # one value: a plain mask
        self.assertEqual(len(generate(b, nSpheres=2)), 2)


class Comparisons(unittest.TestCase):
    def test_compare_many_reads_every_clump_format(self):
        from yade_mss import compareMany
        C = os.path.join(DATA, 'clump')
        rows = compareMany(ELL, [os.path.join(C, 'FA_ellipsoid_N10_min.txt'), os.path.join(C, 'FA_ellipsoid_N10_min.vtk'),
                                 generate(ELL, nSpheres=10, resolution=60)])
        self.assertEqual([r['spheres'] for r in rows], [10, 10, 10])
        self.assertAlmostEqual(rows[0]['dice'], rows[1]['dice'], places=4)  # the text and the VTK file agree
        self.assertAlmostEqual(rows[0]['dice'], 0.0114, delta=0.001)  # shared/data/clump/README.md
        self.assertLess(rows[2]['dice'], rows[0]['dice'])
        for r in rows:
            self.assertGreaterEqual(r['protrusion'], 0.0)
            self.assertLess(abs(r['massError']), 0.1)

    def test_another_frame_is_refused_then_aligned(self):
        from yade_mss import compareMany
        eu = os.path.join(DATA, 'clump', 'EU_femur_N70_div150_rMin4_ov0.95.txt')
        with self.assertRaises(ValueError) as ctx:
            compareMany(FEMUR, [eu])
        self.assertIn("the option align (bbox, centroid or principal)", str(ctx.exception))
        row = compareMany(FEMUR, [eu], align='bbox')[0]
        self.assertLessEqual(row['dice'], 0.085)
        self.assertGreater(np.linalg.norm(row['translation']), 100)
        self.assertEqual(compareMany(FEMUR, [eu], align='none')[0]['dice'], 1.0)  # as written: no overlap
        self.assertIn(eu, str(ctx.exception))  # the file at fault named, not the grain

    def test_align_registers_only_a_file_in_another_frame_and_a_bad_file_is_a_row(self):
        # the bugs: --align principal re-registered our own file too (D 0.0278 -> 0.0305); one Euclidean file
        # aborted the whole table; an in-memory result was labelled with the grain's file name
        from yade_mss import compareMany
        eu = os.path.join(DATA, 'clump', 'EU_femur_N70_div150_rMin4_ov0.95.txt')
        ours = generate(FEMUR, nSpheres=20, resolution=40)
        plain, aligned = compareMany(FEMUR, [ours], resolution=40)[0], \
            compareMany(FEMUR, [ours, eu], resolution=40, align='principal')
        self.assertEqual(aligned[0]['dice'], plain['dice'])  # in the grain's frame: scored as written
        np.testing.assert_array_equal(aligned[0]['translation'], [0, 0, 0])
        self.assertGreater(np.linalg.norm(aligned[1]['translation']), 100)  # the other frame: registered
        self.assertEqual(aligned[0]['file'], 'result 1 (human_femur.stl)')
        rows = compareMany(FEMUR, [eu, ours], resolution=40)
        self.assertEqual(len(rows), 2)
        self.assertIn('another frame', rows[0]['error'])
        self.assertTrue(rows[0]['error'].startswith(eu))
        self.assertEqual(rows[1]['error'], '')
        self.assertEqual(rows[1]['dice'], plain['dice'])


class Scoring(unittest.TestCase):
    def test_score_prefers_more_spheres(self):
        few = score(FEMUR, generate(FEMUR, nSpheres=5, resolution=40), resolution=50)
        many = score(FEMUR, generate(FEMUR, nSpheres=40, resolution=40), resolution=50)
        self.assertLess(many['dice'], few['dice'])
        self.assertGreater(many['coverage'], few['coverage'])

    def test_mass_properties_of_the_ellipsoid(self):
        m = massProperties(ELL)
        w, v = m.principal()
        V = 8 * math.pi / 3
        np.testing.assert_allclose(w, V * np.array([2, 5, 5]) / 5, rtol=2e-3)
        self.assertAlmostEqual(abs(v[0, 0]), 1.0, places=9)


def runFemur(env, look=None):
    """Runs `mss generate` on the femur with @env; while it works, calls look(pid) every 5 ms until that returns
    something other than None. Returns (that or None, the command's stderr)."""
    import subprocess
    import time
    mss = os.environ.get('MSS_BINARY', 'mss')
    seen = None
    with tempfile.TemporaryDirectory() as d:
        p = subprocess.Popen([mss, 'generate', FEMUR, '--spheres', '70', '--resolution', '150', '-o',
                              os.path.join(d, 's.csv')], env=env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
        deadline = time.time() + 10
        while look and seen is None and time.time() < deadline and p.poll() is None:
            try:
                seen = look(p.pid)
            except OSError:
                break
            time.sleep(0.005)
        err = p.communicate()[1].decode()
        if p.returncode != 0:
            raise RuntimeError('mss generate failed: ' + err)
    return seen, err


def openmpSettings(err):
    """What libgomp printed of its settings (OMP_DISPLAY_ENV=VERBOSE), the last time: a command that runs itself
    again with its choices (the dynamically linked build) prints them twice."""
    blocks = err.split('OPENMP DISPLAY ENVIRONMENT BEGIN')
    if len(blocks) < 2:
        return None
    return dict(re.findall(r"^\s*([A-Z_]+) = '([^']*)'", blocks[-1], re.M))


def heapOnHugePages(pid):
    """True when a mapping of the process's heap is marked for transparent huge pages (VmFlags hg), else None."""
    heap = False
    with open('/proc/%d/smaps' % pid) as f:
        for line in f:
            if re.match(r'^[0-9a-f]+-[0-9a-f]+ ', line):
                heap = line.rstrip().endswith('[heap]')
            elif heap and line.startswith('VmFlags:') and 'hg' in line.split()[1:]:
                return True
    return None


class SharingTheCores(unittest.TestCase):
    def test_busy_cores_make_the_command_wait_passively(self):
        # with more busy processes than cores, `mss` must run its OpenMP threads with passive waiting (no
        # spin), on as many threads as cores are free (none: one); it chooses as it starts, before libgomp
        # reads its settings, which libgomp prints here as it uses them
        import subprocess
        import time
        busy = [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range((os.cpu_count() or 1) + 1)]
        try:
            time.sleep(0.3)
            env = {k: v for k, v in os.environ.items() if k not in ('OMP_WAIT_POLICY', 'GOMP_SPINCOUNT', 'OMP_NUM_THREADS')}
            env['OMP_DISPLAY_ENV'] = 'VERBOSE'
            _, err = runFemur(env)
        finally:
            for b in busy:
                b.kill()
                b.wait()
        used = openmpSettings(err)
        self.assertIsNotNone(used, 'libgomp printed no settings: ' + err)
        self.assertEqual(used['OMP_WAIT_POLICY'], 'PASSIVE')
        self.assertEqual(used['GOMP_SPINCOUNT'], '0')  # no spinning at all
        self.assertEqual(used['OMP_NUM_THREADS'], '1')  # no core is free: one thread

    def test_free_cores_make_the_command_spin_briefly(self):
        # the other side: cores free, a short spin (thousands of short parallel regions), whatever it runs on
        env = {k: v for k, v in os.environ.items() if k not in ('OMP_WAIT_POLICY', 'GOMP_SPINCOUNT', 'OMP_NUM_THREADS')}
        env['OMP_DISPLAY_ENV'] = 'VERBOSE'
        _, err = runFemur(env)
        used = openmpSettings(err)
        self.assertIsNotNone(used, 'libgomp printed no settings: ' + err)
        if used['OMP_WAIT_POLICY'] == 'PASSIVE':  # this machine was busy as it started: passive, as above
            self.assertEqual(used['GOMP_SPINCOUNT'], '0')
        else:
            self.assertEqual(used['OMP_WAIT_POLICY'], 'ACTIVE')
            self.assertEqual(used['GOMP_SPINCOUNT'], '10000')

    def test_the_command_asks_malloc_for_huge_pages(self):
        # `mss` puts malloc's heap on transparent huge pages (a fresh 4 KiB page costs a fault of 10-15 us
        # under this machine's kernel): seen in the heap's mappings while it works; malloc settings the user
        # gave (GLIBC_TUNABLES) are kept as given
        for given, expected in ((None, True), ('glibc.malloc.hugetlb=0', None)):
            env = {k: v for k, v in os.environ.items() if k not in ('OMP_WAIT_POLICY', 'GOMP_SPINCOUNT', 'GLIBC_TUNABLES')}
            if given:
                env['GLIBC_TUNABLES'] = given
            seen, _ = runFemur(env, heapOnHugePages)
            self.assertEqual(seen, expected, given)


if __name__ == '__main__':
    unittest.main()
