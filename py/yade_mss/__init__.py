"""yade-mss: multi-sphere (MSS) clumps for YADE, from a triangle mesh or a voxel volume.

The generator (C++, module :mod:`yade_mss._mss`) works in any Python with numpy; the functions that build
bodies (:func:`mssClump`, :func:`mssTemplate`) need a running YADE (``yade -n -x script.py``).

Quick start, in a YADE script::

    from yade_mss import mssClump
    clumpId, memberIds = mssClump('grain.stl', nSpheres=30)

Units are those of the input file. Densities come from the material, as in :yref:`utils.sphere`.
"""

import json
import math
import os
import warnings

import numpy as np

from . import _mss

__all__ = ['MssResult', 'generate', 'readSpheres', 'score', 'massProperties', 'mssClump', 'mssTemplate',
           'MssTemplate', 'mssClumpCloud']

_MESH_EXT = ('.stl', '.obj', '.off', '.ply')


class MassProperties(object):
    """Volume, centroid and inertia tensor (about the centroid, world axes) of a solid of unit density."""

    def __init__(self, volume, centroid, inertia):
        self.volume = float(volume)
        self.centroid = np.asarray(centroid, dtype=float).reshape(3)
        self.inertia = np.asarray(inertia, dtype=float).reshape(3, 3)

    @staticmethod
    def _fromDict(d):
        return MassProperties(d['volume'], d['centroid'], d['inertia'])

    def principal(self):
        """Principal moments (ascending) and axes (columns of a rotation matrix)."""
        w, v = np.linalg.eigh(self.inertia)
        if np.linalg.det(v) < 0:
            v[:, 2] = -v[:, 2]
        return w, v

    def transformed(self, scale=1.0, rotation=None, center=None):
        """The same solid scaled about its centroid, rotated by the matrix *rotation*, moved to *center*."""
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
        c = self.centroid if center is None else np.asarray(center, dtype=float)
        return MassProperties(self.volume * scale ** 3, c, scale ** 5 * R.dot(self.inertia).dot(R.T))

    def _toDict(self):
        return {'volume': self.volume, 'centroid': self.centroid.tolist(), 'inertia': self.inertia.ravel().tolist()}


class MssResult(object):
    """A sphere set and where it came from: what :func:`generate` returns and :func:`mssClump` accepts.

    :ivar centers: sphere centres, numpy array (n, 3), world units
    :ivar radii: sphere radii, numpy array (n,)
    :ivar metrics: dict of figures on the generation grid (spheres, eta, dice, iterations, seconds...)
    :ivar grid: dict (dims, voxelSize, origin) of the generation grid, or None
    :ivar targetMass: :class:`MassProperties` of the target solid (unit density), or None if unknown
    :ivar source: description of the input (file name or 'array')
    """

    def __init__(self, centers, radii, metrics=None, grid=None, targetMass=None, source=''):
        self.centers = np.asarray(centers, dtype=float).reshape(-1, 3)
        self.radii = np.asarray(radii, dtype=float).reshape(-1)
        if len(self.centers) != len(self.radii):
            raise ValueError('MssResult: %d centres but %d radii' % (len(self.centers), len(self.radii)))
        self.metrics = dict(metrics or {})
        self.grid = grid
        self.targetMass = targetMass
        self.source = source
        self._unionMass = None

    def __len__(self):
        return len(self.radii)

    def __repr__(self):
        return '<MssResult %d spheres from %s, dice %s>' % (len(self), self.source or '?', self.metrics.get('dice', '?'))

    def unionMass(self, resolution=200):
        """:class:`MassProperties` of the union of the spheres (overlaps counted once), unit density."""
        if self._unionMass is None or self._unionMass[0] != resolution:
            d = _mss.massSpheres(self.centers.ravel().tolist(), self.radii.tolist(), resolution)
            self._unionMass = (resolution, MassProperties._fromDict(d))
        return self._unionMass[1]

    def save(self, path):
        """Writes the result to *path* (.npz), so that a batch need not generate again; see :meth:`load`."""
        if not str(path).endswith('.npz'):
            raise ValueError('MssResult.save: %s: use the .npz extension' % path)
        meta = {'metrics': self.metrics, 'grid': self.grid, 'source': self.source,
                'targetMass': self.targetMass._toDict() if self.targetMass is not None else None, 'version': 1}
        tmp = str(path) + '.tmp%d.npz' % os.getpid()
        try:
            np.savez_compressed(tmp, centers=self.centers, radii=self.radii, meta=np.array(json.dumps(meta)))
            os.replace(tmp, str(path))
        except OSError as e:
            if os.path.exists(tmp):
                os.remove(tmp)
            raise RuntimeError('MssResult.save: %s: cannot write (%s)' % (path, e))

    @staticmethod
    def load(path):
        """Reads a result written by :meth:`save`."""
        try:
            with np.load(str(path), allow_pickle=False) as z:
                meta = json.loads(str(z['meta']))
                r = MssResult(z['centers'], z['radii'], meta.get('metrics'), meta.get('grid'), None, meta.get('source', ''))
        except (OSError, KeyError, ValueError) as e:
            raise ValueError('MssResult.load: %s: not a saved result (%s)' % (path, e))
        if meta.get('targetMass'):
            r.targetMass = MassProperties._fromDict(meta['targetMass'])
        return r


