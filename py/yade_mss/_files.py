"""Files written whole or not at all: a temporary file beside the target, then a rename."""

import os


def atomicWrite(path, write, where):
    """Calls ``write(tmp)`` on a temporary path beside *path* (same extension), then renames it onto *path*;
    nothing is left behind if anything fails. An OSError becomes RuntimeError('WHERE: PATH: cannot write ...')."""
    path = os.fspath(path)
    tmp = '%s.tmp%d%s' % (path, os.getpid(), os.path.splitext(path)[1])
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        if isinstance(e, OSError):
            raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
        raise


def parseOrigin(text, n):
    """``--origin X,Y,Z`` (or X,Y for images) -> n floats; ValueError naming the option otherwise."""
    if text is None:
        return None
    try:
        v = [float(x) for x in text.split(',')]
    except ValueError:
        v = []
    if len(v) != n or not all(x == x and abs(x) != float('inf') for x in v):
        raise ValueError('--origin: expected %s (finite numbers), got %r' % (','.join('XYZ'[:n]), text))
    return v
