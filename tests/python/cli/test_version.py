"""One version, from one place (CMakeLists.txt's project): the command, the Python package, the CMake and
pkg-config files, the manual's configuration, CITATION.cff and the CHANGELOG's newest section all say it. Run with
/usr/bin/python3."""
import os
import re
import subprocess
import sys
import unittest

import yade_mss

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..')
BINARY = os.environ.get('MSS_BINARY', 'mss')


def read(*path):
    with open(os.path.join(ROOT, *path)) as f:
        return f.read()


class Version(unittest.TestCase):
    def test_every_place_says_the_projects_version(self):
        v = re.search(r'project\(yade_mss VERSION ([0-9]+\.[0-9]+\.[0-9]+)', read('CMakeLists.txt')).group(1)
        p = subprocess.run([BINARY, '--version'], capture_output=True, text=True, timeout=30)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout.strip(), 'mss (yade-mss) ' + v)
        self.assertEqual(yade_mss.__version__, v)
        self.assertEqual(yade_mss._mss.version(), v)
        self.assertIn('\nversion: %s\n' % v, read('CITATION.cff'))
        # the newest numbered section (an "Unreleased" one may come above it, for what is not released yet)
        self.assertEqual(re.search(r'^## ([0-9]+\.[0-9]+\.[0-9]+) \(\d{4}-\d\d-\d\d\)$', read('CHANGELOG.md'),
                                   re.M).group(1), v)
        self.assertRegex(read('CITATION.cff'), r'\ndate-released: \d{4}-\d\d-\d\d\n')
        sys.path.insert(0, os.path.join(ROOT, 'docs'))
        try:
            import conf
        finally:
            sys.path.pop(0)
        self.assertEqual((conf.version, conf.release), (v, v))
        build = os.path.dirname(os.path.abspath(BINARY)) if os.path.isabs(BINARY) else None
        if build and os.path.isfile(os.path.join(build, 'mss.pc')):  # the build tree's CMake and pkg-config files
            with open(os.path.join(build, 'mss.pc')) as f:
                self.assertIn('Version: %s\n' % v, f.read())
            with open(os.path.join(build, 'mssConfigVersion.cmake')) as f:
                self.assertIn('set(PACKAGE_VERSION "%s")' % v, f.read())


if __name__ == '__main__':
    unittest.main()