# ---------------------------------------------------------------- sources

def _flat(a):
    return np.ascontiguousarray(a, dtype=float).ravel().tolist()


class _Mesh(object):
    def __init__(self, vertices, triangles, name):
        self.vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
        self.triangles = np.asarray(triangles).reshape(-1, 3)
        if self.triangles.size and not np.issubdtype(self.triangles.dtype, np.integer):
            if not np.all(np.mod(self.triangles, 1) == 0):
                raise ValueError('mesh: triangle indices must be integers')
        self.triangles = self.triangles.astype(np.int64)
        self.name = name

    def args(self):
        return _flat(self.vertices), self.triangles.ravel().tolist()


class _Voxels(object):
    def __init__(self, array, voxelSize, origin, name, label=None):
        a = np.asarray(array)
        if a.ndim != 3:
            raise ValueError('voxels: the array must be 3-D, got %d-D' % a.ndim)
        if a.size == 0:
            raise ValueError('voxels: the array is empty')
        if not (a.dtype == bool or np.issubdtype(a.dtype, np.integer)):
            raise ValueError('voxels: dtype %s is not boolean or integer (threshold a grey-level volume first)' % a.dtype)
        solid = (a == label) if label is not None else (a != 0)
        if not solid.any():
            raise ValueError('voxels: no voxel has label %s' % label if label is not None else 'voxels: the volume has no solid voxel')
        self.shape = solid.shape
        self.data = np.asfortranarray(solid.astype(np.uint8)).tobytes(order='F')  # x fastest
        self.voxelSize = 1.0 if voxelSize is None else float(voxelSize)
        if not (self.voxelSize > 0 and math.isfinite(self.voxelSize)):
            raise ValueError('voxels: voxel size must be > 0 and finite, got %s' % voxelSize)
        self.origin = [float(x) for x in (origin if origin is not None else (0, 0, 0))]
        if len(self.origin) != 3:
            raise ValueError('voxels: origin must have 3 coordinates')
        self.name = name

    def args(self):
        return self.data, tuple(int(n) for n in self.shape), self.voxelSize, self.origin


def _source(source, voxelSize=None, origin=None, label=None):
    """A mesh or voxel source from a file name, an array, (vertices, triangles) or a dict."""
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        ext = os.path.splitext(path)[1].lower()
        if ext in _MESH_EXT:
            v, t = _mss.readMesh(path)
            return _Mesh(v, t, os.path.basename(path))
        if ext == '.npy':  # the C++ reader: its checks and messages, as in the mss command
            data, shape = _mss.readNpy(path, -1 if label is None else int(label))
            a = np.frombuffer(data, dtype=np.uint8).reshape(shape, order='F')
            return _Voxels(a, voxelSize, origin, os.path.basename(path))
        raise ValueError("readMesh: %s: unknown mesh extension '%s' (expected .stl, .obj, .off or .ply, or .npy voxels)" % (path, ext))
    if isinstance(source, dict) and 'vertices' in source and 'triangles' in source:
        return _Mesh(source['vertices'], source['triangles'], 'mesh')
    if isinstance(source, tuple) and len(source) == 2:
        return _Mesh(source[0], source[1], 'mesh')
    if isinstance(source, np.ndarray):
        return _Voxels(source, voxelSize, origin, 'array', label)
    raise ValueError('source must be a mesh file, a .npy file, a 3-D numpy array, (vertices, triangles) or an '
                     'MssResult; got %s' % type(source).__name__)


