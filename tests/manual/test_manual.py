"""The manual runs as shown: every Python block and every shell step (the ``$`` lines of a console block) of the
README and of each guide and tutorial page, in page order, from a copy of the repository's root (its folders
linked, so that what a page writes lands in a scratch folder) on the bundled data. Python blocks run as one
script from one shell step to the next (later blocks use what earlier ones made), in real YADE where they use
it, else in Debian's python3. The output a console block shows must be what the command prints, line for line
(numbers aside), and so must a block of class ``output`` what the Python blocks before it print. Each guide and
tutorial page must lead with its code, and no code line may be wider than the
manual shows.
Run: MSS_BINARY=build/mss PYTHONPATH=build/py /usr/bin/python3 tests/manual/test_manual.py [page ...]
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import textwrap
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..'))
LINKED = ('tests', 'examples', 'docs', 'scripts', 'bench')  # the folders a page may read
WIDTH = 100  # the widest code line a user copies (the manual's pages show about 100 columns)
LEAD = 12  # a page's first code block starts within this many lines of its title
MIN_BLOCKS = 10
YADE_WORDS = re.compile(r'\bO\.|\bFrictMat\b|\bfrom yade\b|\bimport yade\b|\butils\.|\bmssClump|\bmssTemplate'
                        r'|\bmssAssembly|\bmssSplit|\bMssBreakage|\brestoreClumpProperties|\breadClumps')
YADE_BANNER = re.compile(r'^(Welcome to Yade|Using python version|TCP python prompt|XMLRPC info provider|'
                         r'Running script)')
NUMBER = re.compile(r'[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?')


def pages():
    """The pages whose code must run: README.md, then the guide (with its formats) and the tutorials."""
    found = [os.path.join(ROOT, 'README.md')]
    for pattern in ('docs/guide/*.rst', 'docs/guide/formats/*.rst', 'docs/tutorials/*.rst'):
        found += sorted(glob.glob(os.path.join(ROOT, pattern)))
    return found


def rstBlocks(text):
    """(kind, first line number, lines) of the code blocks of an RST page: 'python', 'console', 'other' (a code
    block in another language, or a literalinclude of an example, which its own test runs)."""
    lines = text.split('\n')
    out, i = [], 0
    while i < len(lines):
        m = re.match(r'\.\. (code-block|code|sourcecode|literalinclude)::\s*(\S*)', lines[i])
        if not m:
            i += 1
            continue
        start, lang = i + 1, m.group(2)
        if m.group(1) == 'literalinclude':
            out.append(('other', start, []))
            i += 1
            continue
        i += 1
        output = False
        while i < len(lines) and re.match(r'\s+:\w', lines[i]):  # the directive's options
            output = output or bool(re.match(r'\s+:class:.*\boutput\b', lines[i]))
            i += 1
        body = []
        while i < len(lines) and (not lines[i].strip() or lines[i].startswith((' ', '\t'))):
            body.append(lines[i])
            i += 1
        body = textwrap.dedent('\n'.join(body)).strip('\n').split('\n')
        # a block of class "output" is what the Python blocks before it print: compared as a console's
        out.append(('output' if output else {'python': 'python', 'console': 'console'}.get(lang, 'other'), start,
                    body))
    return out


def markdownBlocks(text):
    out = []
    for m in re.finditer(r'^```(\w*)\n(.*?)^```', text, flags=re.S | re.M):
        lang, body = m.group(1), m.group(2).rstrip('\n').split('\n')
        kind = 'python' if lang == 'python' else 'console' if any(l.startswith('$ ') for l in body) else 'other'
        out.append((kind, text[:m.start()].count('\n') + 1, body))
    return out


def blocks(path):
    with open(path) as f:
        text = f.read()
    return markdownBlocks(text) if path.endswith('.md') else rstBlocks(text)


def commands(body):
    """[(command, [output lines shown])] of a console block: '$ ' lines (a trailing backslash continues one)."""
    out = []
    lines = iter(body)
    for line in lines:
        if line.startswith('$ '):
            cmd = line[2:]
            while cmd.endswith('\\'):
                cmd = cmd[:-1] + ' ' + next(lines).strip()
            out.append((cmd, []))
        elif out and line.strip():
            out[-1][1].append(line)
    return out


def shape(line):
    """A line of output with its numbers masked and its spaces collapsed: what must match."""
    return ' '.join(NUMBER.sub('#', line).split())


class Page(object):
    """Runs one page's code in a scratch copy of the root."""

    def __init__(self, path, workdir, env):
        self.path, self.workdir, self.env = path, workdir, env
        self.name = os.path.relpath(path, ROOT)
        self.ran = 0

    def shell(self, cmd, shown, line):
        p = subprocess.run(['bash', '-c', 'set -o pipefail; ' + cmd], cwd=self.workdir, env=self.env,
                           capture_output=True, text=True, timeout=900)
        if p.returncode != 0:
            raise AssertionError('%s:%d: $ %s\nexit status %d\n%s%s' % (self.name, line, cmd, p.returncode,
                                                                      p.stdout[-3000:], p.stderr[-3000:]))
        if shown:
            got = [shape(l) for l in p.stdout.split('\n') if l.strip()]
            want = [shape(l) for l in shown]
            if got != want:
                raise AssertionError('%s:%d: $ %s\nthe page shows:\n  %s\nthe command prints:\n  %s'
                                     % (self.name, line, cmd, '\n  '.join(shown),
                                        '\n  '.join(l for l in p.stdout.split('\n') if l.strip())))
        self.ran += 1

    def python(self, stretch):
        code = '\n\n'.join('\n'.join(body) for _, body in stretch)
        script = os.path.join(self.workdir, '.page_%d.py' % stretch[0][0])
        with open(script, 'w') as f:
            f.write(code + '\n')
        yade = bool(YADE_WORDS.search(code))
        argv = ['yade', '-n', '-x', script] if yade else [sys.executable, script]
        p = subprocess.run(argv, cwd=self.workdir, env=self.env, capture_output=True, text=True, timeout=900)
        if p.returncode != 0:
            raise AssertionError('%s:%d: the Python block%s (in %s) failed, exit status %d\n%s%s'
                                 % (self.name, stretch[0][0], 's' if len(stretch) > 1 else '',
                                    'YADE' if yade else 'python3', p.returncode, p.stdout[-3000:], p.stderr[-4000:]))
        self.ran += len(stretch)
        # what the code printed: YADE's banner lines are YADE's, not the page's
        return [l for l in p.stdout.split('\n') if l.strip() and not (yade and YADE_BANNER.match(l))]

    def compare(self, printed, shown, line):
        if [shape(l) for l in printed] != [shape(l) for l in shown]:
            raise AssertionError('%s:%d: the page shows the Python blocks before it print:\n  %s\nthey print:\n  %s'
                                 % (self.name, line, '\n  '.join(shown), '\n  '.join(printed)))

    def run(self):
        stretch = []
        for kind, line, body in blocks(self.path):
            if kind == 'python':
                stretch.append((line, body))
                continue
            if kind == 'output':
                if not stretch:
                    raise AssertionError('%s:%d: an output block that follows no Python block' % (self.name, line))
                self.compare(self.python(stretch), [l for l in body if l.strip()], line)
                stretch = []
                continue
            if kind != 'console':
                continue  # a picture, a literal text, an included example: the Python around it runs as one
            if stretch:
                self.python(stretch)
                stretch = []
            for cmd, shown in commands(body):
                self.shell(cmd, shown, line)
        if stretch:
            self.python(stretch)


