"""Clumps as other DEM codes' templates (``mss export``, :meth:`MssResult.export`): the spheres with the grain's
exact mass, centre and inertia, which those codes otherwise estimate from the spheres' union (LIGGGHTS by
Monte Carlo over ``ntry`` points) or double-count where the spheres overlap.

Every number is written as Python's repr of the double (17 significant digits at most, read back exactly).
"""

import argparse
import os
import re
import shutil
import sys
import tempfile

import numpy as np

from . import _mss, _options
from ._files import _umask, atomicWrite, refuseOverInputs

FORMATS = ('liggghts', 'kratos', 'mercurydpm', 'pfc', 'yade')
EXTENSIONS = {'liggghts': '.in', 'kratos': '.clu', 'mercurydpm': '', 'pfc': '.p3dat', 'yade': '.txt'}  # batch's
_SPHERE_EXT = tuple(f['extension'] for f in _mss.fileFormats() if f['kind'] == 'spheres')  # the format table's


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


MAX_TEMPLATES = 2000000  # seed(MAX_TEMPLATES) is under 2^31


def _number(x):
    return repr(float(x))


def _safe(text):
    """A name for a comment line: anything but printable ASCII becomes '?', so that a file named with a newline
    cannot end the comment and put a command into the script."""
    return re.sub(r'[^ -~]', '?', str(text))


def _whereGenerated(mark, centroid, R):
    """The header's two lines that put a template back where its grain was generated (readSpheres reads them):
    "c = x y z" and "R = rows", after the comment mark *mark*."""
    return ['%sc = %s' % (mark, ' '.join(_number(x) for x in centroid)),
            '%sR = %s (rows)' % (mark, ' ; '.join(' '.join(_number(x) for x in row) for row in R))]


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
        *_whereGenerated('#   ', centroid, R),
        '# mass properties: the grain\'s own (not the spheres\' union): density %s, volume %s, mass %s;'
        % (_number(density), _number(m.volume), _number(mass)),
        '#   inertia about the centre of mass in the template\'s axes: %s' % ' '.join(
            _number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))),
        '# units: lengths as the grain\'s, mass = density x volume in them; %s' % (
            'LIGGGHTS takes mass and inertia as given (use_density: volume = mass / density)' if exact else
            'mass and inertia left to LIGGGHTS\' Monte Carlo estimate of the union (ntry %d)' % ntry),
        '# use: include this file, then e.g. fix pdd all particledistribution/discrete 32452843 1 %s 1.0' % name,
        'fix %s all particletemplate/multisphere %d atom_type %d density constant %s nspheres %d ntry %d spheres &'
        % (name, seed(templateType), atomType, _number(density), len(r), ntry),
    ]
    lines += ['    %s %s %s %s &' % (_number(p[0]), _number(p[1]), _number(p[2]), _number(q)) for p, q in zip(c, r)]
    tail = '    type %d' % templateType
    if exact:
        tail += ' mass %s use_density inertia_tensor %s' % (_number(mass), ' '.join(
            _number(tensor[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))))
    return '\n'.join(lines + [tail]) + '\n'


def _name(result):
    """A one-word name for the template (Kratos reads the word after Name; MercuryDPM names the clump by its
    folder): the source's stem, with anything but letters, digits, '_', '-' and '.' made '_'."""
    stem = os.path.splitext(os.path.basename(str(result.source or '')))[0]
    return re.sub(r'[^A-Za-z0-9_.-]', '_', stem).strip('.') or 'mss_clump'


def _principalOnly(fmt, frame):
    if frame != 'principal':
        raise ValueError("export: %s takes the template in its principal axes (it reads three principal moments "
                         "and puts the principal axes along x, y, z): use frame 'principal'" % fmt)


