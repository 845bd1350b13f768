"""The option table against its front ends: the command line's --help of every command, the Python
functions' signatures, defaults and docstrings, and the binding's conversion. A front end that drifts from
the table (an option added by hand, a default changed in one place, a keyword the binding would ignore)
fails here."""

import inspect
import os
import re
import subprocess
import unittest

import yade_mss
from yade_mss import _mss
from yade_mss.grains import optionTable as _options
from yade_mss.grains import GENERATE_OPTIONS

MSS = os.environ.get('MSS_BINARY', 'mss')
DATA = os.environ.get('MSS_TEST_DATA', os.path.join(os.path.dirname(__file__), '..', '..', 'data'))
COMMANDS = ('generate', 'compare', 'info', 'batch', 'preview', 'curve', 'ochart', 'export', 'spheropolygon')


def helpFlags(command):
    """The long flags that `mss COMMAND --help` lists."""
    out = subprocess.run([MSS, command, '--help'], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    flags = set()
    for line in out.stdout.splitlines():  # the option column of CLI11's and argparse's help
        m = re.match(r'\s{1,4}(-\S.*?)(\s{2,}|$)', line)
        if m:
            flags.update(re.findall(r'--[a-z][a-z0-9-]*', m.group(1)))
    flags.discard('--help')
    return flags, out.stdout


def tableFlags(command):
    return {r['flag'].split(',')[-1] for r in _options.rows(command) if r['flag']}


class CommandLine(unittest.TestCase):
    def test_every_command_lists_exactly_the_table_options(self):
        for command in COMMANDS:
            with self.subTest(command=command):
                listed, text = helpFlags(command)
                self.assertEqual(listed, tableFlags(command), text)

    def test_help_shows_the_table_default_and_range(self):
        _, text = helpFlags('generate')
        self.assertRegex(text, r'--resolution N\s+.*default 100')
        self.assertRegex(text, r'--threads T\s+.*in \[0, 1024\]')
        _, text = helpFlags('preview')  # argparse wraps its lines
        self.assertRegex(' '.join(text.split()), r'--resolution N the pictures\' grid.*default 160')

    def test_a_bad_value_is_named_as_the_command_line_spells_it(self):
        for command, args, message in (
                ('generate', ['--spheres', '0', '-o', '/tmp/x.csv'], '--spheres must be in [1, 65535], got 0'),
                ('generate', ['--spheres', 'three', '-o', '/tmp/x.csv'], "--spheres: 'three' is not an integer"),
                ('compare', ['/dev/null', '--offset', 'x'], "--offset: 'x' is not a number"),
                ('batch', ['--spheres', '3', '--dice', '2', '-o', '/tmp/mss-never'], '--dice must be in [0, 1)'),
                ('curve', ['--counts', '2:4', '--points', '1', '-o', '/tmp/x.png'], '--points must be in [2, 1000]')):
            with self.subTest(command=command, args=args):
                out = subprocess.run([MSS, command, os.path.join(DATA, 'cube.stl')] + args, capture_output=True,
                                     text=True, timeout=120)
                self.assertNotEqual(out.returncode, 0)
                self.assertIn(message, out.stderr)


class Table(unittest.TestCase):
    def test_one_name_one_flag_one_type(self):
        byName, byFlag = {}, {}
        for r in _options.TABLE:
            kind = 'point' if r['type'] == 'point2' else r['type']  # a point in 2-D or 3-D: the same option
            byName.setdefault(r['name'], set()).add((r['flag'], kind, r['unit'], r['python']))
            if r['flag']:
                byFlag.setdefault(r['flag'], set()).add(r['name'])
        for name, kinds in byName.items():
            self.assertEqual(len(kinds), 1, '%s is spelled or typed two ways: %s' % (name, kinds))
        for flag, names in byFlag.items():
            self.assertEqual(len(names), 1, '%s means two options: %s' % (flag, names))

    def test_a_command_takes_an_option_once(self):
        for command in COMMANDS:
            names = [r['name'] for r in _options.rows(command)]
            self.assertEqual(len(names), len(set(names)), command)

    def test_every_default_parses_as_its_type(self):
        for r in _options.TABLE:
            if r['default']:
                for command in r['commands']:
                    _options.default(r['name'], command)  # raises on a default the parser refuses


class PythonFunctions(unittest.TestCase):
    FUNCTIONS = ((yade_mss.generate, 'generate', ('source',)),
                 (yade_mss.compareMany, 'compare', ('target', 'spheres')),
                 (yade_mss.score, 'compare', ('target', 'spheres')))

    def test_signatures_are_the_table_keywords_with_its_defaults(self):
        for f, command, own in self.FUNCTIONS:
            params = inspect.signature(f).parameters
            keywords = [r['name'] for r in _options.rows(command) if r['python']]
            for name, p in params.items():
                if name in own:
                    continue
                with self.subTest(function=f.__name__, keyword=name):
                    self.assertIn(name, keywords)
                    d = _options.default(name, command)
                    # None or () stand for "the table's default" or "not given"
                    self.assertIn(p.default, (None, (), d), 'default %r, table %r' % (p.default, d))
            if f is not yade_mss.score:  # score takes the scoring grid's options only
                self.assertEqual(set(keywords), set(params) - set(own), f.__name__)

    def test_generate_options_are_the_generate_rows(self):
        keywords = {r['name'] for r in _options.rows('generate') if r['python']}
        self.assertEqual(set(GENERATE_OPTIONS), keywords)

    def test_batch_takes_the_batch_rows(self):
        params = set(inspect.signature(yade_mss.batch).parameters)
        for r in _options.rows('batch'):
            if r['python']:
                with self.subTest(keyword=r['name']):
                    self.assertTrue(r['name'] in params or r['name'] in GENERATE_OPTIONS, r['name'])

    def test_export_takes_the_export_rows(self):
        from yade_mss.exports import exportTemplate
        params = set(inspect.signature(exportTemplate).parameters) - {'result', 'path'}
        own = {r['name'] for r in _options.rows('export') if r['python'] and r['name'] not in GENERATE_OPTIONS}
        self.assertEqual(params, own)
        for name in params:  # None: the table's default
            self.assertIsNone(inspect.signature(exportTemplate).parameters[name].default)

    def test_pictures_take_the_table_defaults(self):
        from yade_mss import pictures as _pictures
        for f, command in ((_pictures.preview, 'preview'), (_pictures.curve, 'curve'),
                           (yade_mss.spheropolygon, 'spheropolygon'), (yade_mss.clumpOchart, 'ochart')):
            params = inspect.signature(f).parameters
            for r in _options.rows(command):
                if r['python'] and r['name'] in params:
                    with self.subTest(function=command, keyword=r['name']):
                        d = _options.default(r['name'], command)
                        self.assertIn(params[r['name']].default, (None, (), d, tuple(d) if isinstance(d, list) else d))

    def test_docstrings_document_every_keyword_from_the_table(self):
        for f, command, own in self.FUNCTIONS:
            for name in inspect.signature(f).parameters:
                with self.subTest(function=f.__name__, keyword=name):
                    self.assertRegex(f.__doc__, r':param (\w+ )?%s:' % name)
        doc = ' '.join(yade_mss.generate.__doc__.split())
        self.assertIn(':param int nSpheres: at most this many spheres', doc)
        self.assertIn('command line ``--spheres``', doc)
        self.assertIn('default 100]; command line ``--resolution``', doc)


class Binding(unittest.TestCase):
    CUBE = ([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1],
            [0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4,
             7])

    def test_unknown_keys_are_errors_that_suggest_the_option(self):
        with self.assertRaisesRegex(ValueError, "'nSphere' is not an option of generate \\(did you mean 'nSpheres'"):
            _mss.generateMesh(*self.CUBE, {'nSphere': 3, 'resolution': 10})
        with self.assertRaisesRegex(ValueError, "'protrusionSamples' is not an option of compare"):
            _mss.compareMesh(*self.CUBE, [0.5, 0.5, 0.5], [0.5], {'protrusionSamples': 3})

    def test_the_binding_checks_types_and_ranges_itself(self):
        with self.assertRaisesRegex(ValueError, 'nSpheres must be an integer'):
            _mss.generateMesh(*self.CUBE, {'nSpheres': True, 'resolution': 10})
        with self.assertRaisesRegex(ValueError, 'generate: eta must be in \\[0, 1\\), got 2'):
            _mss.generateMesh(*self.CUBE, {'eta': 2.0, 'resolution': 10})

    def test_the_text_parser_is_the_command_lines(self):
        self.assertEqual(_mss.parseOption('origin', 'generate', '1,2,3'), (1.0, 2.0, 3.0))
        self.assertEqual(_mss.parseOption('nSpheres', 'generate', '7'), 7)
        self.assertIs(_mss.parseOption('keepSymmetry', 'generate', 'false'), False)
        with self.assertRaisesRegex(ValueError, "'7.5' is not an integer"):
            _mss.parseOption('nSpheres', 'generate', '7.5')


if __name__ == '__main__':
    unittest.main()


class Docstrings(unittest.TestCase):
    def test_every_public_function_documents_every_parameter(self):
        """As YADE writes them: a ``:param ... name:`` line for each parameter of each public function, class
        and method (the manual's API pages are made from them)."""
        missing = []
        for name in yade_mss.__all__:
            obj = getattr(yade_mss, name)
            targets = [(name, obj)]
            if inspect.isclass(obj):
                targets += [(name + '.' + m, getattr(obj, m)) for m in vars(obj)
                            if not m.startswith('_') and callable(getattr(obj, m))]
            for label, f in targets:
                params = inspect.signature(f).parameters
                for p, spec in params.items():
                    if p in ('self', 'cls') or spec.kind == inspect.Parameter.VAR_POSITIONAL:
                        continue
                    if not re.search(r':param (\S+ )?%s:' % re.escape(p), f.__doc__ or ''):
                        missing.append('%s(%s)' % (label, p))
        self.assertEqual(missing, [])


class FormatTable(unittest.TestCase):
    def test_the_python_extension_lists_are_the_format_tables(self):
        from yade_mss import grains
        table = _mss.fileFormats()
        self.assertEqual(set(grains.MESH_EXT), {f['extension'] for f in table if f['kind'] == 'mesh'})
        self.assertEqual(set(grains.VOLUME_EXT), {f['extension'] for f in table if f['kind'] == 'voxels'})

    def test_the_command_line_names_the_tables_formats(self):
        out = subprocess.run([MSS, 'generate', os.path.join(DATA, 'cube.stl'), '--spheres', '3', '-o', '/tmp/x.bad'],
                             capture_output=True, text=True, timeout=120)
        written = [f['extension'] for f in _mss.fileFormats() if f['written']]
        self.assertIn('(expected %s or %s)' % (', '.join(written[:-1]), written[-1]), out.stderr)