def scratch():
    """A scratch root: the repository's folders that pages read, linked."""
    d = tempfile.mkdtemp(prefix='mss_manual_')
    for name in LINKED:
        os.symlink(os.path.join(ROOT, name), os.path.join(d, name))
    return d


def environment():
    env = dict(os.environ, MSS_SHORT='1', MPLBACKEND='Agg')
    # the pages run elsewhere: a relative PYTHONPATH would find an installed package instead of this build's
    env['PYTHONPATH'] = os.pathsep.join(os.path.abspath(p) for p in env.get('PYTHONPATH', '').split(os.pathsep) if p)
    binary = os.environ.get('MSS_BINARY', os.path.join(ROOT, 'build', 'mss'))
    env['PATH'] = os.path.dirname(os.path.abspath(binary)) + os.pathsep + env.get('PATH', '')
    # the C++ library page builds against an installation: this build's, in a folder of the test's own (an
    # earlier one installed on the machine could be stale)
    build = os.path.dirname(os.path.abspath(binary))
    prefix = tempfile.mkdtemp(prefix='mss_manual_prefix_')
    subprocess.run(['cmake', '--install', build, '--prefix', prefix], check=True, capture_output=True)
    env['PKG_CONFIG_PATH'] = os.path.join(prefix, 'lib', 'pkgconfig')
    return env, prefix


