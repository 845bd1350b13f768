"""The commands of ``mss`` that run in Python (batch, preview, curve, ochart, export, spheropolygon,
triaxial): each
command's parser, over the layers' functions. ``python3 -m yade_mss COMMAND ...`` runs them; the C++ ``mss``
hands these commands to it.
"""

import sys

from ._batch import main as batch
from ._export import main as export
from ._ochart import main as ochart
from ._pictures import main as pictures
from ._spheropolygon import main as spheropolygon
from ._triaxial import main as triaxial

__all__ = ['run', 'main', 'batch', 'export', 'ochart', 'pictures', 'spheropolygon', 'triaxial']


def run(argv):
    """Runs the command ``argv[0]`` with the rest as its arguments; returns the exit status."""
    command = argv[0] if argv else ''
    if command == 'batch':
        return batch(argv[1:])
    if command == 'export':
        return export(argv[1:])
    if command == 'ochart':
        return ochart(argv[1:])
    if command == 'spheropolygon':
        return spheropolygon(argv[1:])
    if command == 'triaxial':
        return triaxial(argv[1:])
    return pictures(argv)


def _warning(message, category, filename, lineno, file=None, line=None):
    """A warning as a command's line ("mss batch: warning: ..."), not Python's (a source path, a line number
    and the warning's class: what a user of the command has no use for)."""
    return 'mss %s: warning: %s\n' % (_COMMAND[0], message)


_COMMAND = ['']


def main(argv=None):
    """``python3 -m yade_mss``: :func:`run` on the command line's arguments; Ctrl-C is status 130."""
    import warnings
    argv = sys.argv[1:] if argv is None else argv
    _COMMAND[0] = argv[0] if argv else ''
    warnings.formatwarning = _warning
    try:
        return run(argv)
    except KeyboardInterrupt:  # Ctrl-C: whatever was being written is not published (atomic writes)
        print('\nmss %s: interrupted (Ctrl-C)' % (argv[0] if argv else ''), file=sys.stderr)
        return 130
