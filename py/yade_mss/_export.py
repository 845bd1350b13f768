"""Clumps as other DEM codes' templates (``mss export``, :meth:`MssResult.export`): the spheres with the grain's
exact mass, centre and inertia, which those codes otherwise estimate from the spheres' union (LIGGGHTS by
Monte Carlo over ``ntry`` points) or double-count where the spheres overlap.

Every number is written as Python's repr of the double (17 significant digits at most, read back exactly).
"""

import argparse
import os
import re
import sys

import numpy as np

from . import _options
from ._files import atomicWrite

FORMATS = ('liggghts',)
SEED = 15485863  # LIGGGHTS wants a prime over 10000 for the template's random numbers


def _number(x):
    return repr(float(x))


def _safe(text):
    """A name for a comment line: anything but printable ASCII becomes '?', so that a file named with a newline
    cannot end the comment and put a command into the script."""
    return re.sub(r'[^ -~]', '?', str(text))


def templateFrame(result, frame='principal'):
    """The spheres and the grain's inertia in the template's frame, whose origin is the grain's centre of mass.

    :param frame: 'principal' (the axes are the grain's principal axes of inertia, ascending moments) or
        'generated' (the axes the grain was generated in)
    :return: (centres (n, 3), radii (n,), inertia per unit density (3, 3), rotation R, centroid c): a body point
        p is at c + R p in the generated frame
    """
    m = result.targetMass
    if m is None:
        raise ValueError('export: the result has no grain mass properties (a bare sphere file): export the '
                         'grain (mesh or volume) or its saved result (.npz)')
    if frame == 'principal':
        w, R = m.principal()
        inertia = np.diag(w)  # diagonal by construction: R^T I R leaves rounding off the diagonal
    elif frame == 'generated':
        R, inertia = np.eye(3), m.inertia
    else:
        raise ValueError("export: frame must be 'principal' or 'generated', got %r" % (frame,))
    centres = (np.asarray(result.centers, dtype=float) - m.centroid) @ R
    return centres, np.asarray(result.radii, dtype=float), inertia, R, m.centroid.copy()


def liggghtsTemplate(result, density, frame='principal', templateType=1, atomType=1, ntry=1000000, exact=True):
    """The text of a LIGGGHTS input-script file to ``include``: a ``fix particletemplate/multisphere`` with the
    spheres inline and, with *exact*, the grain's exact mass and inertia tensor (``mass M use_density
    inertia_tensor Ixx Ixy Ixz Iyy Iyz Izz``; LIGGGHTS then puts the centre of mass at the template's origin, as
    written here, and runs no Monte Carlo). Without *exact* LIGGGHTS estimates both from the spheres' union."""
    c, r, inertia, R, centroid = templateFrame(result, frame)
    m = result.targetMass
    mass = density * m.volume
    tensor = density * inertia
    name = 'mss_template_%d' % templateType
    lines = [
        '# LIGGGHTS multisphere template, written by yade-mss (mss export --format liggghts)',
        '# grain: %s; %d spheres; Dice mismatch %s on the generation grid'
        % (_safe(result.source or 'unknown'), len(r), _number(result.metrics.get('dice', float('nan')))),
        '# frame: %s axes, the centre of mass at the origin; a template point p is at c + R p where the grain '
        'was generated,' % frame,
        '#   c = %s' % ' '.join(_number(x) for x in centroid),
        '#   R = %s (rows)' % ' ; '.join(' '.join(_number(x) for x in row) for row in R),
        '# mass properties: the grain\'s own (not the spheres\' union): density %s, volume %s, mass %s;'
        % (_number(density), _number(m.volume), _number(mass)),
        '#   inertia about the centre of mass in the template\'s axes: %s' % ' '.join(
            _number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))),
        '# units: lengths as the grain\'s, mass = density x volume in them; %s' % (
            'LIGGGHTS takes mass and inertia as given (use_density: volume = mass / density)' if exact else
            'mass and inertia left to LIGGGHTS\' Monte Carlo estimate of the union (ntry %d)' % ntry),
        '# use: include this file, then e.g. fix pdd all particledistribution/discrete 32452843 1 %s 1.0' % name,
        'fix %s all particletemplate/multisphere %d atom_type %d density constant %s nspheres %d ntry %d spheres &'
        % (name, SEED, atomType, _number(density), len(r), ntry),
    ]
    lines += ['    %s %s %s %s &' % (_number(p[0]), _number(p[1]), _number(p[2]), _number(q)) for p, q in zip(c, r)]
    tail = '    type %d' % templateType
    if exact:
        tail += ' mass %s use_density inertia_tensor %s' % (_number(mass), ' '.join(
            _number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))))
    return '\n'.join(lines + [tail]) + '\n'


