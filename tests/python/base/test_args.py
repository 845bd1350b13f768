"""Strict arguments of the public Python functions (no YADE needed): a bool is not a count, a string is not a
number, a non-integral resolution is not truncated, negative values are not labels. Run with /usr/bin/python3."""
import os
import tempfile
import unittest

import numpy as np

from yade_mss import MssResult, generate
from yade_mss.base import flag, integer, number, vector3
from yade_mss.base import split

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')


class Generate(unittest.TestCase):
    def refused(self, kind, fragment, **kw):
        with self.assertRaises(kind) as ctx:
            generate(ELL, **kw)
        self.assertIn(fragment, str(ctx.exception))

    def test_a_bool_is_not_a_count(self):
        # the bug: nSpheres=True gave one sphere
        self.refused(TypeError, 'nSpheres must be an integer, got True', nSpheres=True, resolution=20)

    def test_a_non_integral_resolution_is_refused(self):
        # the bug: resolution=30.5 was truncated to 30
        self.refused(ValueError, 'resolution must be an integer, got 30.5', nSpheres=3, resolution=30.5)

    def test_strings_are_not_numbers(self):
        # the bug: resolution='30' was accepted
        self.refused(TypeError, "resolution must be an integer, got '30'", nSpheres=3, resolution='30')
        self.refused(TypeError, "nSpheres must be an integer, got '3'", nSpheres='3', resolution=20)
        self.refused(TypeError, "voxelSize must be a number, got '0.1'", nSpheres=3, voxelSize='0.1')
        self.refused(TypeError, "eta must be a number", eta='0.1', resolution=20)

    def test_flags_are_true_or_false(self):
        self.refused(TypeError, 'clip must be True or False, got 1', nSpheres=3, resolution=20, clip=1)
        self.refused(TypeError, "keepSymmetry must be True or False, got 'no'", nSpheres=3, resolution=20,
                     keepSymmetry='no')

    def test_thread_counts_are_bounded(self):
        # the bug: threads=70000 crashed the process
        self.refused(ValueError, 'threads must be in [0, 1024], got 70000', nSpheres=3, resolution=20, threads=70000)
        self.refused(ValueError, 'threads must be in [0, 1024], got -1', nSpheres=3, resolution=20, threads=-1)

    def test_memory_limits_are_bounded(self):
        for bad in (float('nan'), -1, 0, float('inf'), 1e12):
            with self.assertRaises(ValueError) as ctx:
                generate(ELL, nSpheres=3, resolution=20, memoryLimit=bad)
            self.assertIn('memoryLimit', str(ctx.exception))

    def test_labels_are_non_negative_integers(self):
        a = np.zeros((8, 8, 8), dtype=np.int16)
        a[2:6, 2:6, 2:6] = 3
        for bad, kind in ((-1, ValueError), (2.5, ValueError), ('3', TypeError), (True, TypeError)):
            with self.assertRaises(kind) as ctx:
                generate(a, nSpheres=2, label=bad)
            self.assertIn('label', str(ctx.exception))
        self.assertIn(len(generate(a, nSpheres=2, label=3)), (1, 2))

    def test_a_label_for_a_mesh_is_refused(self):
        # the bug: --label (label=) was ignored for meshes
        self.refused(ValueError, 'label applies to labelled voxel volumes', nSpheres=3, resolution=20, label=2)

    def test_negative_values_are_not_a_grain(self):
        # the bug: an int16 volume of all -1 was taken as one grain
        with self.assertRaises(ValueError) as ctx:
            generate(np.full((6, 6, 6), -1, dtype=np.int16), nSpheres=2)
        self.assertIn('negative values (-1)', str(ctx.exception))

    def test_origin_is_three_numbers(self):
        a = np.zeros((8, 8, 8), dtype=bool)
        a[2:6, 2:6, 2:6] = True
        for bad, kind in (('abc', TypeError), ((1, 2), ValueError), ((1, 'x', 3), TypeError)):
            with self.assertRaises(kind) as ctx:
                generate(a, nSpheres=2, origin=bad)
            self.assertIn('origin', str(ctx.exception))

    def test_tiff_volumes_are_read_where_npy_ones_are(self):
        import tifffile
        a = np.zeros((10, 10, 10), dtype=np.uint8)
        a[2:8, 3:7, 2:8] = 1
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'g.npy'), a)
            tifffile.imwrite(os.path.join(d, 'g.tif'), a)
            r1 = generate(os.path.join(d, 'g.npy'), nSpheres=3)
            r2 = generate(os.path.join(d, 'g.tif'), nSpheres=3)
        np.testing.assert_allclose(r1.centers, r2.centers)
        np.testing.assert_allclose(r1.radii, r2.radii)


