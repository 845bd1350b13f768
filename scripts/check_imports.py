#!/usr/bin/python3
"""The import structure of the Python package py/yade_mss, checked (docs/guide/architecture.rst draws it):

- the sub-packages are layers, and a module imports only its own sub-package and the layers below it
  (LAYERS); the C++ module ``yade_mss._mss`` is below them all;
- no import cycle among the package's modules (imports made when a module loads);
- at most MAX_LATE imports of the package made inside functions, each with its reason on the line;
- no private name (``_name``, or a ``_module`` of another sub-package) crosses a sub-package: what a layer needs
  from another is in that sub-package's ``__init__``;
- no module imports the package's own ``__init__`` (``from .. import name``, but for ``_mss``);
- only the ``yade`` sub-package imports YADE; ``base`` and ``grains`` import no matplotlib either.

Prints the layers and each sub-package's imports; exit status 1 when a rule is broken. Run from the repository
root (or give the package's folder).
"""
import ast
import os
import sys

PACKAGE = 'yade_mss'
# rank of each sub-package: a module may import its own sub-package or one of a lower rank
LAYERS = {'base': 0, 'grains': 1, 'exports': 2, 'pictures': 2, 'spheropolygons': 2, 'yade': 3, 'specimens': 4,
          'studies': 5, 'cli': 6}
TOP = 7  # the package's __init__ and __main__
MAX_LATE = 3
NO_YADE = set(LAYERS) - {'yade'}
NO_MATPLOTLIB = {'base', 'grains'}


def modules(root):
    """{dotted module name: path} of every .py file under *root* (the package's folder)."""
    out = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != '__pycache__')
        for f in sorted(files):
            if f.endswith('.py'):
                rel = os.path.relpath(os.path.join(folder, f), os.path.dirname(root))[:-3].split(os.sep)
                if rel[-1] == '__init__':
                    rel = rel[:-1]
                out['.'.join(rel)] = os.path.join(folder, f)
    out[PACKAGE + '._mss'] = None  # the C++ module (built, not in the source tree)
    return out


def isPackage(name, path):
    return path.endswith('__init__.py')


def resolve(mod, path, level, target):
    """The absolute name of a relative import of *target* (may be '') at *level* from module *mod*."""
    parts = mod.split('.')
    if not isPackage(mod, path):
        parts = parts[:-1]
    if level > 1:
        parts = parts[:len(parts) - (level - 1)]
    return '.'.join(parts + ([target] if target else []))


def layer(mod):
    parts = mod.split('.')
    return parts[1] if len(parts) > 1 and parts[1] in LAYERS else None


def rank(mod):
    sub = layer(mod)
    if sub is not None:
        return LAYERS[sub]
    return -1 if mod == PACKAGE + '._mss' else TOP


def imports(mod, path, known):
    """(line, imported module, names, inside a function, the line's text) of every import of the package."""
    with open(path) as f:
        source = f.read()
    tree = ast.parse(source, path)
    lines = source.split('\n')
    out = []

    def visit(node, inFunction):
        for child in ast.iter_child_nodes(node):
            late = inFunction or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.ImportFrom):
                if child.level:
                    base = resolve(mod, path, child.level, child.module or '')
                elif (child.module or '').split('.')[0] in (PACKAGE, 'yade', 'matplotlib'):
                    base = child.module
                else:
                    base = None
                if base is not None:
                    for a in child.names:
                        sub = base + '.' + a.name
                        target = sub if sub in known else base  # `from . import _options` names a module
                        out.append((child.lineno, target, a.name if target == base else '', inFunction,
                                    lines[child.lineno - 1]))
            elif isinstance(child, ast.Import):
                for a in child.names:
                    if a.name.split('.')[0] in (PACKAGE, 'yade', 'matplotlib'):
                        out.append((child.lineno, a.name, '', inFunction, lines[child.lineno - 1]))
            visit(child, late)
    visit(tree, False)
    return out


def cycle(graph):
    """A cycle of the directed *graph* ({node: set}) as a list of nodes, or None."""
    state, stack = {}, []

    def walk(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if state.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if m not in state:
                found = walk(m)
                if found:
                    return found
        state[n] = 2
        stack.pop()
        return None
    for n in sorted(graph):
        if n not in state:
            found = walk(n)
            if found:
                return found
    return None


def check(root):
    known = modules(root)
    bad, late, graph, uses = [], [], {}, {}
    for mod, path in sorted(known.items()):
        if path is None:
            continue
        where = os.path.relpath(path)
        sub = layer(mod)
        for line, target, name, inFunction, text in imports(mod, path, known):
            top = target.split('.')[0]
            if top in ('yade', 'matplotlib'):
                if top == 'yade' and sub in NO_YADE | {None}:
                    bad.append('%s:%d: imports YADE (only the yade sub-package may)' % (where, line))
                if top == 'matplotlib' and sub in NO_MATPLOTLIB:
                    bad.append('%s:%d: imports matplotlib (the %s layer draws nothing)' % (where, line, sub))
                continue
            if target == PACKAGE and mod != PACKAGE:
                bad.append('%s:%d: imports the package\'s __init__ (%s)' % (where, line, name))
            to = layer(target)
            if inFunction:
                late.append('%s:%d: %s' % (where, line, text.strip()))
                if '#' not in text:
                    bad.append('%s:%d: an import inside a function without its reason beside it' % (where, line))
            else:
                graph.setdefault(mod, set()).add(target)
            if to is not None and to != sub:
                uses.setdefault(sub or 'top', set()).add(to)
                private = [p for p in target.split('.')[2:] + ([name] if name else []) if p.startswith('_')]
                if private:
                    bad.append('%s:%d: the private name %s of the %s sub-package used from %s'
                               % (where, line, '.'.join(private), to, sub or 'the package'))
                if rank(target) >= rank(mod) and not inFunction:  # above it, or beside it (sideways)
                    bad.append('%s:%d: %s imports %s, a layer not below it' % (where, line, sub or mod, to))
    # a package's __init__ loads its modules: edges from the package to each module it imports are in graph
    found = cycle(graph)
    if found:
        bad.append('an import cycle: ' + ' -> '.join(found))
    if len(late) > MAX_LATE:
        bad.append('%d imports of the package inside functions (bar %d)' % (len(late), MAX_LATE))
    return bad, late, uses


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.join('py', PACKAGE)
    bad, late, uses = check(root)
    order = sorted(LAYERS, key=lambda s: (LAYERS[s], s))
    print('layers, bottom up: ' + ', '.join('%s (%d)' % (s, LAYERS[s]) for s in order))
    for s in order + ['top']:
        print('  %-15s imports %s' % (s, ', '.join(sorted(uses.get(s, ()), key=lambda t: LAYERS[t])) or 'nothing'))
    print('imports inside functions (%d, bar %d):' % (len(late), MAX_LATE))
    for x in late:
        print('  ' + x)
    for b in bad:
        print('RULE BROKEN: ' + b)
    print('imports: %d rules broken' % len(bad))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
