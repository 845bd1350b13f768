"""Generation and scoring: :func:`generate` (MSS paper, sections 2-3) and :func:`score` (eq. 7, 27)."""

import inspect
import warnings

from . import _mss
from ._args import INT64_MAX, flag, integer, number, vector3
from ._results import MassProperties, MssResult, readSpheres
from ._sources import _Mesh, _flat, _plane, _source


MAX_THREADS = 1024  # OpenMP threads: more fail to start (libgomp) or overflow its stacks
MAX_MEMORY_GIB = 1 << 20  # 1 PiB: beyond it the byte count overflows


def _planeList(planes):
    if isinstance(planes, (str, bytes)) or not hasattr(planes, '__iter__'):
        raise TypeError('generate: planes must be a list of ((px, py, pz), (nx, ny, nz)), got %r' % (planes,))
    return list(planes)


def generate(source, nSpheres=None, eta=None, dice=None, rMin=None, voxelSize=None, resolution=None,
             method='optimized', supersample=1, keepSymmetry=True, maxIterations=100, deltaMin=1.0, threads=0,
             origin=None, label=None, memoryLimit=None, clip=False, refill=True, planes=(), maxProtrusion=None):
    """Generates the sphere set of a grain (MSS paper, sections 2-3).

    :param source: mesh file (.stl .obj .off .ply), voxel file (.npy), 3-D numpy array (bool or int), a tuple
        (vertices (n,3), triangles (m,3)) or a dict with those keys
    :param int nSpheres: at most this many spheres (problem (i))
    :param float eta: stop at relative mismatch eta (eq. 7; problem (ii): fewest spheres meeting it), in (0, 1)
    :param float dice: stop at Dice mismatch (eq. 27), in (0, 1)
    :param float rMin: no sphere smaller than this radius (world units)
    :param float voxelSize: mesh: voxel edge of the generation grid; voxels: the array's voxel edge (default 1)
    :param int resolution: mesh: voxels along the shortest bounding-box edge (default 100 when neither is given)
    :param str method: 'optimized' (default) or 'paper' (the published procedure)
    :param int supersample: mesh: k^3 samples per voxel in voxelisation (1 = voxel centres)
    :param bool keepSymmetry: keep the grain's mirror symmetries (optimized method)
    :param int maxIterations: iteration cap (paper section 3.5)
    :param float deltaMin: paper method: least distance between sphere centres, in voxels
    :param int threads: OpenMP threads (0: OpenMP's default); the result does not depend on it
    :param origin: voxels: world position of the centre of voxel (0, 0, 0)
    :param int label: voxels: solid where the array equals this label (labelled CT volumes; required when the
        volume holds several labels)
    :param float memoryLimit: mesh: refuse grids needing more than this many GiB (default 8), as ``--memory-limit``
    :param bool clip: no sphere protrudes from the grain (mesh: exact distance to the surface; voxels: the faces
        of the solid voxels)
    :param bool refill: with clip or a protrusion bound, choose the spheres under the constraint to regain coverage
        (default); False: generate freely, then shrink the radii
    :param float maxProtrusion: no point of a sphere farther than this beyond the grain (world units; the radius is
        at most the exact distance from the centre to the surface plus this). None (default): one voxel of the
        generation grid, the tolerance of the paper (section 3.5); 0: as ``clip``; ``float('inf')``: unbounded
        (radii grow past the grain wherever that lowers the voxel mismatch: bumps of several voxels)
    :param planes: planes no sphere may cross, as ((px, py, pz), (nx, ny, nz)); spheres stay on the side the
        normal points to. Planes that cut the grain make the target its part on that side (a fragment): the
        mismatch, the quality targets and ``targetMass`` refer to it.
    :return: :class:`MssResult`
    """
    if isinstance(source, MssResult):
        return source
    f = 'generate'
    if method not in ('optimized', 'paper'):
        raise ValueError("generate: method must be 'optimized' or 'paper', got %r" % (method,))
    opts = {'maxIterations': integer(f, 'maxIterations', maxIterations, 1),
            'deltaMin': number(f, 'deltaMin', deltaMin, 0.0),
            'keepSymmetry': flag(f, 'keepSymmetry', keepSymmetry),
            'threads': integer(f, 'threads', threads, 0, MAX_THREADS), 'method': method,
            'clip': flag(f, 'clip', clip), 'refill': flag(f, 'refill', refill),
            'planes': [_plane(p) for p in _planeList(planes)]}
    if maxProtrusion is not None:  # its range is checked by the core (validateOptions), with the same message
        try:
            opts['maxProtrusion'] = number(f, 'maxProtrusion', maxProtrusion, finite=False, nan=True)
        except (TypeError, ValueError):
            raise ValueError('generate: maxProtrusion must be a number (world units; inf: unbounded), got %r'
                             % (maxProtrusion,))
    if nSpheres is not None:
        opts['nSpheres'] = integer(f, 'nSpheres', nSpheres, 1)
    for key, val in (('eta', eta), ('dice', dice), ('rMin', rMin)):
        if val is not None:
            opts[key] = number(f, key, val, finite=False, nan=True)  # ranges: the core's checks and messages
    if voxelSize is not None:
        voxelSize = number(f, 'voxelSize', voxelSize)
    if resolution is not None:
        resolution = integer(f, 'resolution', resolution, 1)
    if label is not None:
        label = integer(f, 'label', label, 0, INT64_MAX)
    if origin is not None:
        origin = vector3(f, 'origin', origin)
    supersample = integer(f, 'supersample', supersample, 1, 16)
    s = _source(source, voxelSize, origin, label)
    if isinstance(s, _Mesh):
        if label is not None:  # it was ignored
            raise ValueError('generate: %s: label applies to labelled voxel volumes; this is a mesh' % s.name)
        res = {}
        if voxelSize is not None and resolution is not None:
            raise ValueError('generate: give voxelSize or resolution, not both')
        if voxelSize is not None:
            res['voxelSize'] = voxelSize
        else:
            res['resolution'] = resolution if resolution is not None else 100
        if memoryLimit is not None:
            gib = number(f, 'memoryLimit', memoryLimit)
            if not 0 < gib <= MAX_MEMORY_GIB:
                raise ValueError('generate: memoryLimit must be in (0, %d] GiB, got %r' % (MAX_MEMORY_GIB, memoryLimit))
            res['memoryLimit'] = int(gib * 2 ** 30)
        d = _mss.generateMesh(*s.args(), res, opts, supersample)
        target = MassProperties._fromDict(_mss.massMesh(*s.args(), opts['planes']))
    else:
        if resolution is not None:
            raise ValueError('generate: resolution applies to meshes; voxels are used at their own resolution')
        d = _mss.generateVoxels(*s.args(), opts)
        target = MassProperties._fromDict(_mss.massVoxels(*s.args(), opts['planes']))
    for w in d['metrics'].get('warnings', []):
        warnings.warn('%s: %s' % (s.name, w))
    r = MssResult(d['centers'], d['radii'], d['metrics'], d['grid'], target, s.name)
    r.grain = source if label is None else None  # a labelled volume needs its label again: not kept
    return r