def kratosCluster(result, frame='principal'):
    """The text of a Kratos DEM cluster file (.clu): the spheres (``Begin centers_and_radii``) in the grain's
    principal axes with its centre of mass at the origin, ``Particle_center_and_diameter`` (the origin and the
    diameter of the ball about it holding every sphere), ``Size`` (the diameter of the ball of the grain's volume),
    ``Volume`` (the grain's exact volume) and ``Inertia per unit mass`` (its three principal moments over its
    mass). Kratos scales the volume and inertia by the material's density, so no density is written."""
    _principalOnly('kratos', frame)
    c, r, inertia, R, centroid = templateFrame(result, frame)
    m = result.targetMass
    reach = float(np.max(np.linalg.norm(c, axis=1) + r))
    lines = ['//', '//   Cluster Name: "%s"' % _name(result),
             '//   written by yade-mss (mss export --format kratos) from %s: %d spheres, Dice mismatch %s on the '
             'generation grid' % (_safe(result.source or 'unknown'), len(r),
                                  _number(result.metrics.get('dice', float('nan')))),
             '//   principal axes, the centre of mass at the origin; a point p is at c + R p where the grain was '
             'generated:',
             *_whereGenerated('//   ', centroid, R),
             "//   Volume and inertia are the grain's own, not the spheres' union; Size is the diameter of a ball "
             'of that volume',
             '//', '', 'Name', _name(result), '', 'Begin centers_and_radii']
    lines += ['%s %s %s %s' % (_number(p[0]), _number(p[1]), _number(p[2]), _number(q)) for p, q in zip(c, r)]
    lines += ['End centers_and_radii', '', 'Particle_center_and_diameter', '0.0 0.0 0.0 %s' % _number(2 * reach),
              '', 'Size', _number(2 * (3 * m.volume / (4 * np.pi)) ** (1 / 3)), '', 'Volume', _number(m.volume), '',
              'Inertia per unit mass'] + [_number(inertia[i, i] / m.volume) for i in range(3)]
    return '\n'.join(lines) + '\n'


def mercuryFiles(result, density, frame='principal'):
    """MercuryDPM's clump (the layout its MClump tool writes and ``ClumpInput.h`` reads), as {relative path:
    text}: Clump/Clump.txt (x,y,z,r a pebble a line, the principal axes, the centre of mass at the origin),
    Inertia/Mass.txt, Inertia/TOI.txt (the inertia tensor, three rows), Inertia/PD.txt (the principal
    directions, three rows: the axes themselves) and mss_export.txt (how it was made: those files hold numbers
    only)."""
    _principalOnly('mercurydpm', frame)
    c, r, inertia, R, centroid = templateFrame(result, frame)
    m = result.targetMass
    rows = lambda a: '\n'.join(','.join(_number(x) for x in row) for row in a) + '\n'  # noqa: E731
    return {
        os.path.join('Clump', 'Clump.txt'): rows(np.column_stack([c, r])),
        os.path.join('Inertia', 'Mass.txt'): _number(density * m.volume) + '\n',
        os.path.join('Inertia', 'TOI.txt'): rows(density * inertia),
        os.path.join('Inertia', 'PD.txt'): rows(np.eye(3)),
        'mss_export.txt': '\n'.join([
            'MercuryDPM clump written by yade-mss (mss export --format mercurydpm)',
            'grain: %s; %d pebbles; Dice mismatch %s on the generation grid' % (
                _safe(result.source or 'unknown'), len(r), _number(result.metrics.get('dice', float('nan')))),
            "mass and inertia: the grain's own (density %s, volume %s), not the pebbles' union" % (
                _number(density), _number(m.volume)),
            'principal axes, the centre of mass at the origin; a point p is at c + R p where the grain was '
            'generated:',
            *_whereGenerated('', centroid, R),
            'full doubles are written; MercuryDPM\'s ClumpInput.h reads them with std::stof (single precision)', '']),
    }


def _placed(result, frame):
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
    p, r, inertia, at, R, centroid = _placed(result, frame)
    m = result.targetMass
    name = _name(result)
    lines = [
        '; PFC3D clump template, written by yade-mss (mss export --format pfc)',
        '; grain: %s; %d pebbles; Dice mismatch %s on the generation grid'
        % (_safe(result.source or 'unknown'), len(r), _number(result.metrics.get('dice', float('nan')))),
        '; frame: %s axes; a template point p (about its centroid) is at c + R p where the grain was generated,'
        % frame,
        *_whereGenerated(';   ', centroid, R),
        "; volume and inertia are the grain's own, not the pebbles' union; inertia for unit density, lengths as "
        "the grain's",
        'clump template create name \'%s\' ...' % name,
        '    pebbles %d ...' % len(r)]
    lines += ['    %s %s %s %s ...' % (_number(q), _number(x[0]), _number(x[1]), _number(x[2])) for x, q in zip(p, r)]
    lines += ['    volume %s ...' % _number(m.volume),
              '    inertia %s ...' % ' '.join(_number(inertia[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1),
                                                                                   (0, 2), (1, 2))),
              '    position %s' % ' '.join(_number(x) for x in at)]
    return '\n'.join(lines) + '\n'


