"""MercuryDPM: a clump folder, as its MClump tool writes it."""

import os

import numpy as np

from ._common import number, principalOnly, safe, templateFrame, whereGenerated
from ._registry import Format, register


def mercuryFiles(result, density, frame='principal'):
    """MercuryDPM's clump (the layout its MClump tool writes and ``ClumpInput.h`` reads), as {relative path:
    text}: Clump/Clump.txt (x,y,z,r a pebble a line, the principal axes, the centre of mass at the origin),
    Inertia/Mass.txt, Inertia/TOI.txt (the inertia tensor, three rows), Inertia/PD.txt (the principal
    directions, three rows: the axes themselves) and mss_export.txt (how it was made: those files hold numbers
    only)."""
    principalOnly('mercurydpm', frame)
    c, r, inertia, R, centroid = templateFrame(result, frame)
    m = result.targetMass
    rows = lambda a: '\n'.join(','.join(number(x) for x in row) for row in a) + '\n'  # noqa: E731
    return {
        os.path.join('Clump', 'Clump.txt'): rows(np.column_stack([c, r])),
        os.path.join('Inertia', 'Mass.txt'): number(density * m.volume) + '\n',
        os.path.join('Inertia', 'TOI.txt'): rows(density * inertia),
        os.path.join('Inertia', 'PD.txt'): rows(np.eye(3)),
        'mss_export.txt': '\n'.join([
            'MercuryDPM clump written by yade-mss (mss export --format mercurydpm)',
            'grain: %s; %d pebbles; Dice mismatch %s on the generation grid' % (
                safe(result.source or 'unknown'), len(r), number(result.metrics.get('dice', float('nan')))),
            "mass and inertia: the grain's own (density %s, volume %s), not the pebbles' union" % (
                number(density), number(m.volume)),
            'principal axes, the centre of mass at the origin; a point p is at c + R p where the grain was '
            'generated:',
            *whereGenerated('', centroid, R),
            'full doubles are written; MercuryDPM\'s ClumpInput.h reads them with std::stof (single precision)', '']),
    }


register(Format('mercurydpm', '', lambda r, o: mercuryFiles(r, o['density'], o['frame']), folder=True))
