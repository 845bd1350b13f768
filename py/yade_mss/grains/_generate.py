"""Generation and scoring: :func:`generate` (MSS paper, sections 2-3) and :func:`score` (eq. 7, 27)."""

import inspect
import os
import warnings

import numpy as np

from .. import _mss
from . import _options
from ._contacts import contactPoints as pointsOf, findContacts
from ._results import MassProperties, MssResult, readSpheres
from ._sources import Mesh, flatArray, massProperties, readGrain
from ._volumes import readVolume


@_options.documented('generate')
def generate(source, nSpheres=None, eta=None, dice=None, rMin=None, rMinVoxels=None, voxelSize=None,
             resolution=None, method='optimized', supersample=1, keepSymmetry=True, polish=False, maxIterations=100, deltaMin=1.0,
             threads=0, origin=None, label=None, memoryLimit=None, clip=False, refill=True, planes=(),
             maxProtrusion=None, contacts=True, contactGap=1.0, neighbourProtrusion=1.0, maxWork=None, scale=None):
    """Generates the sphere set of a grain (MSS paper, sections 2-3). The options are the option table's
    (``mss generate --help`` lists the same, spelled for the command line).

    :param source: mesh file (.stl .obj .off .ply), voxel file (.npy, .tif), 3-D numpy array (bool or int), a
        tuple (vertices (n,3), triangles (m,3)) or a dict with those keys
    OPTIONS
    :return: :class:`MssResult`
    """
    if isinstance(source, MssResult):
        return source
    given = dict(locals())
    del given['source']
    return generateWith(source, given)


def generateWith(source, given, contactPoints=None, neighbours=None, target=None):
    """:func:`generate` with its keywords in *given* (None: not given); *contactPoints*: the points to reach
    (6 numbers each: point, normal into the grain; :func:`contactPoints`, or a fragment's
    contacts in a scene) and *neighbours* (a boolean array on the source's grid: the other grains), found here
    for a labelled volume's grain when None and contacts are kept; *target*: the source's mass properties where
    the caller has them (a dict as _mss.massMesh gives), not computed again."""
    opts = _options.collect('generate', 'generate', given)
    label, origin, resolution = given.get('label'), given.get('origin'), given.get('resolution')
    s = readGrain(source, opts.get('voxelSize'), opts.get('origin'), opts.get('label'), opts.get('scale'))
    if isinstance(s, Mesh):
        if label is not None:  # it would be ignored
            raise ValueError('generate: %s: label applies to labelled voxel volumes; this is a mesh' % s.name)
        if origin is not None:
            raise ValueError('generate: %s: origin applies to voxel volumes; this is a mesh' % s.name)
        d = _mss.generateMesh(*s.args(), opts, contactPoints or [])
        target = MassProperties._fromDict(target or _mss.massMesh(*s.args(), opts.get('planes', [])))
    else:
        if resolution is not None:
            raise ValueError('generate: resolution applies to meshes; voxels are used at their own resolution')
        if contactPoints is None:
            contactPoints = []
            if label is not None and opts.get('contacts', True):  # its neighbours, as mss batch finds them
                labels = readVolume(source) if isinstance(source, (str, os.PathLike)) else np.asarray(source)
                contactPoints = pointsOf(findContacts(labels, s.voxelSize, s.origin, gap=opts.get('contactGap', 1.0)),
                                         label)
                neighbours = (labels != 0) & (labels != label)
        d = _mss.generateVoxels(*s.args(), opts, contactPoints, None if neighbours is None else np.asfortranarray(
            neighbours, dtype=np.uint8).tobytes(order='F'))
        target = MassProperties._fromDict(_mss.massVoxels(*s.args(), opts.get('planes', [])))
    for w in d['metrics'].get('warnings', []):
        warnings.warn('%s: %s' % (s.name, w))
    r = MssResult(d['centers'], d['radii'], d['metrics'], d['grid'], target, s.name)
    r.grain = source if label is None else None  # a labelled volume needs its label again: not kept
    if opts.get('scale', 1.0) != 1.0:  # the grain as generated: scaled (a volume would need its scale again)
        r.grain = (s.vertices, s.triangles) if isinstance(s, Mesh) else None
    return r


# the keywords generate() takes besides the source: what mssClump and friends pass through
GENERATE_OPTIONS = tuple(p for p in inspect.signature(generate).parameters if p != 'source')


