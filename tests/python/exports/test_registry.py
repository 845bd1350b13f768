"""The export registry (py/yade_mss/exports): one module a format, each registered once, the same names and order
as the option table's --format choices, so that the command line, batch --format and MssResult.export offer
exactly the formats that are written. Run with /usr/bin/python3."""
import os
import tempfile
import unittest

import numpy as np

import yade_mss
from yade_mss.exports import FORMATS, Format, exportTemplate, register
from yade_mss.grains import optionTable


class Registry(unittest.TestCase):
    def test_the_registry_is_the_option_tables_choices(self):
        self.assertEqual(list(FORMATS), optionTable.row('format', 'export')['choices'].split('|'))

    def test_each_format_in_its_own_module(self):
        modules = {f.write.__module__ for f in FORMATS.values()}
        self.assertEqual(len(modules), len(FORMATS))
        self.assertTrue(all(m.startswith('yade_mss.exports._') for m in modules), modules)

    def test_a_name_registered_twice_is_refused(self):
        with self.assertRaisesRegex(ValueError, "format 'kratos' is registered twice"):
            register(Format('kratos', '.x', lambda r, o: ''))
        self.assertEqual(FORMATS['kratos'].extension, '.clu')

    def test_every_format_writes_through_the_registry(self):
        r = yade_mss.generate(os.path.join(os.environ['MSS_TEST_DATA'], 'ellipsoid_2_1_1.stl'), nSpheres=4,
                              resolution=30)
        with tempfile.TemporaryDirectory() as d:
            for name, f in FORMATS.items():
                path = os.path.join(d, 'grain' + (f.extension or '_folder'))
                exportTemplate(r, path, format=name, density=2650.0)
                if f.folder:
                    self.assertTrue(os.path.isdir(path), name)
                    texts = [open(os.path.join(a, b)).read() for a, _, bs in os.walk(path) for b in bs]
                else:
                    texts = [open(path).read()]
                # each writes the grain's exact volume or mass, not the spheres' union
                volume = r.targetMass.volume
                wanted = (repr(volume), repr(2650.0 * volume))
                self.assertTrue(any(w in t for t in texts for w in wanted), name)
                self.assertFalse(np.isclose(volume, r.unionVolume(), rtol=1e-3), 'the test needs them apart')


if __name__ == '__main__':
    unittest.main()