def yadeClumps(result, density, frame='principal'):
    """The text of a yade-mss clumps file (what :func:`yade_mss.writeClumps` writes and
    :func:`yade_mss.readClumps` reads): ``x y z r 0`` a sphere (YADE's ``ymport.textClumps`` reads them) and a
    ``#mss clump`` line with the grain's exact mass, centre of mass and inertia tensor for *density*."""
    from ._clumpfiles import HEADER
    p, r, inertia, R, centroid = templateFrame(result, frame)  # the centre of mass at the origin, as templates
    m = result.targetMass
    I = density * inertia
    lines = [HEADER.rstrip('\n'),
             '# written by mss export --format yade from %s: %d spheres, Dice mismatch %s on the generation grid'
             % (_safe(result.source or 'unknown'), len(r), _number(result.metrics.get('dice', float('nan')))),
             '# frame: %s axes; a point p (about the centre of mass) is at c + R p where the grain was generated,'
             % frame,
             *_whereGenerated('#   ', centroid, R),
             '#mss clump 0 density %s mass %s centroid %s inertia %s' % (
                 _number(density), _number(density * m.volume), ' '.join(_number(x) for x in np.zeros(3)),
                 ' '.join(_number(I[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))))]
    lines += ['%s %s %s %s 0' % (_number(x[0]), _number(x[1]), _number(x[2]), _number(q)) for x, q in zip(p, r)]
    return '\n'.join(lines) + '\n'


MARK = 'mss_export.txt'


def _writeFolder(path, files):
    """Writes *files* ({relative path: text}) as the folder *path*, whole or not at all: built beside it under
    an unpredictable name, then renamed onto it. An existing folder is replaced only if this command wrote it
    (it holds mss_export.txt); a file, link or foreign folder there is refused."""
    path = os.path.abspath(os.fspath(path))
    if os.path.islink(path) or (os.path.lexists(path) and not os.path.isdir(path)):
        raise RuntimeError('export: %s: exists and is not a folder: not replaced' % path)
    if os.path.isdir(path) and not os.path.isfile(os.path.join(path, MARK)):
        raise RuntimeError('export: %s: a folder mss export did not write (no %s): not replaced' % (path, MARK))
    parent = os.path.dirname(path)
    try:
        tmp = tempfile.mkdtemp(prefix='.%s.' % os.path.basename(path)[:64], dir=parent)
    except OSError as e:
        raise RuntimeError('export: %s: cannot write (%s)' % (path, e))
    old = None
    try:
        for rel, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(tmp, rel)), exist_ok=True)
            with open(os.path.join(tmp, rel), 'x') as f:
                f.write(text)
        os.chmod(tmp, 0o777 & ~_umask())
        if os.path.isdir(path):
            old = tempfile.mkdtemp(prefix='.%s.old.' % os.path.basename(path)[:64], dir=parent)
            os.rename(path, os.path.join(old, 'x'))
        os.rename(tmp, path)
    except BaseException as e:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and os.path.isdir(os.path.join(old, 'x')) and not os.path.exists(path):
            os.rename(os.path.join(old, 'x'), path)  # put the earlier one back
        if isinstance(e, OSError):
            raise RuntimeError('export: %s: cannot write (%s)' % (path, e))
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def quaternion(R):
    """The unit quaternion (w, x, y, z), w >= 0, of the rotation matrix *R* (the largest of the four candidates
    is computed first, so that none divides by a small number)."""
    R = np.asarray(R, dtype=float)
    t = np.trace(R)
    cands = [t, R[0, 0], R[1, 1], R[2, 2]]
    i = int(np.argmax(cands))
    if i == 0:
        w = np.sqrt(1 + t) / 2
        q = [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]
    else:
        a, b, c = (i - 1, i % 3, (i + 1) % 3)
        v = np.sqrt(1 + R[a, a] - R[b, b] - R[c, c]) / 2
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (R[c, b] - R[b, c]) / (4 * v)
        q[1 + a], q[1 + b], q[1 + c] = v, (R[b, a] + R[a, b]) / (4 * v), (R[c, a] + R[a, c]) / (4 * v)
    q = np.array(q)
    return q if q[0] >= 0 else -q