def massProperties(source, voxelSize=None, origin=None, label=None, planes=()):
    """:class:`MassProperties` (unit density) of a mesh (exact, divergence theorem) or voxels (exact voxel sums).
    With ``planes`` (as in :func:`generate`): of the part on their allowed side, a fragment (a mesh cut and capped
    exactly; voxels whose centre is on that side)."""
    s = _source(source, voxelSize, origin, label)
    cuts = [_plane(p) for p in planes]
    if isinstance(s, _Mesh):
        return MassProperties._fromDict(_mss.massMesh(*s.args(), cuts))
    return MassProperties._fromDict(_mss.massVoxels(*s.args(), cuts))


def generate(source, nSpheres=None, eta=None, dice=None, rMin=None, voxelSize=None, resolution=None,
             method='optimized', supersample=1, keepSymmetry=True, maxIterations=100, deltaMin=1.0, threads=0,
             origin=None, label=None, memoryLimit=None, clip=False, refill=True, planes=()):
    """Generates the sphere set of a grain (MSS paper, sections 2-3).

    :param source: mesh file (.stl .obj .off .ply), voxel file (.npy), 3-D numpy array (bool or int), a tuple
        (vertices (n,3), triangles (m,3)) or a dict with those keys
    :param int nSpheres: at most this many spheres (problem (i))
    :param float eta: stop at relative mismatch eta (eq. 7; problem (ii): fewest spheres meeting it)
    :param float dice: stop at Dice mismatch (eq. 27)
    :param float rMin: no sphere smaller than this radius (world units)
    :param float voxelSize: mesh: voxel edge of the generation grid; voxels: the array's voxel edge (default 1)
    :param int resolution: mesh: voxels along the shortest bounding-box edge (default 100 when neither is given)
    :param str method: 'optimized' (default) or 'paper' (the published procedure)
    :param int supersample: mesh: k^3 samples per voxel in voxelisation (1 = voxel centres)
    :param origin: voxels: world position of the centre of voxel (0, 0, 0)
    :param int label: voxels: solid where the array equals this label (labelled CT volumes)
    :param bool clip: no sphere protrudes from the grain (mesh: exact distance to the surface; voxels: the faces
        of the solid voxels)
    :param bool refill: with clip, choose the spheres under the constraint to regain coverage (default)
    :param planes: planes no sphere may cross, as ((px, py, pz), (nx, ny, nz)); spheres stay on the side the
        normal points to. Planes that cut the grain make the target its part on that side (a fragment): the
        mismatch, the quality targets and ``targetMass`` refer to it.
    :return: :class:`MssResult`
    """
    if isinstance(source, MssResult):
        return source
    if method not in ('optimized', 'paper'):
        raise ValueError("generate: method must be 'optimized' or 'paper', got %r" % (method,))
    opts = {'maxIterations': int(maxIterations), 'deltaMin': float(deltaMin), 'keepSymmetry': bool(keepSymmetry),
            'threads': int(threads), 'method': method, 'clip': bool(clip), 'refill': bool(refill),
            'planes': [_plane(p) for p in planes]}
    if nSpheres is not None:
        if int(nSpheres) != nSpheres or nSpheres < 1:
            raise ValueError('generate: nSpheres must be an integer >= 1, got %r' % (nSpheres,))
        opts['nSpheres'] = int(nSpheres)
    for key, val in (('eta', eta), ('dice', dice), ('rMin', rMin)):
        if val is not None:
            opts[key] = float(val)
    s = _source(source, voxelSize, origin, label)
    if isinstance(s, _Mesh):
        res = {}
        if voxelSize is not None and resolution is not None:
            raise ValueError('generate: give voxelSize or resolution, not both')
        if voxelSize is not None:
            res['voxelSize'] = float(voxelSize)
        else:
            res['resolution'] = int(resolution) if resolution is not None else 100
        if memoryLimit is not None:
            res['memoryLimit'] = int(memoryLimit)
        d = _mss.generateMesh(*s.args(), res, opts, int(supersample))
        target = MassProperties._fromDict(_mss.massMesh(*s.args(), opts['planes']))
    else:
        if resolution is not None:
            raise ValueError('generate: resolution applies to meshes; voxels are used at their own resolution')
        d = _mss.generateVoxels(*s.args(), opts)
        target = MassProperties._fromDict(_mss.massVoxels(*s.args(), opts['planes']))
    for w in d['metrics'].get('warnings', []):
        warnings.warn('%s: %s' % (s.name, w))
    return MssResult(d['centers'], d['radii'], d['metrics'], d['grid'], target, s.name)


