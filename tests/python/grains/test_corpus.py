"""The bad-input corpus (tests/corpus) through the Python API: ValueError or RuntimeError with the same message
as the command line, never a crash."""
import os
import unittest

import numpy as np

import yade_mss

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, '..', '..', 'corpus')


def cases():
    with open(os.path.join(CORPUS, 'cases.tsv')) as f:
        for line in f:
            if not line.strip() or line.startswith('#'):
                continue
            name, args, fragment = line.rstrip('\n').split('\t')
            words = args.split()
            if fragment.startswith('ok:'):
                continue
            if words[0] == 'generate' and words[1].startswith('{C}'):
                yield name, os.path.join(CORPUS, 'files', words[1][4:]), fragment.strip(), options(words[2:])


# the command's options that bound the work, as generate's keywords: the case is the same in both
OPTIONS = {'--spheres': ('nSpheres', int), '--resolution': ('resolution', int), '--memory-limit': ('memoryLimit', float),
           '--max-work': ('maxWork', float), '--scale': ('scale', float)}


def options(words):
    kw = {'nSpheres': 3, 'resolution': 20}
    for flag, value in zip(words, words[1:]):
        if flag in OPTIONS:
            key, kind = OPTIONS[flag]
            kw[key] = kind(value)
    return kw


class Corpus(unittest.TestCase):
    def test_every_bad_file(self):
        n = 0
        for name, path, fragment, kw in cases():
            with self.subTest(name):
                with self.assertRaises((ValueError, RuntimeError)) as ctx:
                    yade_mss.generate(path, **kw)
                self.assertIn(fragment, str(ctx.exception))
                n += 1
        self.assertGreaterEqual(n, 20)

    def test_extreme_but_valid_sizes(self):
        import numpy as np
        from yade_mss import _mss
        v, t = _mss.readMesh(os.path.join(HERE, '..', '..', 'data', 'sphere_r1.stl'))
        for scale in (1e-30, 1e30):
            r = yade_mss.generate((np.array(v).reshape(-1, 3) * scale, np.array(t).reshape(-1, 3)), nSpheres=1,
                                  resolution=30)
            self.assertAlmostEqual(r.radii[0] / scale, 1.0, delta=0.05)
        full = yade_mss.generate(os.path.join(CORPUS, 'files', 'full.npy'), nSpheres=1)  # solid up to its border
        self.assertEqual(len(full), 1)



class Arguments(unittest.TestCase):
    """The Python API's arguments by name (the attack: truthy strings, internal exceptions)."""

    def test_regions_only_is_a_list(self):
        from yade_mss import regions
        L = np.zeros((5, 5, 5), int)
        L[1, 1, 1], L[2, 2, 2], L[3, 3, 3] = 1, 2, 12
        for only in ('12', 12, b'12'):
            with self.assertRaisesRegex(TypeError, 'only must be a list'):
                regions(L, only=only)
        self.assertEqual([r.label for r in regions(L, only=[12])], [12])
        self.assertEqual([r.label for r in regions(L, only=[1, 2])], [1, 2])

    def test_a_result_saved_to_a_folder_is_named(self):
        import tempfile
        from yade_mss import MssResult
        with tempfile.TemporaryDirectory() as d:
            for path in (d, d + os.sep):
                with self.assertRaisesRegex(ValueError, 'is a folder: give a file name'):
                    MssResult([0, 0, 0], [1.0]).save(path)

    def test_a_result_of_the_wrong_shape_is_named(self):
        from yade_mss import MssResult
        with self.assertRaisesRegex(ValueError, r'MssResult: centres must be an \(n, 3\) array'):
            MssResult(np.array(1.0), np.array(1.0))
        with self.assertRaisesRegex(TypeError, 'MssResult'):
            MssResult([['a', 'b', 'c']], [1.0])
        self.assertEqual(len(MssResult([0, 0, 0], [1.0])), 1)


if __name__ == '__main__':
    unittest.main()