def writeTemplates(outdir, b, fmt, density):
    """A batch's grains as *fmt*'s templates, one per grain in the principal axes (OUTDIR/templates/, written
    whole: a rerun leaves none of an earlier run's), and OUTDIR/placements.csv: where each goes (its centre of
    mass and the rotation from template to world as a quaternion w x y z; a template point p is at c + R p) and
    its mass. LIGGGHTS: the templates are types 1, 2, ... in the batch's order, and templates/templates.in
    includes them all."""
    files, rows = {MARK: 'templates written by mss batch --format %s (density %s): one per grain, placements '
                   'in ../placements.csv\n' % (fmt, _number(density))}, []
    ext = EXTENSIONS[fmt]
    for i, (key, r) in enumerate(b.results.items(), 1):
        name = key + ext
        if fmt == 'liggghts':
            files[name] = liggghtsTemplate(r, density, 'principal', i)
        elif fmt == 'kratos':
            files[name] = kratosCluster(r)
        elif fmt == 'pfc':
            files[name] = pfcTemplate(r)
        elif fmt == 'yade':
            files[name] = yadeClumps(r, density)
        else:
            files.update({os.path.join(key, rel): text for rel, text in mercuryFiles(r, density).items()})
        m = r.targetMass
        _, R = m.principal()
        rows.append([key, b.rows[key]['label'], os.path.join('templates', name), i] + [_number(x) for x in m.centroid]
                    + [_number(x) for x in quaternion(R)] + [_number(density * m.volume)])
    if fmt == 'liggghts':
        files['templates.in'] = ''.join('include templates/%s\n' % (key + ext) for key in b.results)
    _writeFolder(os.path.join(outdir, 'templates'), files)

    def table(p):
        import csv
        with open(p, 'w', newline='') as f:
            w = csv.writer(f)
            w.writerow(['grain', 'label', 'template', 'type', 'x', 'y', 'z', 'qw', 'qx', 'qy', 'qz', 'mass'])
            w.writerows(rows)
    atomicWrite(os.path.join(outdir, 'placements.csv'), table, 'batch')


def _checked(given):
    """The export options in *given* (None: the table's default), checked against the table."""
    return {k: _options.check('export', 'export', k, v if v is not None else _options.default(k, 'export'))
            for k, v in given.items()}


def exportTemplate(result, path, format=None, density=None, frame=None, templateType=None, atomType=None):
    """Writes *result* as *format*'s template to *path* (atomically), with the grain's exact mass properties
    (the options are ``mss export``'s; None: the table's default).

    :param result: an :class:`MssResult` (generated from a grain, or loaded from its .npz)
    :param format: 'liggghts' (an input-script file to include), 'kratos' (a .clu cluster file), 'mercurydpm'
        (a folder, the clump's name, as MClump writes it), 'pfc' (a PFC3D data file with ``clump template
        create``) or 'yade' (a yade-mss clumps file, for :func:`yade_mss.readClumps`)
    :param float density: mass per world unit cubed; the mass is it times the grain's exact volume (Kratos and
        PFC: not written, the material's or replication's density applies)
    :param frame: 'principal' or 'generated' (see :func:`templateFrame`; kratos and mercurydpm: principal; pfc
        and yade: the generated frame keeps the pebbles where they were generated)
    :param int templateType: the template's number (LIGGGHTS: consecutive from 1)
    :param int atomType: the spheres' atom (material) type (LIGGGHTS)
    """
    o = _checked(dict(format=format, density=density, frame=frame, templateType=templateType, atomType=atomType))
    if o['format'] == 'mercurydpm':
        _writeFolder(path, mercuryFiles(result, o['density'], o['frame']))
        return
    if o['format'] == 'kratos':
        text = kratosCluster(result, o['frame'])
    elif o['format'] == 'pfc':
        text = pfcTemplate(result, o['frame'])
    elif o['format'] == 'yade':
        text = yadeClumps(result, o['density'], o['frame'])
    else:
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
    if ext in _SPHERE_EXT:
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
        refuseOverInputs('export', [('-o', v.get('output'))], [a.input])
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
