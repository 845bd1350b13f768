"""yade-mss clumps files: YADE's ``x y z r clumpId`` lines (``ymport.textClumps`` reads them) and a ``#mss clump``
line a clump with its exact mass properties (:func:`yade_mss.readClumps` restores them)."""

import numpy as np

from ..base import requireRegularFile
from ._common import number, safe, templateFrame, whereGenerated
from ._registry import Format, register


HEADER = ('# yade-mss clumps: x y z r clumpId, one line per sphere (ymport.textClumps reads the spheres, with '
          "YADE's own summed masses).\n# Each '#mss clump' line holds that clump's exact mass properties; "
          'yade_mss.readClumps restores them.\n')


def yadeClumps(result, density, frame='principal'):
    """The text of a yade-mss clumps file (what :func:`yade_mss.writeClumps` writes and
    :func:`yade_mss.readClumps` reads): ``x y z r 0`` a sphere (YADE's ``ymport.textClumps`` reads them) and a
    ``#mss clump`` line with the grain's exact mass, centre of mass and inertia tensor for *density*."""
    p, r, inertia, R, centroid = templateFrame(result, frame)  # the centre of mass at the origin, as templates
    m = result.targetMass
    I = density * inertia
    lines = [HEADER.rstrip('\n'),
             '# written by mss export --format yade from %s: %d spheres, Dice mismatch %s on the generation grid'
             % (safe(result.source or 'unknown'), len(r), number(result.metrics.get('dice', float('nan')))),
             '# frame: %s axes; a point p (about the centre of mass) is at c + R p where the grain was generated,'
             % frame,
             *whereGenerated('#   ', centroid, R),
             '#mss clump 0 density %s mass %s centroid %s inertia %s' % (
                 number(density), number(density * m.volume), ' '.join(number(x) for x in np.zeros(3)),
                 ' '.join(number(I[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))))]
    lines += ['%s %s %s %s 0' % (number(x[0]), number(x[1]), number(x[2]), number(q)) for x, q in zip(p, r)]
    return '\n'.join(lines) + '\n'


MAX_CLUMP_FILE_BYTES = 4 << 30  # readClumps reads the file whole: beyond this it is refused, not read


def parseClumps(path):
    """{clumpId: [spheres (x, y, z, r)]} in file order, and {clumpId: header numbers}."""
    groups, headers = {}, {}
    requireRegularFile('readClumps', path)  # a FIFO would block, a device never end
    try:
        with open(path, 'rb') as f:
            raw = f.read(MAX_CLUMP_FILE_BYTES + 1)
        if len(raw) > MAX_CLUMP_FILE_BYTES:
            raise ValueError('readClumps: %s: over %d bytes (a clumps file of 10^7 spheres takes about 1 GB)'
                             % (path, MAX_CLUMP_FILE_BYTES))
    except OSError as e:
        raise ValueError('readClumps: %s: cannot open file (%s)' % (path, e.strerror))
    for n, line in enumerate(raw.decode('utf-8', 'backslashreplace').splitlines(), 1):
        words = line.split()
        if not words:
            continue
        try:
            if words[:2] == ['#mss', 'clump']:
                v = [float(w) for w in words[2:] if w not in ('density', 'mass', 'centroid', 'inertia')]
                if len(v) != 12:
                    raise ValueError
                headers[int(v[0])] = v[1:]
                continue
            if words[0].startswith('#'):
                continue
            if len(words) < 5:
                raise ValueError
            x, y, z, r = (float(w) for w in words[:4])
            cid = int(float(words[4]))
        except ValueError:
            raise ValueError('readClumps: %s: line %d: expected x y z r clumpId, got %r' % (path, n, line[:80]))
        if not (r > 0 and np.isfinite([x, y, z, r]).all()):
            raise ValueError('readClumps: %s: line %d: radius must be > 0 and numbers finite' % (path, n))
        groups.setdefault(cid, []).append((x, y, z, r))
    if not groups:
        raise ValueError('readClumps: %s: no spheres in file' % path)
    return groups, headers


register(Format('yade', '.txt', lambda r, o: yadeClumps(r, o['density'], o['frame'])))
