"""Every public name of yade_mss that runs without YADE, every keyword argument of it given a value of the
wrong kind (a string or a list for a number, 'no' or 1.5 for a bool, an object for anything else): a
TypeError or ValueError that names the argument, from the shared checkers of yade_mss.base, never an internal
error (AttributeError, "float() argument must be ...") and never a value taken silently. The YADE names are
checked the same way in tests/yade/test_clump_api.py. Run with /usr/bin/python3."""
import inspect
import os
import tempfile
import unittest

import numpy as np

import yade_mss

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
LABELS = os.path.join(DATA, 'two_grains_labels.npy')

# the names that need YADE's O (checked inside YADE) or start YADE processes of their own (triaxialStudy: its
# wrong arguments are refused before any process starts, below)
YADE = {'mssClump', 'restoreClumpProperties', 'totalMass', 'porosity', 'writeClumps', 'readClumps', 'mssTemplate',
        'mssClumpCloud', 'mssReplaceByClumps', 'mssAssembly', 'mssSplit', 'MssBreakage', 'breakageLog',
        'grainSizes', 'contactStiffnessEngine', 'triaxial', 'triaxialStudy'}


def badValues(default):
    """Values of the wrong kind for an argument whose default is *default*."""
    if isinstance(default, bool):
        return ['no', 1.5]
    if isinstance(default, (int, float)):
        return ['abc', [1]]
    return [object()]


class EveryName(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.spheres = os.path.join(d, 's.csv')
        yade_mss.generate(ELL, nSpheres=3, resolution=20).save(cls.spheres)
        image = np.zeros((40, 40), np.uint8)
        image[10:30, 12:28] = 1
        labels = np.load(LABELS)
        # a cheap valid call of each name: the wrong value replaces one keyword at a time
        cls.calls = {
            'generate': ((ELL,), dict(nSpheres=3, resolution=20)),
            'readSpheres': ((cls.spheres,), {}),
            'score': ((ELL, cls.spheres), dict(resolution=20)),
            'compareMany': ((ELL, [cls.spheres]), dict(resolution=20)),
            'massProperties': ((ELL,), {}),
            'regions': ((labels,), {}),
            'syntheticSpecimen': ((), dict(shape=(30, 30, 30), grains=3, size=(4, 6))),
            'packedSpecimen': ((), dict(shape=(20, 20, 20), grains=3, size=(3, 5))),
            'voronoiBall': ((), dict(radius=10, cells=3)),
            'porousScan': ((), dict(shape=(30, 30, 30), grains=3, size=(4, 6))),
            'findContacts': ((labels,), {}),
            'spheropolygon': ((image,), dict(vertices=6)),
            'spheropolygons': ((image,), dict(vertices=6)),
            'boundaryRegions': ((image,), {}),
            'ochart': ((image, os.path.join(d, 'oc')), dict(vertices=(4, 5), radii=(0.05, 0.1))),
            'clumpOchart': ((ELL, os.path.join(d, 'o.png')), dict(points=2, radiusPoints=2, resolution=20)),
            'breakagePotential': (([1.0, 2.0], [1.0, 1.0], 0.5), {}),
            'relativeBreakage': ((([1.0, 2.0], [1.0, 1.0]), ([1.0, 2.0], [1.5, 0.5]), 0.5), {}),
            'batch': ((LABELS, None), dict(voxelSize=1e-3, nSpheres=3, progress=False)),
        }

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_public_name_is_covered(self):
        functions = {n for n in yade_mss.__all__ if callable(getattr(yade_mss, n))
                     and not inspect.isclass(getattr(yade_mss, n))}
        self.assertEqual(functions - YADE - set(self.calls), set(), 'public names this test does not call')

    def test_the_valid_calls_run(self):
        for name, (args, kw) in self.calls.items():
            with self.subTest(name):
                getattr(yade_mss, name)(*args, **kw)

    def check(self, name, f, args, kw):
        for p in inspect.signature(f).parameters.values():
            if p.default is inspect.Parameter.empty or p.kind in (p.VAR_KEYWORD, p.VAR_POSITIONAL):
                continue
            for bad in badValues(p.default):
                with self.subTest('%s(%s=%r)' % (name, p.name, bad)):
                    with self.assertRaises((TypeError, ValueError)) as ctx:
                        f(*args, **dict(kw, **{p.name: bad}))
                    self.assertIn(p.name, str(ctx.exception))

    def test_every_keyword_of_the_wrong_kind_is_refused_by_name(self):
        for name, (args, kw) in self.calls.items():
            self.check(name, getattr(yade_mss, name), args, kw)

    def test_a_study_s_wrong_arguments_are_refused_before_it_starts(self):
        # a value taken here would start the study's YADE processes (minutes): refused first, each by name
        out = os.path.join(self.tmp.name, 'study')
        self.check('triaxialStudy', yade_mss.triaxialStudy, ([ELL], out), dict(nSpheres=[3], quiet=True))
        self.assertFalse(os.path.exists(out))

    def test_the_result_s_methods_too(self):
        r = yade_mss.generate(ELL, nSpheres=3, resolution=20)
        self.check('MssResult.save', r.save, (os.path.join(self.tmp.name, 'r.csv'),), {})
        self.check('MssResult.unionMass', r.unionMass, (), {})
        self.check('MssResult.boundingRadius', r.boundingRadius, (), {})


if __name__ == '__main__':
    unittest.main()