class Manual(unittest.TestCase):
    def test_every_page_leads_with_code_of_readable_width(self):
        for path in pages():
            name = os.path.relpath(path, ROOT)
            found = blocks(path)
            runnable = [b for b in found if b[0] in ('python', 'console')]
            if not path.endswith('.md'):
                self.assertTrue(runnable, '%s: no code a user can run' % name)
                self.assertLessEqual(found[0][1], LEAD, '%s: the first code is on line %d, not leading the page'
                                     % (name, found[0][1]))
            for kind, line, body in found:
                # what a user copies must fit; a command's output wraps (docs/_static/custom.css)
                copied = body if kind != 'console' else [l for l in body if l.startswith('$ ') or l.startswith(' ')]
                for k, text in enumerate(copied):
                    self.assertLessEqual(len(text), WIDTH, '%s:%d: a code line of %d characters (the manual shows '
                                         '%d)' % (name, line + k, len(text), WIDTH))

    def test_every_block_runs_as_shown(self):
        only = [os.path.abspath(p) for p in sys.argv[1:]] if __name__ == '__main__' else []
        (env, prefix), total, failures = environment(), 0, []
        self.addCleanup(shutil.rmtree, prefix, True)
        for path in pages():
            if only and path not in only:
                continue
            d = scratch()
            try:
                page = Page(path, d, env)
                page.run()
                total += page.ran
                print('%-40s %d blocks and steps ran' % (page.name, page.ran), flush=True)
            except AssertionError as e:
                failures.append(str(e))
                print('%-40s FAILED' % os.path.relpath(path, ROOT), flush=True)
            finally:
                shutil.rmtree(d, ignore_errors=True)
        self.assertEqual(failures, [], '\n\n'.join(failures))
        if not only:
            self.assertGreaterEqual(total, MIN_BLOCKS)

    def test_the_parser_sees_what_a_page_shows(self):
        page = ('Title\n=====\n\n.. code-block:: console\n\n   $ mss generate a.stl \\\n       --spheres 3\n'
                '   spheres  3\n\n.. code-block:: python\n   :caption: x\n\n   print(1)\n\n   print(2)\n\ntext::\n\n'
                '   not code\n')
        found = rstBlocks(page)
        self.assertEqual([b[0] for b in found], ['console', 'python'])
        self.assertEqual(commands(found[0][2]), [('mss generate a.stl  --spheres 3', ['spheres  3'])])
        self.assertEqual(found[1][2], ['print(1)', '', 'print(2)'])
        self.assertEqual(shape('dice   0.0281602   (Dice, eq. 27)'), 'dice # (Dice, eq. #)')
        shown = rstBlocks('.. code-block:: python\n\n   print(3)\n\n.. code-block:: text\n   :class: output\n\n   3\n')
        self.assertEqual([b[0] for b in shown], ['python', 'output'])

    def test_an_output_block_is_compared_with_what_the_code_prints(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'page.rst')
            for printed, ok in (('2.5', True), ('3 extra', False)):
                with open(path, 'w') as f:
                    f.write('.. code-block:: python\n\n   print(%r)\n\n.. code-block:: text\n   :class: output\n\n'
                            '   2.5\n' % printed)
                page = Page(path, d, dict(os.environ))
                if ok:
                    page.run()
                    self.assertEqual(page.ran, 1)
                else:
                    with self.assertRaisesRegex(AssertionError, 'the page shows the Python blocks before it print'):
                        page.run()


if __name__ == '__main__':
    sys.argv, pagesGiven = sys.argv[:1], sys.argv[1:]
    suite = unittest.TestSuite()
    loader = unittest.TestLoader()
    if pagesGiven:
        sys.argv += pagesGiven
        suite.addTest(Manual('test_every_block_runs_as_shown'))
    else:
        suite = loader.loadTestsFromTestCase(Manual)
    sys.exit(0 if unittest.TextTestRunner(verbosity=2).run(suite).wasSuccessful() else 1)