class Results(unittest.TestCase):
    def test_loading_a_sphere_file_says_read_spheres(self):
        # the bug: MssResult.load('g.csv') spoke of pickled data
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'g.csv')
            generate(ELL, nSpheres=3, resolution=20).save(f)
            with self.assertRaises(ValueError) as ctx:
                MssResult.load(f)
        self.assertIn('readSpheres', str(ctx.exception))


class Archives(unittest.TestCase):
    def test_a_small_archive_that_expands_hugely_is_refused(self):
        # the bug: a 3 MB .npz expanded to 2.8 GB in MssResult.load
        import zipfile
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'bomb.npz')
            with zipfile.ZipFile(f, 'w', zipfile.ZIP_DEFLATED) as z:
                with z.open('centers.npy', 'w', force_zip64=True) as m:
                    block = bytes(1 << 20)
                    for _ in range(1100):
                        m.write(block)
            self.assertLess(os.path.getsize(f), 4 << 20)
            with self.assertRaises(ValueError) as ctx:
                MssResult.load(f)
            self.assertIn('would take', str(ctx.exception))

    def test_nan_centres_and_negative_radii_are_not_a_result(self):
        # the bug: such a result saved and loaded
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'r.npz')
            r = generate(ELL, nSpheres=3, resolution=20)
            r.save(f)
            with np.load(f) as z:
                c, meta = z['centers'].copy(), z['meta']
            c[0, 0] = np.nan
            np.savez(f, centers=c, radii=-np.ones(len(c)), meta=meta)
            with self.assertRaises(ValueError) as ctx:
                MssResult.load(f)
            self.assertIn('finite', str(ctx.exception))
            with open(f, 'wb') as g:
                g.write(b'PK not a zip')
            with self.assertRaises(ValueError):
                MssResult.load(f)
            np.savez(f, centers=c[:1], radii=np.ones(1), meta=np.array('[1, 2]'))  # meta not a dict
            with self.assertRaises(ValueError) as ctx:
                MssResult.load(f)
            self.assertIn('not a saved result', str(ctx.exception))
        # nor is one made in memory: nothing such is saved (the bug: it saved)
        with self.assertRaises(ValueError) as ctx:
            MssResult([[np.nan, 0, 0]], [1.0])
        self.assertIn('finite', str(ctx.exception))
        with self.assertRaises(ValueError):
            MssResult([[0, 0, 0]], [-1.0])

    def test_huge_integers_are_refused_with_a_message(self):
        # the bug: Python's OverflowError ('int too large to convert to C long'), not a message
        from yade_mss import readSpheres, regions, score, syntheticSpecimen
        Generate.refused(self, ValueError, 'nSpheres must be in [1, 65535], got 10' + '0' * 29, nSpheres=10 ** 30)
        Generate.refused(self, ValueError, 'resolution must be in [1, 2147483647]', nSpheres=3, resolution=10 ** 30)
        spheres = os.path.join(DATA, '..', 'corpus', 'files', 'two_clumps.txt')
        for v in (float('inf'), 10 ** 30, -10 ** 20):
            with self.assertRaises(ValueError) as ctx:
                readSpheres(spheres, clumpId=v)
            self.assertIn('clumpId must be', str(ctx.exception))
            with self.assertRaises(ValueError) as ctx:
                score(ELL, spheres, resolution=v)
            self.assertIn('resolution must be', str(ctx.exception))
            with self.assertRaises(ValueError):
                MssResult([[0, 0, 0]], [1.0]).unionMass(v)
        with self.assertRaises(ValueError) as ctx:
            regions(10 ** 30)
        self.assertIn('3-D array of integers', str(ctx.exception))

    def test_out_of_memory_is_a_runtime_error_with_the_remedy(self):
        # the bug: a bare bad_alloc; the address space of a child is capped at 6 GB, the machine untouched
        import subprocess
        import sys
        code = ("import resource, yade_mss\nresource.setrlimit(resource.RLIMIT_AS, (6 << 30, 6 << 30))\ntry:\n"
                "    yade_mss.generate(%r, nSpheres=3, resolution=1200, memoryLimit=100000)\n"
                "except RuntimeError as e:\n    print('RuntimeError:', e)\n" % os.path.join(DATA, 'cube.stl'))
        out = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=300)
        self.assertIn('RuntimeError: out of memory: the machine could not give', out.stdout, out.stderr)

    def test_a_specimen_of_no_grains_is_refused_at_once(self):
        # the bug: grains=-1 tried 20000 placements (minutes) for nothing
        from yade_mss import syntheticSpecimen
        for kw, fragment in (({'grains': -1}, 'grains must be >= 1'), ({'grains': True}, 'grains must be an integer'),
                             ({'shape': (30, 30)}, 'shape must be 3 integers'), ({'size': (9, 3)}, 'size must be'),
                             ({'gap': -1}, 'gap must be >= 0'), ({'shape': (10 ** 4,) * 3}, 'over 2^31 voxels')):
            with self.assertRaises((TypeError, ValueError)) as ctx:
                syntheticSpecimen(**dict({'shape': (30, 30, 30), 'grains': 2}, **kw))
            self.assertIn(fragment, str(ctx.exception))

    def test_grains_that_cannot_fit_give_up_with_a_warning(self):
        # the bug: 60 grains of 8 to 14 voxels in 40^3 ran past 60 s, then returned fewer without a word
        import warnings
        from yade_mss import syntheticSpecimen
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter('always')
            L = syntheticSpecimen(shape=(40, 40, 40), grains=60, size=(8, 14))
        said = [str(w.message) for w in caught if 'syntheticSpecimen' in str(w.message)]
        self.assertEqual(len(said), 1)
        self.assertIn('%d of 60 grains placed: the rest do not fit' % L.max(), said[0])
        self.assertLess(L.max(), 60)


