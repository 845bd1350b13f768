"""The option table (pkg/mss/generation/option_table.cpp, through the binding) as the Python front ends use it: the
checks of keyword arguments, the ``mss batch`` / ``preview`` / ``curve`` parsers and the ``:param`` lines of the public
functions' docstrings are all made from it, so they cannot drift from the command line's."""

import argparse

from .. import _mss
from ..base import INT64_MAX, flag, integer, number, vector3
from ._sources import planeList

TABLE = tuple(_mss.optionTable())

_PYTHON_TYPES = {'int': 'int ', 'float': 'float ', 'bool': 'bool ', 'choice': 'str ', 'str': 'str ', 'point': '',
                 'point2': '', 'planes': '', 'files': ''}


def rows(command):
    """The table's rows for *command* ('generate', 'compare', 'info', 'batch', 'preview', 'curve', 'ochart',
    'spheropolygon')."""
    return [r for r in TABLE if command in r['commands']]


def row(name, command):
    for r in TABLE:
        if r['name'] == name and command in r['commands']:
            return r
    raise KeyError('%s: no option %r in the table' % (command, name))


def default(name, command):
    """The table's default of an option as a Python value (None where it has none)."""
    r = row(name, command)
    return _mss.parseOption(name, command, r['default']) if r['default'] else None


def _planes(func, value):
    return planeList(func, value)


def check(func, command, name, value):
    """*value* of option *name* checked as its row's type and range say (a bool is not a count, a string is not
    a number), with the core's messages; the core checks again."""
    r = row(name, command)
    t = r['type']
    if t == 'int':
        low = int(r['low'])
        high = min(int(r['high']), INT64_MAX) if r['high'] < 9.2e18 else INT64_MAX
        return integer(func, name, value, low, high)
    if t == 'float':
        v = number(func, name, value, finite=False, nan=True)
        low, high = r['low'], r['high']
        inside = (v > low if r['lowOpen'] else v >= low) and (v < high if r['highOpen'] else v <= high)
        if not inside:  # as the core says it
            raise ValueError('%s: %s must be %s, got %r' % (func, name, r['range'] or 'finite', value))
        return v
    if t == 'bool':
        return flag(func, name, value)
    if t in ('choice', 'str'):
        if not isinstance(value, str):
            raise TypeError('%s: %s must be a string, got %r' % (func, name, value))
        if t == 'choice' and value not in r['choices'].split('|'):
            raise ValueError('%s: %s must be one of %s, got %r' % (func, name, ', '.join(r['choices'].split('|')),
                                                                    value))
        return value
    if t == 'point':
        return [float(x) for x in vector3(func, name, value)]
    if t == 'point2':
        if isinstance(value, (str, bytes)) or not hasattr(value, '__len__') or len(value) != 2:
            raise TypeError('%s: %s must be 2 numbers, got %r' % (func, name, value))
        return [number(func, name, x) for x in value]
    if t == 'planes':
        return _planes(func, value)
    if t == 'files':
        if isinstance(value, (str, bytes)):
            return [value]
        return [str(v) for v in value]
    raise TypeError('%s: %s has a type the table does not know (%s)' % (func, name, t))


def collect(func, command, given):
    """The options in *given* (keyword -> value; None: not given) checked against *command*'s rows."""
    return {k: check(func, command, k, v) for k, v in given.items() if v is not None}


_SHAPES = {'point': '(x, y, z)', 'point2': '(x, y)', 'planes': '[((px, py, pz), (nx, ny, nz)), ...]'}


def facts(r, python=False, withDefault=True):
    """What a row says beside its help, as every front end's help shows it (--help of the Python parsers, the
    docstrings, the manual's reference): its choices or shape, unit, range and default."""
    out = [x for x in (r['unit'], r['range']) if x]
    if r['type'] == 'choice':
        words = r['choices'].split('|')
        out.insert(0, ' or '.join("'%s'" % c for c in words) if python else 'one of ' + ', '.join(words))
    if python and r['type'] in _SHAPES:
        out.insert(0, _SHAPES[r['type']])
    if withDefault and r['default'] and (python or r['type'] != 'bool'):
        out.append('default %s' % (r['default'].capitalize() if r['type'] == 'bool' else r['default']))
    return out