def _plane(p):
    try:
        point, normal = p
        v = [float(x) for x in point] + [float(x) for x in normal]
    except (TypeError, ValueError):
        raise ValueError('planes: each plane is ((px, py, pz), (nx, ny, nz)), got %r' % (p,))
    if len(v) != 6:
        raise ValueError('planes: each plane is ((px, py, pz), (nx, ny, nz)), got %r' % (p,))
    return v


def readSpheres(path):
    """Reads a sphere file (CLUMP's ``x,y,z,r`` CSV, a YADE text clump ``x y z r id``, our .csv/.txt) as an
    :class:`MssResult` without a target (use ``mass='union'`` with it)."""
    c, r = _mss.readSpheres(os.fspath(path))
    return MssResult(c, r, source=os.path.basename(os.fspath(path)))


def score(target, spheres, resolution=100, offset=0.37, voxelSize=None, origin=None, label=None, planes=()):
    """Scores a sphere set (an :class:`MssResult` or a sphere file) against a target on a grid of its own.
    With ``planes`` the target is its part on their allowed side (a fragment, as :func:`generate` makes it).

    :return: dict with dice (eq. 27), eta (eq. 7), volumeRatio, coverage, outside, and the grid
    """
    sp = spheres if isinstance(spheres, MssResult) else readSpheres(spheres)
    s = _source(target, voxelSize, origin, label)
    cuts = [_plane(p) for p in planes]
    if isinstance(s, _Mesh):
        return _mss.scoreMesh(*s.args(), _flat(sp.centers), sp.radii.tolist(), int(resolution), float(offset), 1,
                              cuts)
    return _mss.scoreVoxels(*s.args(), _flat(sp.centers), sp.radii.tolist(), cuts)


# ---------------------------------------------------------------- YADE

def _yade():
    try:
        from yade import utils
        from yade.wrapper import Omega
        import yade.minieigenHP as me
    except ImportError:
        raise RuntimeError('this function builds YADE bodies: run the script with yade (yade -n -x script.py)')
    return utils, Omega(), me


def _rotation(orientation, me):
    """3x3 rotation matrix from None, a YADE Quaternion, (axis, angle), a 3x3 matrix or (w, x, y, z)."""
    if orientation is None:
        return np.eye(3)
    if hasattr(orientation, 'toRotationMatrix'):
        m = orientation.toRotationMatrix()
        return np.array([[m[i, j] for j in range(3)] for i in range(3)])
    o = orientation
    if isinstance(o, (tuple, list)) and len(o) == 2 and np.size(o[0]) == 3:
        axis = np.asarray(o[0], dtype=float)
        n = np.linalg.norm(axis)
        if not n > 0:
            raise ValueError('orientation: rotation axis must be non-zero')
        q = me.Quaternion(me.Vector3(*(axis / n)), float(o[1]))
        return _rotation(q, me)
    a = np.asarray(o, dtype=float)
    if a.shape == (3, 3):
        if not (np.allclose(a.dot(a.T), np.eye(3), atol=1e-9) and np.linalg.det(a) > 0):
            raise ValueError('orientation: the matrix is not a rotation')
        return a
    if a.shape == (4,):
        n = np.linalg.norm(a)
        if not n > 0:
            raise ValueError('orientation: zero quaternion')
        w, x, y, z = a / n
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    raise ValueError('orientation: give a Quaternion, (axis, angle), a 3x3 rotation matrix or (w, x, y, z)')


