"""LIGGGHTS (``fix particletemplate/multisphere``): an input-script file to ``include``, with the grain's exact
mass and inertia tensor (no Monte Carlo)."""

from ._common import number, safe, templateFrame, whereGenerated
from ._registry import Format, register

MAX_TEMPLATES = 2000000  # seed(MAX_TEMPLATES) is under 2^31


def seed(templateType):
    """The template's random seed: LIGGGHTS wants a prime over 10000, and different ones for every template of
    a distribution and for its insertion fix, so each type gets its own (the first prime from 20,000,000 + 1000
    type: the seeds its manual's examples use stay free)."""
    n = 20000000 + 1000 * int(templateType)
    while any(n % d == 0 for d in range(2, int(n ** 0.5) + 1)):
        n += 1
    if n > 2 ** 31 - 1:  # LIGGGHTS reads a seed with atoi: a larger one would wrap
        raise ValueError('export: template type %d: its seed %d does not fit LIGGGHTS\' 32-bit integers '
                         '(at most %d templates)' % (templateType, n, MAX_TEMPLATES))
    return n


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
        % (safe(result.source or 'unknown'), len(r), number(result.metrics.get('dice', float('nan')))),
        '# frame: %s axes, the centre of mass at the origin; a template point p is at c + R p where the grain '
        'was generated,' % frame,
        *whereGenerated('#   ', centroid, R),
        '# mass properties: the grain\'s own (not the spheres\' union): density %s, volume %s, mass %s;'
        % (number(density), number(m.volume), number(mass)),
        '#   inertia about the centre of mass in the template\'s axes: %s' % ' '.join(
            number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))),
        '# units: lengths as the grain\'s, mass = density x volume in them; %s' % (
            'LIGGGHTS takes mass and inertia as given (use_density: volume = mass / density)' if exact else
            'mass and inertia left to LIGGGHTS\' Monte Carlo estimate of the union (ntry %d)' % ntry),
        '# use: include this file, then e.g. fix pdd all particledistribution/discrete 32452843 1 %s 1.0' % name,
        'fix %s all particletemplate/multisphere %d atom_type %d density constant %s nspheres %d ntry %d spheres &'
        % (name, seed(templateType), atomType, number(density), len(r), ntry),
    ]
    lines += ['    %s %s %s %s &' % (number(p[0]), number(p[1]), number(p[2]), number(q)) for p, q in zip(c, r)]
    tail = '    type %d' % templateType
    if exact:
        tail += ' mass %s use_density inertia_tensor %s' % (number(mass), ' '.join(
            number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))))
    return '\n'.join(lines + [tail]) + '\n'


register(Format('liggghts', '.in', lambda r, o: liggghtsTemplate(r, o['density'], o['frame'], o['templateType'],
                                                                  o['atomType']),
                index=lambda names: {'templates.in': ''.join('include templates/%s\n' % n for n in names)}))
