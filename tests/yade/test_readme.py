"""The README's Python blocks run as written, each in a fresh scene of real YADE, from the repository's root.
Run: yade -n -x tests/yade/test_readme.py"""
import os
import re
import sys
import unittest

from yade.wrapper import Omega

O = Omega()
ROOT = os.path.join(os.environ.get('MSS_TEST_DATA', 'tests/data'), '..', '..')


def blocks():
    with open(os.path.join(ROOT, 'README.md')) as f:
        text = f.read()
    return re.findall(r'```python\n(.*?)```', text, flags=re.S)


class Readme(unittest.TestCase):
    def test_there_are_python_blocks(self):
        self.assertGreaterEqual(len(blocks()), 1)

    def test_every_python_block_runs(self):
        here = os.getcwd()
        os.chdir(ROOT)
        try:
            for k, code in enumerate(blocks()):
                O.reset()
                scope = dict(globals())
                exec(compile(code, 'README.md python block %d' % (k + 1), 'exec'), scope)
                # the first block builds clumps with their grains' exact masses: it must have built some
                if k == 0:
                    clumps = [b for b in O.bodies if b is not None and b.isClump]
                    self.assertGreater(len(clumps), 2)
                    self.assertTrue(all(b.state.mass > 1e-9 for b in clumps))  # SI kg, not a mm material
        finally:
            os.chdir(here)


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