def _ghost(centers, radii, density, M, C, I):
    """Mass, position and inertia tensor of the correction member (see :func:`mssClump`).

    YADE's Clump::updateProperties (no discretization) sums over members: a sphere counts as a solid ball of its
    material's density, m = rho 4/3 pi r^3 and 2/5 m r^2, overlaps counted twice; any other member counts with
    its own state.mass, state.inertia and state.ori. One non-sphere member carrying the difference makes the
    sums exact: total mass M, centre of mass C, tensor I about C.
    """
    m = density * 4.0 / 3.0 * math.pi * radii ** 3
    d = centers - C
    mg = M - m.sum()
    first = (m[:, None] * d).sum(axis=0)  # sum m_i (x_i - C); the ghost must cancel it
    if abs(mg) < 1e-12 * M:
        if np.linalg.norm(first) > 1e-12 * M * max(1.0, np.max(radii)):
            raise RuntimeError('mssClump: cannot place the mass correction (spheres weigh exactly the target)')
        dg = np.zeros(3)
    else:
        dg = -first / mg
    T = lambda v: v.dot(v) * np.eye(3) - np.outer(v, v)
    spheres = np.zeros((3, 3))
    for mi, ri, di in zip(m, radii, d):
        spheres += 0.4 * mi * ri * ri * np.eye(3) + mi * T(di)
    J = I - spheres - mg * T(dg)
    J = 0.5 * (J + J.T)
    j, V = np.linalg.eigh(J)
    if np.linalg.det(V) < 0:
        V[:, 2] = -V[:, 2]
    return mg, C + dg, j, V


def _quaternionFromMatrix(V, me):
    return me.Quaternion(me.Matrix3(*[float(V[i, j]) for i in range(3) for j in range(3)]))


# YADE rotates a non-sphere member's tensor by its ori or by its conjugate depending on the version; found out
# on the first clump and remembered.
_ghostConjugate = [None]