@_options.documented('compare')
def score(target, spheres, resolution=100, offset=0.37, voxelSize=None, origin=None, label=None, planes=(),
          exact=False, samples=None, seed=None, scale=None):
    """Scores a sphere set (an :class:`MssResult` or a sphere file) against a target on a grid of its own, as
    ``mss compare`` does (with fewer figures: :func:`compareMany` gives them all).

    :param target: the grain: a mesh file, voxel file, array or (vertices, triangles), as :func:`generate` takes
    :param spheres: an :class:`MssResult` or a sphere file
    OPTIONS
    :return: dict with dice (eq. 27), eta (eq. 7), volumeRatio, coverage, outside, and the grid; with *exact*
        also exact: dice, diceError, eta, etaError, targetVolume, targetVolumeError, sphereVolume,
        sphereVolumeError (Monte Carlo on the exact shapes, one standard error each), samples, seed
    """
    opts = _options.collect('score', 'compare', dict(resolution=resolution, offset=offset, planes=planes,
                                                     exact=exact, samples=samples, seed=seed, scale=scale))
    scale = opts.get('scale')
    resolution, offset, cuts = opts['resolution'], opts['offset'], opts.get('planes', [])
    sp = spheres if isinstance(spheres, MssResult) else readSpheres(spheres)
    s = readGrain(target, voxelSize, origin, label, scale)
    if isinstance(s, Mesh):
        d = _mss.scoreMesh(*s.args(), flatArray(sp.centers), sp.radii.tolist(), resolution, offset, 1, cuts)
    else:
        d = _mss.scoreVoxels(*s.args(), flatArray(sp.centers), sp.radii.tolist(), cuts)
    if opts.get('exact'):
        n, seed = opts.get('samples', 1000000), opts.get('seed', 1)
        f = _mss.scoreExactMesh if isinstance(s, Mesh) else _mss.scoreExactVoxels
        d['exact'] = f(*s.args(), flatArray(sp.centers), sp.radii.tolist(), n, seed, cuts)
    return d


@_options.documented('compare')
def compareMany(target, spheres, resolution=100, offset=0.37, align=None, planes=(), clumpId=None, voxelSize=None,
                origin=None, label=None, supersample=1, exact=False, samples=None, seed=None, maxWork=None,
                scale=None):
    """Compares sphere files (or :class:`MssResult` objects) of any generator with a grain, one row each, as
    ``mss compare GRAIN A B C`` prints them.

    :param target: the grain: a mesh file, voxel file, array or (vertices, triangles), as :func:`generate` takes
    :param spheres: a list of sphere files (CLUMP's ``x,y,z,r`` in its Python or MATLAB form, legacy VTK, YADE
        text clumps with ``clumpId``, ours) or results
    OPTIONS
    :return: list of dicts: file (a result: "result K (its grain's file)"), spheres, dice, eta, volumeRatio,
        coverage, outside, protrusion (largest, world units), smallestRadius, massError, centroidError,
        inertiaError (the union against the grain), rotation (3x3) and translation of the registration applied
        (*align* registers only a set in another frame: under half its volume inside the grain's bounding box),
        error ('' or, with several, the one file's error: that row has only file and error); with *exact* also
        exact (as :func:`score` gives it)
    """
    items = list(spheres) if isinstance(spheres, (list, tuple)) else [spheres]
    opts = _options.collect('compareMany', 'compare', dict(resolution=resolution, offset=offset, align=align,
                                                           planes=planes, supersample=supersample, exact=exact,
                                                           samples=samples, seed=seed, maxWork=maxWork,
                                                           scale=scale))
    scale = opts.get('scale')
    s = readGrain(target, voxelSize, origin, label, scale)
    if isinstance(s, Mesh) and (voxelSize is not None or origin is not None or label is not None):
        raise ValueError('compareMany: %s: voxelSize, origin and label apply to voxel volumes; this is a mesh '
                         '(resolution sets the scoring grid)' % s.name)
    if isinstance(s, Mesh) and len(items) > 1:  # the grain's own faults first, named by it (a flat mesh)
        try:
            massProperties((s.vertices, s.triangles))
        except ValueError as e:
            raise ValueError('%s: %s' % (s.name, e)) from None
    rows = []
    for k, item in enumerate(items):
        # an in-memory result is labelled as one (its grain's file name would read as a sphere file's)
        name = ('result %d (%s)' % (k + 1, os.path.basename(item.source) or 'in memory')
                if isinstance(item, MssResult) else str(item))
        try:
            sp = item if isinstance(item, MssResult) else readSpheres(item, clumpId)
            if isinstance(s, Mesh):
                row = _mss.compareMesh(*s.args(), flatArray(sp.centers), sp.radii.tolist(), opts)
            else:
                row = _mss.compareVoxels(*s.args(), flatArray(sp.centers), sp.radii.tolist(), opts)
        except ValueError as e:
            message = str(e) if name in str(e) else '%s: %s' % (name, e)  # the file at fault, not the grain
            if len(items) == 1:
                raise ValueError(message) from None
            rows.append({'file': name, 'error': message})  # one bad file is a row, not the end of the table
            continue
        row['file'] = name
        row['error'] = ''
        row['rotation'] = [row['rotation'][3 * i:3 * i + 3] for i in range(3)]
        rows.append(row)
    return rows