def _checked(given):
    """The export options in *given* (None: the table's default), checked against the table."""
    return {k: _options.check('export', 'export', k, v if v is not None else _options.default(k, 'export'))
            for k, v in given.items()}


def exportTemplate(result, path, format=None, density=None, frame=None, templateType=None, atomType=None):
    """Writes *result* as *format*'s template to *path* (atomically), with the grain's exact mass properties
    (the options are ``mss export``'s; None: the table's default).

    :param result: an :class:`MssResult` (generated from a grain, or loaded from its .npz)
    :param format: 'liggghts' (an input-script file to include)
    :param float density: mass per world unit cubed; the mass is it times the grain's exact volume
    :param frame: 'principal' or 'generated' (see :func:`templateFrame`)
    :param int templateType: the template's number (LIGGGHTS: consecutive from 1)
    :param int atomType: the spheres' atom (material) type
    """
    o = _checked(dict(format=format, density=density, frame=frame, templateType=templateType, atomType=atomType))
    text = liggghtsTemplate(result, o['density'], o['frame'], o['templateType'], o['atomType'])

    def write(p):
        with open(p, 'w') as f:
            f.write(text)
    atomicWrite(path, write, 'export')


def _result(source, gen):
    """The result to export: a saved result (.npz) as it is, or a grain generated with *gen*."""
    from ._generate import _generate
    from ._results import MssResult
    if isinstance(source, str) and os.path.splitext(source)[1].lower() == '.npz':
        if gen:
            raise ValueError('export: %s is a saved result; generation options (%s) apply to a grain'
                             % (source, ', '.join(sorted(gen))))
        return MssResult.load(source)
    ext = os.path.splitext(source)[1].lower() if isinstance(source, str) else ''
    if ext in ('.csv', '.txt', '.vtk'):
        raise ValueError('export: %s is a sphere file without its grain: export the grain (mesh or volume) or its '
                         'saved result (.npz), so that the mass properties are the grain\'s' % source)
    return _generate(source, gen)


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss export', description='a clump as another DEM code\'s template, with the '
                                'grain\'s exact mass properties (yade-mss)')
    p.add_argument('input', help='a grain (mesh or voxel volume; generated with the options given) or a saved '
                   'result (.npz)')
    _options.addArguments(p, 'export')
    a = p.parse_args(argv)
    try:
        v = _options.parsed('export', a)
        own = ('output', 'format', 'density', 'frame', 'templateType', 'atomType')
        gen = {k: x for k, x in v.items() if k not in own}
        r = _result(a.input, gen)
        o = _checked({k: v.get(k) for k in own if k != 'output'})
        exportTemplate(r, v['output'], **o)
    except (ValueError, RuntimeError, OSError) as e:
        print('mss export: error: %s' % e, file=sys.stderr)
        return 1
    m = r.targetMass
    print('wrote       %s  (%s template of %d spheres; mass %.6g = density %g x the grain\'s volume %.6g)'
          % (v['output'], o['format'], len(r), o['density'] * m.volume, o['density'], m.volume))
    return 0


if __name__ == '__main__':
    sys.exit(main())