def mssClump(source, nSpheres=None, eta=None, dice=None, rMin=None, voxelSize=None, resolution=None, clip=False,
             center=None, orientation=None, scale=1.0, material=-1, color=None, mask=1, mass='target', planes=(),
             **kw):
    """Builds one YADE clump from a grain and appends it to O.bodies, as ``O.bodies.appendClumped`` does.

    :param source: mesh file, voxel file (.npy), 3-D numpy array, (vertices, triangles), or an :class:`MssResult`
        (then no generation happens)
    :param int nSpheres: at most this many spheres; eta, dice, rMin, voxelSize, resolution: see :func:`generate`
    :param bool clip: no sphere protrudes from the grain (see :func:`generate`); planes: likewise (in the file's
        frame, before placement)
    :param Vector3 center: where the clump's centre of mass goes (default: where it is in the file's frame)
    :param orientation: rotation about the centre of mass: a Quaternion, (axis, angle), a 3x3 matrix
    :param float scale: size factor about the centre of mass
    :param material, color, mask: as for :yref:`utils.sphere`; the material's density gives the mass
    :param str mass: 'target': mass, centre and inertia of the target solid (exact for a mesh; voxel sums);
        'union': those of the union of the spheres (overlaps counted once)
    :param kw: passed to ``utils.sphere`` (e.g. ``fixed``, ``wire``)
    :return: (clumpId, [memberIds]) of the spheres; O.bodies is unchanged if anything fails

    YADE computes a clump's mass and inertia from its members as if the spheres did not overlap. To give the
    clump the exact properties asked for, each clump gets one more member: a :yref:`Box` of zero extent without
    bound (``bounded=False``, ``mask=0``, so never in a contact) whose mass (usually negative), position and
    inertia make YADE's sums come out exact. Its id is the last in ``O.bodies[clumpId].shape.members``.
    """
    utils, O, me = _yade()
    if mass not in ('target', 'union'):
        raise ValueError("mssClump: mass must be 'target' or 'union', got %r" % (mass,))
    if not (float(scale) > 0 and math.isfinite(float(scale))):
        raise ValueError('mssClump: scale must be > 0, got %r' % (scale,))
    r = source if isinstance(source, MssResult) else generate(source, nSpheres=nSpheres, eta=eta, dice=dice,
                                                               rMin=rMin, voxelSize=voxelSize, resolution=resolution,
                                                               clip=clip, planes=planes)
    if len(r) == 0:
        raise RuntimeError('mssClump: the generator returned no sphere')
    if mass == 'target':
        if r.targetMass is None:
            raise ValueError("mssClump: this result has no target solid (read from a sphere file?); use mass='union'")
        props = r.targetMass
    else:
        props = r.unionMass()
    R = _rotation(orientation, me)
    C = props.centroid if center is None else np.array([float(x) for x in center])
    if C.shape != (3,) or not np.all(np.isfinite(C)):
        raise ValueError('mssClump: center must be 3 finite numbers')
    s = float(scale)
    centers = C + (s * (r.centers - props.centroid)).dot(R.T)
    radii = s * r.radii
    placed = props.transformed(s, R, C)

    def spheres():
        return [utils.sphere(tuple(float(x) for x in p), float(rad), material=material, color=color, mask=mask, **kw)
                for p, rad in zip(centers, radii)]

    bodies = spheres()
    density = bodies[0].material.density
    if not density > 0:
        raise ValueError('mssClump: the material density must be > 0, got %g' % density)
    M, I = density * placed.volume, density * placed.inertia
    mg, xg, j, V = _ghost(centers, radii, density, M, C, I)
    from yade.wrapper import Body, Box, State
    for conjugate in ([_ghostConjugate[0]] if _ghostConjugate[0] is not None else [True, False]):
        ghost = Body()
        ghost.shape = Box(extents=me.Vector3(0, 0, 0))
        ghost.state = State()
        ghost.state.pos = me.Vector3(*[float(x) for x in xg])
        ghost.state.mass = float(mg)
        ghost.state.inertia = me.Vector3(*[float(x) for x in j])
        q = _quaternionFromMatrix(V, me)
        ghost.state.ori = q.conjugate() if conjugate else q
        ghost.material = bodies[0].material
        ghost.bounded = False  # no bound: never in a contact
        ghost.mask = 0
        clumpId, ids = O.bodies.appendClumped(bodies + [ghost])
        # YADE chose the clump frame from the members: check it is the principal frame of the tensor we want
        cl = O.bodies[clumpId].state
        Rc = _rotation(cl.ori, me)
        Ic = Rc.dot(np.diag([cl.inertia[0], cl.inertia[1], cl.inertia[2]])).dot(Rc.T)
        ok = (abs(cl.mass - M) <= 1e-9 * M and np.linalg.norm(np.array(cl.pos) - C) <= 1e-9 * max(1.0, np.max(np.abs(C)))
              and np.linalg.norm(Ic - I) <= 1e-7 * np.linalg.norm(I))
        if os.environ.get('MSS_DEBUG'):
            print('mssClump: conjugate', conjugate, 'ok', ok, cl.mass - M, np.linalg.norm(np.array(cl.pos) - C),
                  np.linalg.norm(Ic - I) / np.linalg.norm(I))
        if ok:
            _ghostConjugate[0] = conjugate
            return clumpId, list(ids[:-1])
        O.bodies.erase(clumpId, True)
        bodies = spheres()
    raise RuntimeError('mssClump: YADE did not take the requested mass properties (mass %g vs %g); nothing was added'
                       % (cl.mass, M))