def _paramLine(r, indent):
    extra = facts(r, python=True)
    text = ':param %s%s: %s' % (_PYTHON_TYPES[r['type']], r['name'], r['help'])
    if extra:
        text += ' [%s]' % '; '.join(extra)
    if r['flag']:
        text += '; command line ``%s``' % r['flag'].split(',')[-1]
    words, lines, line = text.split(' '), [], ''
    for w in words:  # wrapped at 110 columns, continuation lines indented as reST wants
        if line and len(line) + 1 + len(w) > 110 - len(indent):
            lines.append(line)
            line = '    ' + w
        else:
            line = (line + ' ' + w) if line else w
    lines.append(line)
    return '\n'.join(indent + x for x in lines)


def documented(command, skip=()):
    """Decorator: replaces the line ``OPTIONS`` of the docstring by a ``:param`` line for each of the function's
    keywords that *command*'s rows hold, in the signature's order."""
    import inspect

    def wrap(f):
        names = [p for p in inspect.signature(f).parameters if p not in skip]
        doc = f.__doc__
        at = doc.index('OPTIONS')
        indent = doc[doc.rindex('\n', 0, at) + 1:at]
        byName = {r['name']: r for r in rows(command) if r['python']}
        lines = [_paramLine(byName[n], indent) for n in names if n in byName]
        f.__doc__ = doc[:at - len(indent)] + '\n'.join(lines) + doc[at + len('OPTIONS'):]
        return f
    return wrap


class _Store(argparse.Action):
    """Keeps an option's text by its table name; --plane and --compare may repeat."""

    def __call__(self, parser, namespace, values, option_string=None):
        texts = getattr(namespace, '_texts', None)
        if texts is None:
            texts = {}
            setattr(namespace, '_texts', texts)
        if self.const is not None:  # a flag: the opposite of its default
            texts[self.dest] = [self.const]
        else:
            for v in values if isinstance(values, list) else [values]:
                texts.setdefault(self.dest, []).append(v)


def addArguments(parser, command, skip=()):
    """Adds *command*'s rows that have a flag (all but *skip*) to an argparse parser; after parsing,
    :func:`parsed` gives their values."""
    for r in rows(command):
        if not r['flag'] or r['name'] in skip:
            continue
        flags = r['flag'].split(',')
        helpText = ('turns off: ' if r['type'] == 'bool' and r['default'] == 'true' else '') + r['help']
        extra = facts(r)
        if extra:
            helpText += ' [%s]' % '; '.join(extra)
        helpText = helpText.replace('%', '%%')
        if r['type'] == 'bool':
            parser.add_argument(*flags, dest=r['name'], action=_Store, nargs=0,
                                const='false' if r['default'] == 'true' else 'true', help=helpText)
        else:
            parser.add_argument(*flags, dest=r['name'], action=_Store, metavar=r['metavar'], help=helpText,
                                nargs='+' if r['type'] == 'files' else None, required=r['name'] == 'output')
    if command in ('preview', 'curve'):  # the name before --voxel-size took the voxel volumes' edge too
        parser.add_argument('--npy-voxel-size', dest='voxelSize', action=_Store, help=argparse.SUPPRESS)
    parser.set_defaults(**{r['name']: None for r in rows(command) if r['flag']})


def parseOne(name, command, text):
    """One value of option *name* of *command* from its text, as the command line parses it."""
    return _mss.parseOption(name, command, text.strip())


def parsed(command, namespace):
    """The values the command line gave to *command*'s table rows, parsed as ``mss generate`` parses them
    (the same C++ parser): name -> value."""
    out = {}
    for name, texts in (getattr(namespace, '_texts', None) or {}).items():
        r = row(name, command)
        try:
            if r['type'] == 'planes':
                out[name] = [p for t in texts for p in _mss.parseOption(name, command, t)]
            elif r['type'] == 'files':
                out[name] = list(texts)
            else:
                out[name] = _mss.parseOption(name, command, texts[-1])
        except ValueError as e:  # named as the command line spells it
            text = str(e)
            prefix = 'options: ' + name
            if text.startswith(prefix):
                text = r['flag'].split(',')[-1] + text[len(prefix):]
            raise ValueError(text)
    return out
