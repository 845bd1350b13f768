"""The Python loaders under random input (Hypothesis): a saved result (.npz) mutated, sphere files of random text,
.npy files with random headers. Each either loads something valid or raises ValueError naming the file: never
another exception, a crash or a hang. Run with /usr/bin/python3."""
import logging
import os
import pickle
import struct
import tempfile
import unittest
import zlib

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

from yade_mss import MssResult, generate, readSpheres
from yade_mss.grains import readVolume
from yade_mss.spheropolygons import readImage

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
_valid = []
logging.getLogger('tifffile').setLevel(logging.ERROR)  # its warnings on each damaged file; the errors are tested


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

    def test_every_byte_of_a_result_archive_set_to_0_and_255(self):
        # the random flips above reach a few bytes; this reaches each one (headers, deflate streams, directory)
        raw = validArchive()
        for at in range(len(raw)):
            for value in (0, 255):
                damaged = bytearray(raw)
                damaged[at] = value
                path = self.write('r.npz', bytes(damaged))
                try:
                    r = MssResult.load(path)
                except ValueError as e:
                    self.assertIn('MssResult.load', str(e))
                    continue
                self.assertTrue(np.all(np.isfinite(r.centers)) and np.all(r.radii > 0), (at, value))

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
        for read in (readVolume, readImage):  # the Python readers of the same files
            try:
                read(path)
            except ValueError as e:
                self.assertIn('v.npy', str(e))

    @SETTINGS
    @given(st.binary(max_size=200), st.lists(st.tuples(st.integers(0, 10 ** 6), st.integers(0, 255)), max_size=6))
    def test_random_and_damaged_tiffs(self, data, flips):
        for raw in (data, damaged(tiffBytes(), flips)):
            path = self.write('v.tif', raw)
            try:
                a = readVolume(path)
            except ValueError as e:
                self.assertIn('v.tif', str(e))
                continue
            self.assertEqual(a.ndim, 3)


def damaged(raw, flips):
    raw = bytearray(raw)
    for at, value in flips:
        raw[at % len(raw)] = value
    return bytes(raw)


def tiffBytes():
    import tifffile
    with tempfile.TemporaryDirectory() as d:
        tifffile.imwrite(os.path.join(d, 'v.tif'), (np.arange(24).reshape(2, 3, 4) % 3).astype(np.uint8))
        with open(os.path.join(d, 'v.tif'), 'rb') as f:
            return f.read()


def tiffDeclaring(width, height):
    """A one-page 8-bit TIFF whose header declares width x height pixels and holds one byte of them."""
    tags = [(256, 4, width), (257, 4, height), (258, 3, 8), (259, 3, 1), (262, 3, 1), (273, 4, 8 + 2 + 8 * 12 + 4),
            (278, 4, height), (279, 4, 1)]
    ifd = struct.pack('<H', len(tags)) + b''.join(
        struct.pack('<HHI', tag, kind, 1) + (struct.pack('<HH', value, 0) if kind == 3 else struct.pack('<I', value))
        for tag, kind, value in tags) + struct.pack('<I', 0)
    return b'II*\x00' + struct.pack('<I', 8) + ifd + b'\x01'


class HostileArrays(unittest.TestCase):
    """Files built to defeat a reader: each is refused by name, by readVolume (specimens) and readImage
    (spheropolygons), before anything large is allocated."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def refused(self, name, raw, why, readers=(readVolume, readImage)):
        path = os.path.join(self.dir.name, name)
        with open(path, 'wb') as f:
            f.write(raw)
        for read in readers:
            with self.assertRaises(ValueError) as e:
                read(path)
            self.assertIn(name, str(e.exception))
            self.assertIn(why, str(e.exception))

    def npy(self, header, data=b''):
        h = header.encode('latin1')
        return b'\x93NUMPY\x01\x00' + len(h).to_bytes(2, 'little') + h + data

    def test_an_archive_named_npy(self):
        with tempfile.TemporaryDirectory() as d:
            np.savez(os.path.join(d, 'z.npz'), a=np.zeros((3, 3, 3), np.uint8))
            with open(os.path.join(d, 'z.npz'), 'rb') as f:
                self.refused('z.npy', f.read(), 'not a .npy file')

    def test_a_pickle_named_npy(self):
        self.refused('p.npy', pickle.dumps([1, 2]), 'not a .npy file')

    def test_a_header_cut_short(self):
        self.refused('h.npy', self.npy("{'descr': '<i4', 'fo"), 'cannot read the .npy file')

    def test_python_objects(self):
        self.refused('o.npy', self.npy("{'descr': '|O', 'fortran_order': False, 'shape': (2,), }", b'\0' * 16),
                     'Python objects')

    def test_a_shape_the_file_does_not_hold(self):
        self.refused('s.npy', self.npy("{'descr': '<i8', 'fortran_order': False, 'shape': (100000, 100000, 1000), }",
                                       b'\0' * 64), 'the file holds 64')

    def test_format_version_3(self):
        raw = bytearray(self.npy("{'descr': '<i4', 'fortran_order': False, 'shape': (1, 1, 1), }", b'\0' * 4))
        raw[6] = 3
        self.refused('v.npy', bytes(raw), 'version 3.0')

    def test_a_tiff_declaring_a_terapixel(self):
        self.refused('t.tif', tiffDeclaring(1000000, 1000000), 'more than half the memory', readers=(readVolume,))

    def test_random_bytes_named_tif(self):
        self.refused('r.tif', b'II*\x00' + bytes(range(256)) * 4, 'cannot read the TIFF', readers=(readVolume,))

    def test_a_png_declaring_ten_gigapixels(self):
        def chunk(kind, data):
            return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data))
        def png(side):
            return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', side, side, 8, 0, 0, 0, 0))
                    + chunk(b'IDAT', zlib.compress(b'\0' * 100)) + chunk(b'IEND', b''))
        self.refused('big.png', png(100000), 'declares 100000 x 100000 pixels', readers=(readImage,))
        self.refused('cut.png', png(4)[:20], 'not a PNG file', readers=(readImage,))
        self.refused('junk.png', png(4)[:33] + bytes(range(256)), 'cannot read the PNG', readers=(readImage,))

    def test_a_small_declared_tiff_is_read(self):
        # the hand-made TIFF above is one tifffile reads when its size is honest: the refusal is the size's
        path = os.path.join(self.dir.name, 'ok.tif')
        with open(path, 'wb') as f:
            f.write(tiffDeclaring(1, 1))
        with self.assertRaises(ValueError) as e:
            readVolume(path)
        self.assertIn('must be 3-D, got 2-D', str(e.exception))


if __name__ == '__main__':
    unittest.main()
