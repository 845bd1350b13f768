"""Itasca PFC3D: a data file (.p3dat) with ``clump template create``."""

import numpy as np

from ._common import number, safe, templateFrame, templateName, whereGenerated
from ._registry import Format, register


def placed(result, frame):
    """The template's pebbles and inertia per unit density, with the centre of mass they are about: in the
    principal frame the pebbles about the origin, in the generated frame where they were generated (the centre
    of mass the grain's own)."""
    c, r, inertia, R, centroid = templateFrame(result, frame)
    if frame == 'generated':
        return c + centroid, r, inertia, centroid, R, centroid
    return c, r, inertia, np.zeros(3), R, centroid


def pfcTemplate(result, frame='principal'):
    """The text of an Itasca PFC3D data file (.p3dat) holding a ``clump template create`` command: the pebbles
    (``pebbles N r x y z ...``), the grain's exact ``volume``, its ``inertia`` tensor for unit density (I11 I22
    I33 I12 I13 I23, as PFC takes a template's) and the ``position`` of its centroid. PFC translates the
    pebbles so that the centroid is at the template's origin and keeps the position for ``clump replicate
    original-position``; templates are of unit density (``clump replicate density`` scales them)."""
    p, r, inertia, at, R, centroid = placed(result, frame)
    m = result.targetMass
    name = templateName(result)
    lines = [
        '; PFC3D clump template, written by yade-mss (mss export --format pfc)',
        '; grain: %s; %d pebbles; Dice mismatch %s on the generation grid'
        % (safe(result.source or 'unknown'), len(r), number(result.metrics.get('dice', float('nan')))),
        '; frame: %s axes; a template point p (about its centroid) is at c + R p where the grain was generated,'
        % frame,
        *whereGenerated(';   ', centroid, R),
        "; volume and inertia are the grain's own, not the pebbles' union; inertia for unit density, lengths as "
        "the grain's",
        'clump template create name \'%s\' ...' % name,
        '    pebbles %d ...' % len(r)]
    lines += ['    %s %s %s %s ...' % (number(q), number(x[0]), number(x[1]), number(x[2])) for x, q in zip(p, r)]
    lines += ['    volume %s ...' % number(m.volume),
              '    inertia %s ...' % ' '.join(number(inertia[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1),
                                                                                   (0, 2), (1, 2))),
              '    position %s' % ' '.join(number(x) for x in at)]
    return '\n'.join(lines) + '\n'


register(Format('pfc', '.p3dat', lambda r, o: pfcTemplate(r, o['frame'])))