class Checks(unittest.TestCase):
    def test_integer(self):
        self.assertEqual(integer('f', 'n', 3.0), 3)
        self.assertEqual(integer('f', 'n', np.int64(4), 1), 4)
        for bad, kind in ((True, TypeError), ('3', TypeError), (3.5, ValueError), (float('nan'), ValueError),
                          (0, ValueError), (None, TypeError)):
            with self.assertRaises(kind):
                integer('f', 'n', bad, 1)

    def test_number_flag_vector(self):
        self.assertEqual(number('f', 'x', np.float32(0.5)), 0.5)
        for bad, kind in ((True, TypeError), ('1', TypeError), (float('inf'), ValueError), (-1, ValueError)):
            with self.assertRaises(kind):
                number('f', 'x', bad, 0)
        self.assertTrue(flag('f', 'b', np.bool_(True)))
        with self.assertRaises(TypeError):
            flag('f', 'b', 0)
        np.testing.assert_array_equal(vector3('f', 'v', (1, 2, 3)), [1, 2, 3])
        with self.assertRaises(TypeError):
            vector3('f', 'v', 'abc')

    def test_own_parameters_are_suggested_and_listed(self):
        # the bug: 'orientaton', 'nmu', 'seeed' got no suggestion; the valid list omitted the function's own
        for wrong, right in (('orientaton', 'orientation'), ('seeed', 'seed'), ('psdSize', 'psdSizes')):
            with self.assertRaises(TypeError) as ctx:
                split('f', {wrong: 1}, ('nSpheres',), extra=('orientation', 'seed', 'psdSizes'))
            self.assertIn("did you mean '%s'" % right, str(ctx.exception))
        with self.assertRaises(TypeError) as ctx:
            split('f', {'zzzz': 1}, ('nSpheres',), extra=('num',))
        self.assertIn('valid: nSpheres, num', str(ctx.exception))


if __name__ == '__main__':
    unittest.main()