# the keywords generate() takes besides the source: what mssClump and friends pass through
GENERATE_OPTIONS = tuple(p for p in inspect.signature(generate).parameters if p != 'source')


def score(target, spheres, resolution=100, offset=0.37, voxelSize=None, origin=None, label=None, planes=()):
    """Scores a sphere set (an :class:`MssResult` or a sphere file) against a target on a grid of its own.
    With ``planes`` the target is its part on their allowed side (a fragment, as :func:`generate` makes it).

    :return: dict with dice (eq. 27), eta (eq. 7), volumeRatio, coverage, outside, and the grid
    """
    resolution = integer('score', 'resolution', resolution, 1)
    offset = number('score', 'offset', offset)
    sp = spheres if isinstance(spheres, MssResult) else readSpheres(spheres)
    s = _source(target, voxelSize, origin, label)
    cuts = [_plane(p) for p in planes]
    if isinstance(s, _Mesh):
        return _mss.scoreMesh(*s.args(), _flat(sp.centers), sp.radii.tolist(), resolution, offset, 1,
                              cuts)
    return _mss.scoreVoxels(*s.args(), _flat(sp.centers), sp.radii.tolist(), cuts)


def compareMany(target, spheres, resolution=100, offset=0.37, align=None, planes=(), clumpId=None, voxelSize=None,
                origin=None, label=None):
    """Compares sphere files (or :class:`MssResult` objects) of any generator with a grain, one row each, as
    ``mss compare GRAIN A B C`` prints them.

    :param spheres: a list of sphere files (CLUMP's ``x,y,z,r`` in its Python or MATLAB form, legacy VTK, YADE
        text clumps with ``clumpId``, ours) or results
    :param str align: None (a set in another frame is refused, with a hint), 'centroid', 'bbox', 'principal', or
        'none' (as written, no check)
    :return: list of dicts: file, spheres, dice, eta, volumeRatio, coverage, outside, protrusion (largest, world
        units), smallestRadius, massError, centroidError, inertiaError (the union against the grain), rotation
        (3x3) and translation of the registration applied
    """
    items = list(spheres) if isinstance(spheres, (list, tuple)) else [spheres]
    opts = {'resolution': integer('compareMany', 'resolution', resolution, 1),
            'offset': number('compareMany', 'offset', offset), 'planes': [_plane(p) for p in planes]}
    if align is not None:  # 'none': as written, even in another frame
        opts['align'] = str(align)
    s = _source(target, voxelSize, origin, label)
    rows = []
    for item in items:
        sp = item if isinstance(item, MssResult) else readSpheres(item, clumpId)
        if isinstance(s, _Mesh):
            row = _mss.compareMesh(*s.args(), _flat(sp.centers), sp.radii.tolist(), opts)
        else:
            row = _mss.compareVoxels(*s.args(), _flat(sp.centers), sp.radii.tolist(), opts)
        row['file'] = sp.source if isinstance(item, MssResult) else str(item)
        row['rotation'] = [row['rotation'][3 * i:3 * i + 3] for i in range(3)]
        rows.append(row)
    return rows
