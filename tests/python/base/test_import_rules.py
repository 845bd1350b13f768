"""scripts/check_imports.py, the rules of the package's layers, on a small package made here that breaks each
rule once, and on the real package, which keeps them all. Run with /usr/bin/python3."""
import importlib.util
import os
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..')
spec = importlib.util.spec_from_file_location('check_imports', os.path.join(ROOT, 'scripts', 'check_imports.py'))
rules = importlib.util.module_from_spec(spec)
spec.loader.exec_module(rules)

FILES = {
    '__init__.py': 'from .grains import generate\n',
    'base/__init__.py': 'from ._a import a\n',
    'base/_a.py': 'from .. import _mss\n\ndef a():\n    return _mss\n',
    'grains/__init__.py': 'from ._g import generate\nfrom ._h import h\n',
    'grains/_g.py': ('from ..base._a import a\n'            # a private module of another layer
                     'from ._h import h\n'                  # with _h: a cycle
                     'from ..yade import clump\n'           # upward
                     'import matplotlib\n'                  # grains draws nothing
                     'def generate():\n'
                     '    from ..exports import one\n'
                     '    from ..exports import two\n'
                     '    from ..exports import three  # why\n'
                     '    from ..exports import four  # why\n'
                     '    return a, h, clump\n'),
    'grains/_h.py': 'from ._g import generate\nfrom .. import generate as top\nh = 1\n',
    'exports/__init__.py': 'import yade.wrapper\nfrom ..pictures import p\none = two = three = four = 1\n',
    'pictures/__init__.py': 'p = 1\n',
    'yade/__init__.py': 'from yade import utils\nclump = 1\n',
}


class Rules(unittest.TestCase):
    def test_each_broken_rule_is_named(self):
        with tempfile.TemporaryDirectory() as d:
            root = os.path.join(d, 'yade_mss')
            for rel, text in FILES.items():
                os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
                with open(os.path.join(root, rel), 'w') as f:
                    f.write(text)
            bad, late, uses = rules.check(root)
        text = '\n'.join(bad)
        self.assertIn('the private name _a of the base sub-package used from grains', text)
        self.assertIn('grains imports yade, a layer not below it', text)
        self.assertIn('imports matplotlib (the grains layer draws nothing)', text)
        self.assertIn("imports the package's __init__ (generate)", text)
        self.assertIn('exports/__init__.py:1: imports YADE', text)
        self.assertIn('exports imports pictures, a layer not below it', text)  # beside it: sideways
        self.assertNotIn('yade/__init__.py:1: imports YADE', text)  # the yade layer may
        self.assertEqual(text.count('without its reason beside it'), 2)
        self.assertIn('4 imports of the package inside functions (bar 3)', text)
        cycle = [b for b in bad if b.startswith('an import cycle: ')]
        self.assertEqual(len(cycle), 1)
        self.assertIn('yade_mss.grains._g -> yade_mss.grains._h', cycle[0])
        self.assertEqual(len(late), 4)
        self.assertEqual(uses['grains'], {'base', 'yade', 'exports'})

    def test_the_package_keeps_them(self):
        bad, late, uses = rules.check(os.path.join(ROOT, 'py', 'yade_mss'))
        self.assertEqual(bad, [])
        self.assertLessEqual(len(late), rules.MAX_LATE)
        self.assertGreaterEqual(len([s for s in uses if s != 'top']), 4)  # at least four sub-packages in use
        self.assertEqual(uses['base'] if 'base' in uses else set(), set())


if __name__ == '__main__':
    unittest.main()
