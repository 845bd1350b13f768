"""The Python loaders under random input (Hypothesis): a saved result (.npz) mutated, sphere files of random text,
.npy files with random headers. Each either loads something valid or raises ValueError naming the file: never
another exception, a crash or a hang. Run with /usr/bin/python3."""
import os
import tempfile
import unittest

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

from yade_mss import MssResult, generate, readSpheres

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'data')
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
_valid = []


def validArchive():
    if not _valid:
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'r.npz')
            generate(os.path.join(DATA, 'cube.stl'), nSpheres=4, resolution=16).save(f)
            with open(f, 'rb') as g:
                _valid.append(g.read())
    return _valid[0]


class Loaders(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def write(self, name, data):
        path = os.path.join(self.dir.name, name)
        with open(path, 'wb') as f:
            f.write(data)
        return path

    @SETTINGS
    @given(st.lists(st.tuples(st.integers(0, 10 ** 6), st.integers(0, 255)), max_size=8),
           st.integers(0, 10 ** 6))
    def test_a_mutated_result_archive(self, flips, cut):
        raw = bytearray(validArchive())
        for at, value in flips:
            raw[at % len(raw)] = value
        path = self.write('r.npz', bytes(raw[:max(1, cut % (len(raw) + 1))]))
        try:
            r = MssResult.load(path)
        except ValueError as e:
            self.assertIn('MssResult.load', str(e))
            return
        self.assertTrue(np.all(np.isfinite(r.centers)) and np.all(r.radii > 0))

    @SETTINGS
    @given(st.lists(st.text(alphabet=st.sampled_from(list('0123456789.-+eE ,;\t#xyzrnaifINFAN\ufeff')), max_size=40),
                    max_size=12))
    def test_random_sphere_files(self, lines):
        path = self.write('s.csv', '\n'.join(lines).encode('utf-8'))
        try:
            r = readSpheres(path)
        except ValueError as e:
            self.assertIn('s.csv', str(e))
            return
        self.assertGreater(len(r), 0)
        self.assertTrue(np.all(np.isfinite(r.centers)) and np.all(r.radii > 0))

    @SETTINGS
    @given(st.text(max_size=300), st.binary(max_size=64))
    def test_random_npy_headers(self, header, data):
        h = header.encode('utf-8', 'replace')
        raw = b'\x93NUMPY\x01\x00' + len(h).to_bytes(2, 'little') + h + data
        path = self.write('v.npy', raw)
        try:
            generate(path, nSpheres=2)
        except ValueError as e:
            self.assertIn('v.npy', str(e))


if __name__ == '__main__':
    unittest.main()
