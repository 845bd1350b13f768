"""Kratos DEM: a cluster file (.clu)."""

import numpy as np

from ._common import number, principalOnly, safe, templateFrame, templateName, whereGenerated
from ._registry import Format, register


def kratosCluster(result, frame='principal'):
    """The text of a Kratos DEM cluster file (.clu): the spheres (``Begin centers_and_radii``) in the grain's
    principal axes with its centre of mass at the origin, ``Particle_center_and_diameter`` (the origin and the
    diameter of the ball about it holding every sphere), ``Size`` (the diameter of the ball of the grain's volume),
    ``Volume`` (the grain's exact volume) and ``Inertia per unit mass`` (its three principal moments over its
    mass). Kratos scales the volume and inertia by the material's density, so no density is written."""
    principalOnly('kratos', frame)
    c, r, inertia, R, centroid = templateFrame(result, frame)
    m = result.targetMass
    reach = float(np.max(np.linalg.norm(c, axis=1) + r))
    lines = ['//', '//   Cluster Name: "%s"' % templateName(result),
             '//   written by yade-mss (mss export --format kratos) from %s: %d spheres, Dice mismatch %s on the '
             'generation grid' % (safe(result.source or 'unknown'), len(r),
                                  number(result.metrics.get('dice', float('nan')))),
             '//   principal axes, the centre of mass at the origin; a point p is at c + R p where the grain was '
             'generated:',
             *whereGenerated('//   ', centroid, R),
             "//   Volume and inertia are the grain's own, not the spheres' union; Size is the diameter of a ball "
             'of that volume',
             '//', '', 'Name', templateName(result), '', 'Begin centers_and_radii']
    lines += ['%s %s %s %s' % (number(p[0]), number(p[1]), number(p[2]), number(q)) for p, q in zip(c, r)]
    lines += ['End centers_and_radii', '', 'Particle_center_and_diameter', '0.0 0.0 0.0 %s' % number(2 * reach),
              '', 'Size', number(2 * (3 * m.volume / (4 * np.pi)) ** (1 / 3)), '', 'Volume', number(m.volume), '',
              'Inertia per unit mass'] + [number(inertia[i, i] / m.volume) for i in range(3)]
    return '\n'.join(lines) + '\n'


register(Format('kratos', '.clu', lambda r, o: kratosCluster(r, o['frame'])))