class MssTemplate(object):
    """A grain as a clump template, generated once and reused for a packing.

    :ivar clumpTemplate: ``utils.clumpTemplate`` for ``O.bodies.replaceByClumps`` (relative radii and positions:
        centred at the union's centre of mass, scaled to the radius of the sphere of equal volume, 1)
    :ivar spherePack: ``SpherePack`` for ``SpherePack.makeClumpCloud`` (file units times scale, centred at the
        centre of mass)
    :ivar result: the :class:`MssResult`
    """

    def __init__(self, result, scale=1.0):
        utils, O, me = _yade()
        from yade import pack
        self.result = result
        u = result.unionMass()
        rEq = (3.0 * u.volume / (4.0 * math.pi)) ** (1.0 / 3.0)
        rel = (result.centers - u.centroid) / rEq
        self.clumpTemplate = utils.clumpTemplate(relRadii=[float(x) for x in result.radii / rEq],
                                                 relPositions=[[float(x) for x in p] for p in rel])
        self.scale = scale
        self.unionCentroid = u.centroid
        self.spherePackCenters = scale * (result.centers - u.centroid)
        self.spherePackRadii = scale * result.radii
        self.spherePack = pack.SpherePack([(tuple(float(x) for x in p), float(rad))
                                           for p, rad in zip(self.spherePackCenters, self.spherePackRadii)])
        self.equivalentRadius = rEq * scale


def mssTemplate(source, nSpheres=None, eta=None, dice=None, rMin=None, voxelSize=None, resolution=None, scale=1.0,
                clip=False):
    """Generates a grain once as a template for packings; see :class:`MssTemplate`.

    Templates normalised for ``replaceByClumps`` (``t.clumpTemplate``) and ``makeClumpCloud`` (``t.spherePack``).
    """
    if not (float(scale) > 0):
        raise ValueError('mssTemplate: scale must be > 0, got %r' % (scale,))
    r = source if isinstance(source, MssResult) else generate(source, nSpheres=nSpheres, eta=eta, dice=dice,
                                                               rMin=rMin, voxelSize=voxelSize, resolution=resolution,
                                                               clip=clip)
    return MssTemplate(r, float(scale))


def _kabsch(Q, P):
    """Rotation R and translation t with P ~ t + R Q (least squares; Kabsch 1976)."""
    qc, pc = Q.mean(axis=0), P.mean(axis=0)
    H = (Q - qc).T.dot(P - pc)
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(Vt.T.dot(U.T))) or 1.0
    R = Vt.T.dot(np.diag([1.0, 1.0, d])).dot(U.T)
    return R, pc - R.dot(qc)


def mssClumpCloud(templates, minCorner, maxCorner, num=-1, periodic=False, seed=-1, material=-1, color=None, mask=1,
                  mass='target', **kw):
    """A random loose packing of clumps from :class:`MssTemplate` objects, with exact mass properties.

    Positions and orientations come from ``SpherePack.makeClumpCloud`` (same parameters); each clump is then
    built by :func:`mssClump`, so it has the mass, centre and inertia of its grain (``toSimulation`` would let
    YADE sum the overlapping spheres).

    :return: list of (clumpId, [memberIds])
    """
    utils, O, me = _yade()
    from yade import pack
    templates = list(templates)
    if not templates or not all(isinstance(t, MssTemplate) for t in templates):
        raise ValueError('mssClumpCloud: give a list of MssTemplate (from mssTemplate)')
    sp = pack.SpherePack()
    sp.makeClumpCloud(me.Vector3(*minCorner), me.Vector3(*maxCorner), [t.spherePack for t in templates],
                      periodic=periodic, num=num, seed=seed)
    groups = {}
    for c, r, cid in sp.toList():
        groups.setdefault(cid, []).append((np.array([c[0], c[1], c[2]]), r))
    out = []
    for cid in sorted(groups):
        P = np.array([c for c, r in groups[cid]])
        radii = np.array([r for c, r in groups[cid]])
        t = next((t for t in templates if len(t.spherePackRadii) == len(radii)
                  and np.allclose(t.spherePackRadii, radii, rtol=1e-12)), None)
        if t is None:
            raise RuntimeError('mssClumpCloud: a clump of the cloud matches no template')
        R, tr = _kabsch(t.spherePackCenters, P)
        props = t.result.targetMass if mass == 'target' and t.result.targetMass is not None else t.result.unionMass()
        center = tr + t.scale * R.dot(props.centroid - t.unionCentroid)
        out.append(mssClump(t.result, center=center, orientation=R, scale=t.scale, material=material, color=color,
                            mask=mask, mass=mass, **kw))
    return out
